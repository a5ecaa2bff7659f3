/* hair_cyhair.h: the cyHair .hair layout shared by the reader (hair_cyhair.c) and the writer
 * (hair_cyhair_write.c): the header's size and the flag bits of the arrays that follow it
 * (../shared/data/README.md). */
#ifndef SL_HAIR_CYHAIR_H
#define SL_HAIR_CYHAIR_H

enum {
    CY_SEGMENTS = 1u << 0,
    CY_POINTS = 1u << 1,
    CY_THICKNESS = 1u << 2,
    CY_TRANSPARENCY = 1u << 3,
    CY_COLOR = 1u << 4,
    CY_HEADER = 128
};

#endif
