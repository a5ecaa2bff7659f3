/* exr_cxx_shim.h: a C interface over the OpenEXR C++ API (Imf::InputFile) for what OpenEXRCore
 * 3.1 cannot decode (DWAA/DWAB compression; see ../shared/design/toolchain.md sec. 3).
 * Every C++ exception is caught and returned as a message; nothing is printed. */
#ifndef SL_EXR_CXX_SHIM_H
#define SL_EXR_CXX_SHIM_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Decodes the named channels of the first part of the EXR file held in data[0..n) into planar
 * float buffers planes[i] (each w*h floats, row 0 = top of the data window). The file's data
 * window must be w x h (the caller read the header with OpenEXRCore). A channel absent from the
 * file is an error. Returns 0, or -1 with a one-line message in err. */
int sl_exrcxx_read_planes(const unsigned char *data, size_t n, int w, int h, int nplanes,
                          const char *const *names, float *const *planes, char *err,
                          size_t err_size);

#ifdef __cplusplus
}
#endif

#endif
