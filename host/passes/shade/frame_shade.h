/* frame_shade.h: the shade pass: per shading point, the SRBF single-scattering response of every
 * used lobe times the transmittance toward it, plus multiple scattering (frame_shade.c says
 * how). It reads the light pass's transmittances and the volume pass's forward transmittance
 * through the points and the context below; the planner's run is plan/run_shade.c. */
#ifndef SL_FRAME_SHADE_H
#define SL_FRAME_SHADE_H

#include "base/common.h"
#include "cl/clrt.h"
#include "lighting/lobes_json.h"
#include "passes/shade/shade_points.h"
#include "passes/shade/srbf_ren.h"
#include "passes/shade/srbf_tables.h"
#include "passes/volume/dual_deflect.h"
#include "passes/volume/volume.h"
#include "passes/volume/volume_ms.h"
#include "passes/volume/volume_ms_nodes.h"
#include "scene/camera.h"
#include "scene/material.h"

typedef struct sl_shade_ctx {
    const sl_material *mat;
    const sl_lobes *lobes;
    const int *used; /* lobe indices */
    int nused;
    const double *share; /* per used lobe: share of the total power */
    const sl_camera *cam;
    int ms_on;
    const sl_ftex *ftex; /* T_f, sigma_f per lobe (used index) */
    const sl_volume_ms *vms;
    /* per point: skip lobe j when T_j x share_j < point_threshold x the used shares' sum
     * (quality.point_threshold, default SL_FRAME_POINT_THRESHOLD) */
    double point_threshold;
    /* per-strand sigma_a (3 per strand, indexed by sl_shade_points.strand), or NULL: the
     * material's sigma_a everywhere (the same as r->strand_sigma_a, checked against the hair) */
    const float *strand_sigma_a;
    /* with strand_sigma_a and ms_on: the MS response at the strands' sigma_a nodes; a strand
     * whose sigma_a is the material's reads vms */
    const sl_volume_ms_nodes *msn;
    /* with ms_on: per channel, the fiber stack of the MS tables (sl_dual_stack): the local
     * backscattering is weighted by the hair behind each point (sl_shade_points.B); NULL: Zinke's
     * A_b as tabulated (a semi-infinite medium behind every point) */
    const sl_dual_stack *stack;
    /* with ms_on: the material's azimuthal deflections (sl_dual_deflect): the light arriving is
     * spread by the tilt of the fibers it crossed (the march's tilt2), the local term by the
     * fibers' spread around the point, the stacks' interreflected light by its backscattering
     * (docs/volume.md "Where the scattered light goes"); NULL: Zinke's spread sigma_f alone */
    const sl_dual_deflect *deflect;
} sl_shade_ctx;

/* Where and how the rows are evaluated (the planner fills it from the renderer). */
typedef struct sl_shade_env {
    sl_device *dev;
    int threads;   /* C threads */
    int on_device; /* evaluate rows with dev's OpenCL kernels (sl_shade_on_device) */
    int table;     /* rows with the material's sigma_a from Ren's table (ren) */
    int method;    /* the closed form otherwise: SL_SRBF_METHOD_XU or _FAST (cpu/srbf_c.h) */
    int segments;  /* Xu's quadrature segments m */
    sl_srbf_tables *tables;
    sl_srbf_ren *ren;
    cl_mem *ren_mem; /* ren resident on the device, uploaded on first use, kept by the caller */
} sl_shade_env;

/* 1 when the SRBF response (and the K-buffer fill, by the same rule) should run on dev's
 * OpenCL kernels rather than the C twins. */
int sl_shade_on_device(const sl_device *dev);
/* SRBF + MS of every point of p into p->out (SL_SHADE_FLOATS each): C twin in threads, or the
 * OpenCL srbf kernels block by block, falling back to C where dev allows. 0 or -1 with e set. */
int sl_shade_run(const sl_shade_env *env, const sl_shade_ctx *c, sl_shade_points *p, sl_err *e);

#endif
