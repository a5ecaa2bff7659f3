/* material.h: the fiber material of numerics.md section 2, in double on the host (the reference
 * needs the exact decimal values; the float backends convert with sl_material_to_fiber()).
 *
 *   sl_material m;
 *   if (sl_material_load("mat.json", &m, &e)) ... e.msg is "mat.json: beta_R_deg: must be > 0"
 *   sl_fiber_params fp; sl_material_to_fiber(&m, channel, &fp);   (float, one colour channel)
 *
 * JSON keys, defaults and validation rules: numerics.md sec. 2 and docs/eval.md. */
#ifndef SL_MATERIAL_H
#define SL_MATERIAL_H

#include "base/common.h"
#include "fiber_params.h"

#include <cjson/cJSON.h>

enum { SL_MODEL_MARSCHNER = 0, SL_MODEL_DEON = 1, SL_MODEL_CHIANG = 2 };
enum { SL_FRESNEL_EXACT = 0, SL_FRESNEL_SCHLICK = 1 };

/* Largest `orders` a material file may ask for. The float backends (C twin, OpenCL) allow at
 * most SL_DEON_MAX_ORDERS (32, kernels/fiber_deon.h); only the double reference goes higher.
 * The bound keeps the output width (orders + 3 columns) and the reference's run time sane (about
 * 12 ms of CPU per order per scatter row); orders above it are still counted, in f_rest. */
#define SL_MATERIAL_MAX_ORDERS 256

/* The Principled Hair (Chiang 2016, Blender/Cycles) parameters of model chiang as the user gave
 * them (numerics.md sec. 2); sl_material_from_json derives the model's quantities from them into
 * sl_material (docs/numerics-chiang.md): v_p = beta[p]^2, the cuticle shifts in alpha[] (d'Eon
 * form: theta_o - 2 alpha[p]), logistic_s, and sigma_a unless it was given directly. */
typedef struct sl_chiang {
    double melanin;          /* 0..1 */
    double melanin_redness;  /* 0..1 */
    double tint[3];          /* (0, 1] */
    double roughness;        /* (0, 1]: longitudinal, b_l */
    double radial_roughness; /* (0, 1]: azimuthal, b */
    double coat;             /* [0, 1) */
    double offset;           /* cuticle tilt alpha, radians (offset_deg) */
    int sigma_a_given;       /* 1: sigma_a came from the file, not from melanin and tint */
} sl_chiang;

typedef struct sl_material {
    int model;            /* SL_MODEL_* */
    int fresnel;          /* SL_FRESNEL_* */
    int orders;           /* d'Eon explicit orders p = 0..orders (>= 2) */
    double eta;           /* index of refraction, > 1 */
    double alpha[3];      /* R, TT, TRT shifts, radians */
    double beta[3];       /* R, TT, TRT widths, radians (Marschner: Gaussian width; d'Eon: std) */
    double sigma_a[3];    /* absorption per unit radius, r g b */
    int sigma_a_rgb;      /* 1 when given as [r,g,b] or from melanin: outputs get _r/_g/_b */
    double eccentricity;  /* a of Xu Eq. 24 (TRT only) */
    double caustic_width; /* w_c, radians */
    double logistic_s;    /* chiang: azimuthal logistic scale s */
    sl_chiang chiang;     /* chiang: the user's parameters (the model uses the derived fields) */
} sl_material;

/* Chiang / Cycles mappings (numerics.md sec. 3), exposed for the tests and docs:
 * longitudinal variance v for a roughness b_l, logistic scale s for a radial roughness b, and
 * sigma_a from melanin, redness, tint and radial roughness (rgb). */
double sl_chiang_variance(double roughness);
double sl_chiang_logistic_scale(double radial_roughness);
void sl_chiang_sigma_a_rgb(const sl_chiang *c, double sigma_a[3]);
/* Recomputes the derived fields (alpha, beta, logistic_s, and sigma_a unless given) of a chiang
 * material from m->chiang: for code that builds a material without JSON (tests). */
void sl_chiang_derive(sl_material *m);

/* The material keys only some models have (NULL-terminated): those of marschner and deon that
 * chiang lacks, and those of chiang that marschner and deon lack (`melanin` is in neither: an
 * object for marschner / deon, a number for chiang). The parser refuses them on the other
 * models; the viewer drops them when the model changes. */
extern const char *const sl_material_lobe_keys[];
extern const char *const sl_material_chiang_keys[];

/* "marschner", "deon" or "chiang". */
const char *sl_material_model_name(int model);

/* The defaults of numerics.md section 2. */
void sl_material_default(sl_material *m);

/* One colour channel (0 r, 1 g, 2 b; sigma_a[channel]) of m in float for the C twin and the
 * OpenCL kernels. */
void sl_material_to_fiber(const sl_material *m, int channel, sl_fiber_params *fp);

/* Reads the material object `obj` (numerics.md sec. 2) into m. m starts from the defaults
 * (sl_material_default); the keys present override them, and TT/TRT alpha/beta follow R's
 * unless given. Errors name the file and the key path below key_prefix ("" or NULL at the top):
 * "scene.json: material.eta: must be > 1". Returns 0, or -1 with e set (m is then undefined). */
int sl_material_from_json(const cJSON *obj, const char *file, const char *key_prefix,
                          sl_material *m, sl_err *e);

/* Loads a material file whose top level is the material object. Malformed JSON:
 * "mat.json: invalid JSON near line N". */
int sl_material_load(const char *path, sl_material *m, sl_err *e);
/* The same from memory; file_name is used in messages. */
int sl_material_parse(const char *text, size_t len, const char *file_name, sl_material *m,
                      sl_err *e);

#endif
