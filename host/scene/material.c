/* material.c: material defaults, JSON parsing and validation (numerics.md section 2), and the
 * conversion of one colour channel to the float sl_fiber_params of the C twin and OpenCL.
 *
 * Every error names the file and the key path: "mat.json: beta_R_deg: must be > 0", or, from
 * the scene loader (key_prefix "material"), "scene.json: material.eta: must be > 1". */
#include "scene/material.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DEG (3.14159265358979323846 / 180.0)

static void chiang_default(sl_chiang *c) {
    memset(c, 0, sizeof *c);
    c->melanin = 0.8;
    c->melanin_redness = 1.0;
    c->tint[0] = c->tint[1] = c->tint[2] = 1.0;
    c->roughness = 0.3;
    c->radial_roughness = 0.3;
    c->coat = 0.0;
    c->offset = 2.0 * DEG;
}

const char *const sl_material_lobe_keys[] = {"alpha_R_deg",
                                             "beta_R_deg",
                                             "alpha_TT_deg",
                                             "beta_TT_deg",
                                             "alpha_TRT_deg",
                                             "beta_TRT_deg",
                                             "eccentricity",
                                             "caustic_width_deg",
                                             "fresnel",
                                             "orders",
                                             NULL};
const char *const sl_material_chiang_keys[] = {
    "melanin_redness", "tint", "roughness", "radial_roughness", "coat", "offset_deg", NULL};

const char *sl_material_model_name(int model) {
    return model == SL_MODEL_DEON ? "deon" : model == SL_MODEL_CHIANG ? "chiang" : "marschner";
}

void sl_material_default(sl_material *m) {
    memset(m, 0, sizeof *m);
    m->model = SL_MODEL_MARSCHNER;
    m->fresnel = SL_FRESNEL_EXACT;
    m->orders = 8;
    m->eta = 1.55;
    /* Xu 2011 Sec. 6: alpha_TT = -alpha_R/2, alpha_TRT = -3 alpha_R/2, beta_TT = beta_R/2,
     * beta_TRT = 2 beta_R. */
    m->alpha[0] = -7.5 * DEG;
    m->alpha[1] = 3.75 * DEG;
    m->alpha[2] = 11.25 * DEG;
    m->beta[0] = 7.5 * DEG;
    m->beta[1] = 3.75 * DEG;
    m->beta[2] = 15.0 * DEG;
    m->sigma_a[0] = m->sigma_a[1] = m->sigma_a[2] = 0.36;
    m->eccentricity = 1.0;
    m->caustic_width = 15.0 * DEG;
    chiang_default(&m->chiang);
}

/* Cycles' Principled Hair mappings (numerics.md sec. 3). */
double sl_chiang_variance(double bl) {
    double b2 = bl * bl, b4 = b2 * b2, b8 = b4 * b4, b16 = b8 * b8;
    double x = 0.726 * bl + 0.812 * b2 + 3.7 * b16 * b4;
    return x * x;
}

double sl_chiang_logistic_scale(double b) {
    double b2 = b * b, b4 = b2 * b2, b8 = b4 * b4, b16 = b8 * b8;
    return 0.626657068657750126 * (0.265 * b + 1.194 * b2 + 5.372 * b16 * b4 * b2);
}

void sl_chiang_sigma_a_rgb(const sl_chiang *c, double sigma_a[3]) {
    double q = -log(fmax(1.0 - c->melanin, 1e-4));
    double eu = q * (1.0 - c->melanin_redness), ph = q * c->melanin_redness;
    static const double ce[3] = {0.506, 0.841, 1.653}, cp[3] = {0.343, 0.733, 1.924};
    double b = c->radial_roughness, b2 = b * b, b3 = b2 * b, b4 = b3 * b, b5 = b4 * b;
    double den = 5.969 - 0.215 * b + 2.532 * b2 - 10.73 * b3 + 5.574 * b4 + 0.245 * b5;
    for (int i = 0; i < 3; i++) {
        double t = log(c->tint[i]) / den;
        sigma_a[i] = eu * ce[i] + ph * cp[i] + t * t;
    }
}

void sl_chiang_derive(sl_material *m) {
    const sl_chiang *c = &m->chiang;
    double v0 = sl_chiang_variance(c->roughness);
    double vr = sl_chiang_variance(c->roughness * (1.0 - c->coat));
    m->beta[0] = sqrt(vr);
    m->beta[1] = sqrt(v0 / 4.0);
    m->beta[2] = sqrt(4.0 * v0);
    m->alpha[0] = c->offset;
    m->alpha[1] = -c->offset / 2.0;
    m->alpha[2] = -2.0 * c->offset;
    m->logistic_s = sl_chiang_logistic_scale(c->radial_roughness);
    m->orders = 2;
    m->fresnel = SL_FRESNEL_EXACT;
    if (!c->sigma_a_given) {
        sl_chiang_sigma_a_rgb(c, m->sigma_a);
        m->sigma_a_rgb = 1;
    }
}

