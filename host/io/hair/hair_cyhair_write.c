/* hair_cyhair_write.c: an sl_hair written as Cem Yuksel's cyHair .hair (the layout hair_cyhair.c
 * reads, ../shared/data/README.md), so that another renderer (scripts/cycles/) gets exactly the
 * strands ours renders. Every point gets a thickness (2 x its radius: the format stores a
 * diameter); colours and transparency are written when the hair has them. The file is written
 * to a temporary name and renamed (sl_atomic_*), so a failure leaves nothing behind. */
#include "io/hair/hair.h"
#include "io/hair/hair_cyhair.h"

#include <stdlib.h>
#include <string.h>

enum { CY_MAX_SEGMENTS = 65535 /* segments[] is u16 */ };

static void put_u32(unsigned char *p, uint32_t v) {
    for (int k = 0; k < 4; k++)
        p[k] = (unsigned char)(v >> (8 * k));
}

static void put_f32(unsigned char *p, float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    put_u32(p, u);
}

/* A staging buffer flushed to the file in blocks: the arrays can be gigabytes, and little-endian
 * bytes are written explicitly rather than by dumping host floats. */
typedef struct out_buf {
    FILE *fp;
    unsigned char b[1 << 16];
    size_t n;
    int failed;
} out_buf;

static void flush(out_buf *o) {
    if (o->n && fwrite(o->b, 1, o->n, o->fp) != o->n) o->failed = 1;
    o->n = 0;
}

static unsigned char *room(out_buf *o, size_t k) {
    if (o->n + k > sizeof o->b) flush(o);
    unsigned char *p = o->b + o->n;
    o->n += k;
    return p;
}

static void put_floats(out_buf *o, const float *v, size_t count) {
    for (size_t i = 0; i < count; i++)
        put_f32(room(o, 4), v[i]);
}

int sl_hair_write_cyhair(const char *path, const sl_hair *h, const char *info, sl_err *e) {
    for (uint32_t s = 0; s < h->num_strands; s++) {
        uint32_t n = h->strand_first[s + 1] - h->strand_first[s];
        if (n < 2 || n - 1 > CY_MAX_SEGMENTS)
            return sl_fail(e, "%s: strand %u has %u points; a .hair strand holds 2 to %u", path, s,
                           n, CY_MAX_SEGMENTS + 1);
    }
    uint32_t flags = CY_SEGMENTS | CY_POINTS | CY_THICKNESS;
    if (h->transparency) flags |= CY_TRANSPARENCY;
    if (h->color) flags |= CY_COLOR;

    sl_atomic_file af;
    if (sl_atomic_open(&af, path, e)) return -1;
    out_buf *o = sl_calloc(1, sizeof *o);
    o->fp = af.fp;
    unsigned char *hd = room(o, CY_HEADER);
    memset(hd, 0, CY_HEADER);
    memcpy(hd, "HAIR", 4);
    put_u32(hd + 4, h->num_strands);
    put_u32(hd + 8, h->num_points);
    put_u32(hd + 12, flags);
    put_u32(hd + 16, h->num_strands ? h->strand_first[1] - h->strand_first[0] - 1 : 0);
    put_f32(hd + 20, 2.0f * (h->radius ? h->radius[0] : h->default_radius));
    put_f32(hd + 24, h->default_transparency);
    for (int c = 0; c < 3; c++)
        put_f32(hd + 28 + 4 * c, h->default_color[c]);
    if (info) strncpy((char *)hd + 40, info, 87); /* 88 bytes, NUL-padded */

    for (uint32_t s = 0; s < h->num_strands; s++) {
        uint32_t seg = h->strand_first[s + 1] - h->strand_first[s] - 1;
        unsigned char *p = room(o, 2);
        p[0] = (unsigned char)seg;
        p[1] = (unsigned char)(seg >> 8);
    }
    put_floats(o, h->pos, 3 * (size_t)h->num_points);
    for (uint32_t i = 0; i < h->num_points; i++)
        put_f32(room(o, 4), 2.0f * (h->radius ? h->radius[i] : h->default_radius));
    if (h->transparency) put_floats(o, h->transparency, h->num_points);
    if (h->color) put_floats(o, h->color, 3 * (size_t)h->num_points);
    flush(o);
    int failed = o->failed || ferror(af.fp);
    free(o);
    if (failed) {
        sl_atomic_abort(&af);
        return sl_fail(e, "%s: write failed (disk full?)", path);
    }
    return sl_atomic_commit(&af, e);
}
