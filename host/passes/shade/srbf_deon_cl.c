/* srbf_deon_cl.c: OpenCL driver of the d'Eon fast SRBF response (see srbf_deon_cl.h); the launch
 * is srbf_cl.h's slcl_srbf_launch, the one path of every SRBF batch. */
#include "passes/shade/srbf_deon_cl.h"

#include "passes/shade/srbf_cl.h"
#include "srbf_deon.h"

int slcl_srbf_deon_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t, size_t n,
                         const float *in, float *out, sl_err *e) {
    int no = sl_srbf_deon_orders(fp);
    size_t stride = (size_t)no + 3;
    /* sl_srbf_deon_eval(fp, n, in, out, C, H, D) */
    const size_t size[] = {n * 5, n * stride, SL_SRBF_C_FLOATS, SL_SRBF_H_FLOATS,
                           SL_SRBF_DEON_FLOATS};
    const float *src[] = {in, NULL, t->C, t->H, t->D};
    const slcl_srbf_job j = {
        "srbf_deon.cl", "sl_srbf_deon_eval", "", n, "bbbbb", NULL, 1, size, src};
    return slcl_srbf_launch(cl, fp, &j, out, e);
}

int slcl_srbf_deon_rgb_batch(sl_cl *cl, const sl_fiber_params *fp, const sl_srbf_tables *t,
                             size_t n, const float *in, const float *sigma_a, float *out,
                             sl_err *e) {
    /* sl_srbf_deon_rgb(fp, n, in, sig, use_sig, out, C, H, D); sig is a 1-float dummy when
     * sigma_a is NULL (never a NULL buffer argument) */
    float dummy = 0.0f;
    const size_t size[] = {
        n * 5, sigma_a ? n * 3 : 1, n * 9, SL_SRBF_C_FLOATS, SL_SRBF_H_FLOATS, SL_SRBF_DEON_FLOATS};
    const float *src[] = {in, sigma_a ? sigma_a : &dummy, NULL, t->C, t->H, t->D};
    const cl_int ints[] = {sigma_a != NULL};
    const slcl_srbf_job j = {
        "srbf_deon.cl", "sl_srbf_deon_rgb", "", n, "bbibbbb", ints, 2, size, src};
    return slcl_srbf_launch(cl, fp, &j, out, e);
}