void sl_material_to_fiber(const sl_material *m, int channel, sl_fiber_params *fp) {
    memset(fp, 0, sizeof *fp);
    if (channel < 0 || channel > 2) channel = 0;
    fp->model = m->model;
    fp->fresnel = m->fresnel;
    fp->orders = m->orders;
    fp->eta = (float)m->eta;
    fp->eccentricity = (float)m->eccentricity;
    fp->caustic_width = (float)m->caustic_width;
    fp->sigma_a = (float)m->sigma_a[channel];
    fp->logistic_s = (float)m->logistic_s;
    for (int t = 0; t < 3; t++) {
        fp->alpha[t] = (float)m->alpha[t];
        fp->beta[t] = (float)m->beta[t];
    }
}

/* ---- small typed readers; each message is "<file>: <path>: <problem>" ---- */

typedef struct mctx {
    const char *file;
    const char *prefix; /* "" at the top */
} mctx;

static void key_path(const mctx *c, const char *key, char *out, size_t n) {
    if (c->prefix[0])
        snprintf(out, n, "%s.%s", c->prefix, key);
    else
        snprintf(out, n, "%s", key);
}

static int key_fail(const mctx *c, const char *key, const char *problem, sl_err *e) {
    char p[512];
    key_path(c, key, p, sizeof p);
    return sl_fail(e, "%s: %s: %s", c->file, p, problem);
}

/* A finite number (cJSON turns 1e999 into inf; NaN is not JSON at all). */
static int read_number(const mctx *c, const cJSON *v, const char *key, double *out, sl_err *e) {
    if (!cJSON_IsNumber(v)) return key_fail(c, key, "expected a number", e);
    if (!isfinite(v->valuedouble)) return key_fail(c, key, "must be a finite number", e);
    *out = v->valuedouble;
    return 0;
}

/* Unknown keys and duplicate keys (cJSON keeps both; which one wins would be a guess). */
static int check_keys(const mctx *c, const cJSON *obj, const char *const *allowed, sl_err *e) {
    for (const cJSON *it = obj->child; it; it = it->next) {
        const char *k = it->string ? it->string : "";
        int ok = 0;
        for (const char *const *a = allowed; *a; a++)
            if (strcmp(k, *a) == 0) ok = 1;
        if (!ok) return key_fail(c, k, "unknown key", e);
        for (const cJSON *jt = obj->child; jt != it; jt = jt->next)
            if (jt->string && strcmp(jt->string, k) == 0) return key_fail(c, k, "duplicate key", e);
    }
    return 0;
}

static int read_angle(const mctx *c, const cJSON *obj, const char *key, int positive, double *rad,
                      int *given, sl_err *e) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    *given = 0;
    if (!v) return 0;
    double d = 0;
    if (read_number(c, v, key, &d, e)) return -1;
    if (positive && !(d > 0)) return key_fail(c, key, "must be > 0", e);
    /* a positive width so small that it underflows to 0 radians is no width either */
    if (positive && !(d * DEG > 0)) return key_fail(c, key, "must be > 0 (too small)", e);
    *rad = d * DEG;
    *given = 1;
    return 0;
}

static int read_sigma_a(const mctx *c, const cJSON *v, sl_material *m, sl_err *e) {
    if (cJSON_IsNumber(v)) {
        double d = 0;
        if (read_number(c, v, "sigma_a", &d, e)) return -1;
        if (d < 0) return key_fail(c, "sigma_a", "must be >= 0", e);
        m->sigma_a[0] = m->sigma_a[1] = m->sigma_a[2] = d;
        m->sigma_a_rgb = 0;
        return 0;
    }
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3)
        return key_fail(c, "sigma_a", "expected a number or an array of 3 numbers [r, g, b]", e);
    int i = 0;
    for (const cJSON *it = v->child; it; it = it->next, i++) {
        char k[32];
        snprintf(k, sizeof k, "sigma_a[%d]", i);
        if (read_number(c, it, k, &m->sigma_a[i], e)) return -1;
        if (m->sigma_a[i] < 0) return key_fail(c, k, "must be >= 0", e);
    }
    m->sigma_a_rgb = 1;
    return 0;
}

