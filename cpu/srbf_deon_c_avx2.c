/* srbf_deon_c_avx2.c: the chiang RGB batch of cpu/srbf_chiang_batch.inc for AVX2 + FMA (the
 * Makefile compiles this file alone with -mavx2 -mfma on x86-64); slc_srbf_deon_rgb_batch calls
 * it only where slc_simd_avx2() finds both on the CPU. Elsewhere the file is empty. */
#include "srbf_deon_c.h"

#if defined(__x86_64__) && defined(__AVX2__) && defined(__FMA__)
#define SLC_CHIANG_BATCH slc_srbf_chiang_rgb_batch_avx2
#include "srbf_chiang_batch.inc"
#else
typedef int slc_srbf_deon_c_avx2_empty; /* ISO C: no empty translation unit */
#endif
