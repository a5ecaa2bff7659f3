/* ms_cl.h: enqueues kernels/ms.cl (the multiple-scattering response rows; C side
 * host/passes/volume/volume_ms.c). */
#ifndef SL_VOLUME_MS_CL_H
#define SL_VOLUME_MS_CL_H

#include "cl/clrt.h"
#include "passes/volume/volume_ms.h"

/* n rows of 6 floats (theta_o, phi_o, theta_j, phi_j, lambda, sigma_f) -> 2 floats (M^G, M^L) of
 * channel ch, from the response table (the device twin of sl_volume_ms_terms). Returns 0, -1 or
 * SL_CL_EKERNEL. */
int slcl_ms_response_rows(sl_cl *cl, const sl_volume_ms *ms, int ch, size_t n, const float *in,
                          float *out, sl_err *e);

/* The same by the direct evaluation (the twin of sl_volume_ms_terms_exact). */
int slcl_ms_response_rows_exact(sl_cl *cl, const sl_volume_ms *ms, int ch, size_t n,
                                const float *in, float *out, sl_err *e);

#endif