/* d'Eon 2011 Sec. 6.1: sigma_a = rho_e (0.419, 0.697, 1.37) + rho_p (0.187, 0.4, 1.05). */
static int read_melanin(const mctx *c, const cJSON *v, sl_material *m, sl_err *e) {
    if (!cJSON_IsObject(v)) return key_fail(c, "melanin", "expected an object", e);
    char sub[512];
    key_path(c, "melanin", sub, sizeof sub);
    mctx mc = {c->file, sub};
    static const char *const keys[] = {"eumelanin", "pheomelanin", NULL};
    if (check_keys(&mc, v, keys, e)) return -1;
    double rho[2] = {0, 0};
    for (int k = 0; k < 2; k++) {
        const cJSON *x = cJSON_GetObjectItemCaseSensitive(v, keys[k]);
        if (!x) continue;
        if (read_number(&mc, x, keys[k], &rho[k], e)) return -1;
        if (rho[k] < 0) return key_fail(&mc, keys[k], "must be >= 0", e);
    }
    static const double eu[3] = {0.419, 0.697, 1.37}, pheo[3] = {0.187, 0.4, 1.05};
    for (int i = 0; i < 3; i++)
        m->sigma_a[i] = rho[0] * eu[i] + rho[1] * pheo[i];
    if (!isfinite(m->sigma_a[2])) return key_fail(c, "melanin", "too large (sigma_a overflows)", e);
    m->sigma_a_rgb = 1;
    return 0;
}

static int read_choice(const mctx *c, const cJSON *obj, const char *key, const char *a,
                       const char *b, int *out, sl_err *e) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v) return 0;
    char msg[128];
    snprintf(msg, sizeof msg, "expected \"%s\" or \"%s\"", a, b);
    if (!cJSON_IsString(v) || !v->valuestring) return key_fail(c, key, msg, e);
    if (strcmp(v->valuestring, a) == 0)
        *out = 0;
    else if (strcmp(v->valuestring, b) == 0)
        *out = 1;
    else
        return key_fail(c, key, msg, e);
    return 0;
}

static int read_orders(const mctx *c, const cJSON *obj, sl_material *m, sl_err *e) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, "orders");
    if (!v) return 0;
    double d = 0;
    if (read_number(c, v, "orders", &d, e)) return -1;
    if (d != floor(d) || d < 2) return key_fail(c, "orders", "must be an integer >= 2", e);
    if (d > SL_MATERIAL_MAX_ORDERS) {
        char msg[160];
        snprintf(msg, sizeof msg,
                 "must be at most %d (the float backends allow at most 32; the orders above are "
                 "still counted, in f_rest)",
                 SL_MATERIAL_MAX_ORDERS);
        return key_fail(c, "orders", msg, e);
    }
    m->orders = (int)d;
    return 0;
}

/* A number in [lo, hi] (open at an end where lo_open / hi_open). */
static int read_ranged(const mctx *c, const cJSON *obj, const char *key, double lo, int lo_open,
                       double hi, int hi_open, double *out, sl_err *e) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v) return 0;
    double d = 0;
    if (read_number(c, v, key, &d, e)) return -1;
    if ((lo_open ? !(d > lo) : !(d >= lo)) || (hi_open ? !(d < hi) : !(d <= hi))) {
        char msg[96];
        snprintf(msg, sizeof msg, "must be in %c%g, %g%c", lo_open ? '(' : '[', lo, hi,
                 hi_open ? ')' : ']');
        return key_fail(c, key, msg, e);
    }
    *out = d;
    return 0;
}

