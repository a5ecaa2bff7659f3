/* fiber_common_d.h: the double-precision instantiation of fiber_common.inc for C code
 * (prefix `sld_`), used by the reference backend. Not for OpenCL. */
#ifndef SL_FIBER_COMMON_D_H
#define SL_FIBER_COMMON_D_H

#include "sl_compat.h"

#define SL_R double
#define SL_F(name) sld_##name
#define SL_K(x) x
#include "fiber_common.inc"
#undef SL_R
#undef SL_F
#undef SL_K

#endif
