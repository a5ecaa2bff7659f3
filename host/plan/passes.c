/* passes.c: the table of the frame's passes and the one cache-key rule (passes.h). */
#include "plan/passes.h"

#include <stdio.h>
#include <string.h>

#define IN SL_IN

static const char *const data_names[SL_DATA_COUNT] = {
    "geometry", "transparency", "material",   "strand sigma_a", "environment", "camera",
    "quality",  "srbf tables",  "used lobes", "lobes",          "lobe dirs",   "map budget",
    "maps",     "ms decision",  "dual",       "volume",         "ms table",    "K-buffer",
    "points",   "srbf method",  "shaded",     "frame",
};

const char *sl_frame_data_name(int d) {
    return d >= 0 && d < SL_DATA_COUNT ? data_names[d] : "?";
}

const sl_pass_desc sl_passes[SL_PASSID_COUNT] = {
    [SL_PASSID_TABLES] = {.name = "tables",
                          .outputs = IN(SL_DATA_SRBF_TABLES),
                          .keyed = 1, /* no inputs: built or loaded once per renderer */
                          .cached_why = "SRBF tables kept in memory",
                          .run = sl_pass_tables},
    [SL_PASSID_LOBES] = {.name = "lobes",
                         .inputs = IN(SL_DATA_ENVIRONMENT) | IN(SL_DATA_QUALITY),
                         .outputs = IN(SL_DATA_USED_LOBES),
                         .run = sl_pass_lobes},
    [SL_PASSID_SUBDIVIDE] = {.name = "subdivide",
                             .inputs = IN(SL_DATA_USED_LOBES) | IN(SL_DATA_QUALITY),
                             .outputs =
                                 IN(SL_DATA_LOBES) | IN(SL_DATA_LOBE_DIRS) | IN(SL_DATA_MAP_BUDGET),
                             .run = sl_pass_subdivide},
    [SL_PASSID_LIGHT] = {.name = "light",
                         .inputs =
                             IN(SL_DATA_GEOMETRY) | IN(SL_DATA_LOBES) | IN(SL_DATA_MAP_BUDGET),
                         .outputs = IN(SL_DATA_MAPS),
                         .keyed = 1,
                         .settings = sl_light_settings,
                         .settings_name = "quality.shadow_size, layers, kappa",
                         .on_cached = sl_light_on_cached,
                         .run = sl_pass_light},
    [SL_PASSID_MS] = {.name = "ms",
                      .inputs = IN(SL_DATA_MATERIAL) | IN(SL_DATA_QUALITY),
                      .outputs = IN(SL_DATA_MS_ON),
                      .run = sl_pass_ms},
    /* the dual-scattering tables feed only the march: built when MS runs */
    [SL_PASSID_DUAL] = {.name = "dual",
                        .inputs = IN(SL_DATA_MATERIAL),
                        .outputs = IN(SL_DATA_DUAL),
                        .keyed = 1,
                        .settings = sl_dual_settings,
                        .settings_name = "the strands' mean sigma_a",
                        .needed = sl_ms_needed,
                        .skip_why = "no multiple scattering",
                        .cached_why = "dual-scattering tables reused (material unchanged)",
                        .run = sl_pass_dual},
    /* voxel grid (geometry, quality.voxels) + shadow-path march toward every shaded lobe
     * through the dual tables (material): a material edit re-runs only the march */
    [SL_PASSID_VOLUME] = {.name = "volume",
                          .inputs = IN(SL_DATA_GEOMETRY) | IN(SL_DATA_LOBE_DIRS) | IN(SL_DATA_DUAL),
                          .outputs = IN(SL_DATA_VOLUME),
                          .keyed = 1,
                          .settings = sl_volume_settings,
                          .settings_name = "quality.voxels",
                          .needed = sl_ms_needed,
                          .skip_why = "no multiple scattering",
                          .cached_why = "voxel grid and march textures reused (geometry, lobes, "
                                        "material unchanged)",
                          .run = sl_pass_volume},
    [SL_PASSID_MS_TABLE] = {.name = "ms table",
                            .inputs = IN(SL_DATA_MATERIAL),
                            .outputs = IN(SL_DATA_MS_TABLE),
                            .keyed = 1,
                            .settings = sl_ms_table_settings,
                            .settings_name = "the strands' sigma_a nodes",
                            .needed = sl_ms_needed,
                            .skip_why = "no multiple scattering",
                            .cached_why = "material unchanged",
                            .run = sl_pass_ms_table},
    [SL_PASSID_VIEW] = {.name = "view",
                        .inputs =
                            IN(SL_DATA_GEOMETRY) | IN(SL_DATA_TRANSPARENCY) | IN(SL_DATA_CAMERA),
                        .outputs = IN(SL_DATA_KBUFFER),
                        .keyed = 1,
                        .settings = sl_view_settings,
                        .settings_name = "K (quality.oit_layers)",
                        .cached_why = "K-buffer reused (geometry, camera and K unchanged)",
                        .run = sl_pass_view},
    [SL_PASSID_LOOKUP] = {.name = "lookup",
                          .inputs = IN(SL_DATA_KBUFFER) | IN(SL_DATA_MAPS) | IN(SL_DATA_LOBES) |
                                    IN(SL_DATA_QUALITY),
                          .outputs = IN(SL_DATA_POINTS),
                          .run = sl_pass_lookup},
    [SL_PASSID_SRBF] = {.name = "srbf",
                        .inputs = IN(SL_DATA_MATERIAL) | IN(SL_DATA_STRAND_SIGMA) |
                                  IN(SL_DATA_POINTS) | IN(SL_DATA_USED_LOBES),
                        .outputs = IN(SL_DATA_SRBF),
                        .run = sl_pass_srbf},
    [SL_PASSID_SHADE] = {.name = "shade",
                         .inputs = IN(SL_DATA_MATERIAL) | IN(SL_DATA_STRAND_SIGMA) |
                                   IN(SL_DATA_CAMERA) | IN(SL_DATA_LOBES) | IN(SL_DATA_QUALITY) |
                                   IN(SL_DATA_SRBF_TABLES) | IN(SL_DATA_MS_ON) |
                                   IN(SL_DATA_VOLUME) | IN(SL_DATA_MS_TABLE) | IN(SL_DATA_POINTS) |
                                   IN(SL_DATA_SRBF),
                         .outputs = IN(SL_DATA_SHADED),
                         .run = sl_pass_shade},
    [SL_PASSID_RESOLVE] = {.name = "resolve",
                           .inputs = IN(SL_DATA_KBUFFER) | IN(SL_DATA_POINTS) | IN(SL_DATA_SHADED),
                           .outputs = IN(SL_DATA_FRAME),
                           .run = sl_pass_resolve},
};