/* model "chiang": Blender's Principled Hair parameters (numerics.md sec. 2). */
static int read_chiang(const mctx *c, const cJSON *obj, sl_material *m, sl_err *e) {
    static const char *const keys[] = {
        "model",      "melanin", "melanin_redness", "tint", "roughness", "radial_roughness", "coat",
        "offset_deg", "eta",     "sigma_a",         NULL};
    for (const cJSON *it = obj->child; it; it = it->next) {
        const char *k = it->string ? it->string : "";
        int ok = 0;
        for (const char *const *a = keys; *a; a++)
            if (strcmp(k, *a) == 0) ok = 1;
        for (const char *const *a = sl_material_lobe_keys; *a && !ok; a++)
            if (strcmp(k, *a) == 0)
                return key_fail(c, k,
                                "not a key of model \"chiang\" (its keys: melanin, "
                                "melanin_redness, tint, roughness, radial_roughness, coat, "
                                "offset_deg, eta, sigma_a)",
                                e);
    }
    if (check_keys(c, obj, keys, e)) return -1;
    sl_chiang *ch = &m->chiang;
    const cJSON *sa = cJSON_GetObjectItemCaseSensitive(obj, "sigma_a");
    static const char *const pig[] = {"melanin", "melanin_redness", "tint", NULL};
    for (const char *const *k = pig; *k; k++)
        if (sa && cJSON_GetObjectItemCaseSensitive(obj, *k))
            return key_fail(c, *k, "cannot be given together with sigma_a (choose one)", e);
    const cJSON *mel = cJSON_GetObjectItemCaseSensitive(obj, "melanin");
    if (mel && !cJSON_IsNumber(mel))
        return key_fail(c, "melanin",
                        "expected a number in [0, 1] with model \"chiang\" (the eumelanin / "
                        "pheomelanin object is for marschner and deon)",
                        e);
    if (read_ranged(c, obj, "melanin", 0, 0, 1, 0, &ch->melanin, e)) return -1;
    if (read_ranged(c, obj, "melanin_redness", 0, 0, 1, 0, &ch->melanin_redness, e)) return -1;
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(obj, "tint");
    if (t) {
        if (!cJSON_IsArray(t) || cJSON_GetArraySize(t) != 3)
            return key_fail(c, "tint", "expected an array of 3 numbers [r, g, b] in (0, 1]", e);
        int i = 0;
        for (const cJSON *it = t->child; it; it = it->next, i++) {
            char k[32];
            snprintf(k, sizeof k, "tint[%d]", i);
            if (read_number(c, it, k, &ch->tint[i], e)) return -1;
            if (!(ch->tint[i] > 0 && ch->tint[i] <= 1))
                return key_fail(c, k, "must be in (0, 1]", e);
        }
    }
    if (read_ranged(c, obj, "roughness", 0, 1, 1, 0, &ch->roughness, e)) return -1;
    if (read_ranged(c, obj, "radial_roughness", 0, 1, 1, 0, &ch->radial_roughness, e)) return -1;
    if (read_ranged(c, obj, "coat", 0, 0, 1, 1, &ch->coat, e)) return -1;
    double off = ch->offset / DEG;
    if (read_ranged(c, obj, "offset_deg", -45, 0, 45, 0, &off, e)) return -1;
    ch->offset = off * DEG;
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, "eta");
    if (v) {
        if (read_number(c, v, "eta", &m->eta, e)) return -1;
        if (!(m->eta > 1)) return key_fail(c, "eta", "must be > 1", e);
    }
    if (sa) {
        if (read_sigma_a(c, sa, m, e)) return -1;
        ch->sigma_a_given = 1;
    }
    sl_chiang_derive(m);
    /* a roughness so small that its variance underflows to 0 has no lobe */
    for (int p = 0; p < 3; p++)
        if (!(m->beta[p] > 0))
            return key_fail(c, p == 0 && ch->coat > 0 ? "coat" : "roughness",
                            "too small (the longitudinal variance underflows to 0)", e);
    return 0;
}

