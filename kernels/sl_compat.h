/* sl_compat.h: lets one math header compile as OpenCL C 1.2 and as C11 (the way Cycles'
 * kernel/device/<api>/compat.h and Mesa's libcl.h do). Shared headers include only this file and
 * write plain float math: `sqrt(x)`, `exp(x)`, float literals with an `f` suffix (a bare `1.0` is
 * a double and is not allowed on devices without fp64).
 *
 *  - Address-space qualifiers: SL_GLOBAL, SL_LOCAL, SL_CONSTANT (empty in C).
 *  - SL_INLINE for helper functions (static inline in both languages).
 *  - Fixed-width integer types: sl_uint, sl_int, sl_ulong.
 *  - In C, <tgmath.h> makes sqrt/exp/... on floats resolve to sqrtf/expf like OpenCL's overloads.
 *  - sl_clampf, sl_minf, sl_maxf, sl_mixf exist in both (OpenCL's clamp/min/max are builtins). */
#ifndef SL_COMPAT_H
#define SL_COMPAT_H

#if defined(__OPENCL_C_VERSION__) || defined(__OPENCL_VERSION__)
#define SL_OPENCL 1
#define SL_GLOBAL __global
#define SL_LOCAL __local
#define SL_CONSTANT __constant
#define SL_INLINE static inline
typedef uint sl_uint;
typedef int sl_int;
typedef ulong sl_ulong;
#define sl_clampf(x, lo, hi) clamp((float)(x), (float)(lo), (float)(hi))
#define sl_minf(a, b) fmin((float)(a), (float)(b))
#define sl_maxf(a, b) fmax((float)(a), (float)(b))
#define sl_mixf(a, b, t) mix((float)(a), (float)(b), (float)(t))
#define SL_FLT_MAX FLT_MAX
#define SL_FLT_MIN FLT_MIN
#define SL_FLT_EPSILON FLT_EPSILON
#else
#define SL_OPENCL 0
#include <float.h>
#include <stdint.h>
#include <tgmath.h>
#define SL_GLOBAL
#define SL_LOCAL
#define SL_CONSTANT const
#define SL_INLINE static inline
typedef uint32_t sl_uint;
typedef int32_t sl_int;
typedef uint64_t sl_ulong;
SL_INLINE float sl_clampf(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }
SL_INLINE float sl_minf(float a, float b) { return fminf(a, b); }
SL_INLINE float sl_maxf(float a, float b) { return fmaxf(a, b); }
SL_INLINE float sl_mixf(float a, float b, float t) { return a + (b - a) * t; }
#define SL_FLT_MAX FLT_MAX
#define SL_FLT_MIN FLT_MIN
#define SL_FLT_EPSILON FLT_EPSILON
#endif

#define SL_PI_F 3.14159265358979323846f
#define SL_INV_PI_F 0.318309886183790671538f
#define SL_SQRT_PI_F 1.77245385090551602730f

#endif