uint64_t sl_pass_key(const sl_pass_desc *d, const uint64_t *data_hash, uint64_t settings) {
    uint64_t k = sl_hash64(d->name, strlen(d->name), 0x50415353);
    for (int i = 0; i < SL_DATA_COUNT; i++)
        if (d->inputs & IN(i)) k = sl_hash64(&data_hash[i], sizeof data_hash[i], k);
    k = sl_hash64(&settings, sizeof settings, k);
    return k | 1;
}

static uint64_t hash_geometry(const sl_hair *h) {
    uint64_t k = 0x11;
    k = sl_hash64(&h->num_strands, sizeof h->num_strands, k);
    k = sl_hash64(h->strand_first, ((size_t)h->num_strands + 1) * sizeof *h->strand_first, k);
    k = sl_hash64(h->pos, (size_t)h->num_points * 3 * sizeof *h->pos, k);
    if (h->radius)
        k = sl_hash64(h->radius, (size_t)h->num_points * sizeof *h->radius, k);
    else
        k = sl_hash64(&h->default_radius, sizeof h->default_radius, k);
    return k;
}

void sl_frame_hash_inputs(const sl_frame_inputs *in, uint64_t *dh) {
    const sl_hair *h = in->h;
    const sl_material *mat = &in->s->material;
    memset(dh, 0, SL_DATA_COUNT * sizeof *dh);
    dh[SL_DATA_GEOMETRY] = hash_geometry(h);
    uint64_t t = 0x33;
    if (h->transparency) t = sl_hash64(h->transparency, (size_t)h->num_points * sizeof(float), t);
    dh[SL_DATA_TRANSPARENCY] = sl_hash64(&h->default_transparency, sizeof(float), t);
    uint64_t m = 0x22; /* field by field: the struct has padding */
    int mi[4] = {mat->model, mat->fresnel, mat->orders, mat->sigma_a_rgb};
    m = sl_hash64(mi, sizeof mi, m);
    m = sl_hash64(&mat->eta, sizeof mat->eta, m);
    m = sl_hash64(mat->alpha, sizeof mat->alpha, m);
    m = sl_hash64(mat->beta, sizeof mat->beta, m);
    m = sl_hash64(mat->sigma_a, sizeof mat->sigma_a, m);
    m = sl_hash64(&mat->eccentricity, sizeof mat->eccentricity, m);
    m = sl_hash64(&mat->caustic_width, sizeof mat->caustic_width, m);
    /* chiang: the logistic scale (its other parameters reach alpha, beta and sigma_a) */
    dh[SL_DATA_MATERIAL] = sl_hash64(&mat->logistic_s, sizeof mat->logistic_s, m);
    dh[SL_DATA_CAMERA] = sl_hash64(in->cam, sizeof *in->cam, 0x44);
}

void sl_pass_keyed_on(const sl_pass_desc *d, char *buf, size_t n) {
    if (!d->keyed) {
        snprintf(buf, n, "-");
        return;
    }
    size_t at = 0;
    buf[0] = 0;
    for (int i = 0; i < SL_DATA_COUNT && at < n; i++)
        if (d->inputs & IN(i))
            at += (size_t)snprintf(buf + at, n - at, "%s%s", at ? ", " : "", data_names[i]);
    if (d->settings_name && at < n)
        snprintf(buf + at, n - at, "%s%s", at ? " + " : "", d->settings_name);
    else if (!at)
        snprintf(buf, n, "(once)");
}