int sl_material_from_json(const cJSON *obj, const char *file, const char *key_prefix,
                          sl_material *m, sl_err *e) {
    mctx c = {file ? file : "material", key_prefix ? key_prefix : ""};
    sl_material_default(m);
    if (!cJSON_IsObject(obj)) {
        if (c.prefix[0]) return sl_fail(e, "%s: %s: expected an object", c.file, c.prefix);
        return sl_fail(e, "%s: expected a JSON object at the top level", c.file);
    }
    static const char *const keys[] = {"model",         "eta",          "alpha_R_deg",
                                       "beta_R_deg",    "alpha_TT_deg", "beta_TT_deg",
                                       "alpha_TRT_deg", "beta_TRT_deg", "sigma_a",
                                       "melanin",       "eccentricity", "caustic_width_deg",
                                       "fresnel",       "orders",       NULL};
    const cJSON *mv = cJSON_GetObjectItemCaseSensitive(obj, "model");
    if (cJSON_IsString(mv) && mv->valuestring && strcmp(mv->valuestring, "chiang") == 0) {
        m->model = SL_MODEL_CHIANG;
        return read_chiang(&c, obj, m, e);
    }
    for (const char *const *k = sl_material_chiang_keys; *k; k++)
        if (cJSON_GetObjectItemCaseSensitive(obj, *k))
            return key_fail(&c, *k, "is a key of model \"chiang\" only", e);
    if (check_keys(&c, obj, keys, e)) return -1;

    if (mv &&
        !(cJSON_IsString(mv) && mv->valuestring &&
          (strcmp(mv->valuestring, "marschner") == 0 || strcmp(mv->valuestring, "deon") == 0)))
        return key_fail(&c, "model", "expected \"marschner\", \"deon\" or \"chiang\"", e);
    if (read_choice(&c, obj, "model", "marschner", "deon", &m->model, e)) return -1;
    if (read_choice(&c, obj, "fresnel", "exact", "schlick", &m->fresnel, e)) return -1;
    if (m->model == SL_MODEL_DEON && m->fresnel == SL_FRESNEL_SCHLICK)
        return key_fail(&c, "fresnel",
                        "\"schlick\" is not allowed with model \"deon\" (d'Eon always uses exact "
                        "Fresnel)",
                        e);

    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, "eta");
    if (v) {
        if (read_number(&c, v, "eta", &m->eta, e)) return -1;
        if (!(m->eta > 1)) return key_fail(&c, "eta", "must be > 1", e);
    }

    /* R first; TT and TRT follow it (Xu 2011 Sec. 6) unless given explicitly. */
    static const char *const akeys[3] = {"alpha_R_deg", "alpha_TT_deg", "alpha_TRT_deg"};
    static const char *const bkeys[3] = {"beta_R_deg", "beta_TT_deg", "beta_TRT_deg"};
    double a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
    int ga[3], gb[3];
    for (int t = 0; t < 3; t++) {
        if (read_angle(&c, obj, akeys[t], 0, &a[t], &ga[t], e)) return -1;
        if (read_angle(&c, obj, bkeys[t], 1, &b[t], &gb[t], e)) return -1;
    }
    if (ga[0]) m->alpha[0] = a[0];
    if (gb[0]) m->beta[0] = b[0];
    m->alpha[1] = ga[1] ? a[1] : -m->alpha[0] / 2;
    m->alpha[2] = ga[2] ? a[2] : -3 * m->alpha[0] / 2;
    m->beta[1] = gb[1] ? b[1] : m->beta[0] / 2;
    m->beta[2] = gb[2] ? b[2] : 2 * m->beta[0];

    const cJSON *sa = cJSON_GetObjectItemCaseSensitive(obj, "sigma_a");
    const cJSON *mel = cJSON_GetObjectItemCaseSensitive(obj, "melanin");
    if (sa && mel)
        return key_fail(&c, "melanin", "cannot be given together with sigma_a (choose one)", e);
    if (sa && read_sigma_a(&c, sa, m, e)) return -1;
    if (mel && read_melanin(&c, mel, m, e)) return -1;

    v = cJSON_GetObjectItemCaseSensitive(obj, "eccentricity");
    if (v) {
        if (read_number(&c, v, "eccentricity", &m->eccentricity, e)) return -1;
        if (!(m->eccentricity > 0)) return key_fail(&c, "eccentricity", "must be > 0", e);
        /* Outside 1/sqrt(2) < a < sqrt(2), Xu Eq. 24 gives eta* <= 1 for some azimuths; the
         * contract accepts every a > 0, and the TRT term is then 0 where its refraction is
         * impossible (docs/numerics.md, "Eccentricity"). */
    }
    double wc = 0;
    int gwc;
    if (read_angle(&c, obj, "caustic_width_deg", 1, &wc, &gwc, e)) return -1;
    if (gwc) m->caustic_width = wc;
    if (read_orders(&c, obj, m, e)) return -1;
    return 0;
}

static int line_at(const char *text, const char *stop) {
    int line = 1;
    for (const char *p = text; p < stop; p++)
        if (*p == '\n') line++;
    return line;
}

int sl_material_parse(const char *text, size_t len, const char *file_name, sl_material *m,
                      sl_err *e) {
    /* Like sl_json_parse, but content after the JSON value ("{} x") is an error too. */
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    if (!root) {
        const char *stop = end && end >= text && end <= text + len ? end : text;
        return sl_fail(e, "%s: invalid JSON near line %d", file_name, line_at(text, stop));
    }
    for (const char *p = end; p < text + len && *p; p++)
        if (*p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') {
            cJSON_Delete(root);
            return sl_fail(e, "%s: invalid JSON near line %d (text after the object)", file_name,
                           line_at(text, p));
        }
    int rc = sl_material_from_json(root, file_name, "", m, e);
    cJSON_Delete(root);
    return rc;
}

int sl_material_load(const char *path, sl_material *m, sl_err *e) {
    unsigned char *data;
    size_t n;
    if (sl_read_file(path, &data, &n, 1u << 20, e)) return -1;
    int rc = sl_material_parse((const char *)data, n, path, m, e);
    free(data);
    return rc;
}
