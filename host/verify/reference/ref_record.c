/* ref_record.c: see ref_record.h. */
#include "verify/reference/ref_record.h"

#include "io/image/image_write.h"
#include "scene/scene_inputs.h"

#include <stdlib.h>
#include <string.h>

uint64_t sl_ref_hash_doubles(uint64_t h, const double *v, size_t n) {
    return sl_hash64(v, n * sizeof(double), h);
}

uint64_t sl_ref_content_hash(uint64_t h, const sl_hair *hr, uint64_t map_hash, const sl_material *m,
                             const sl_camera *c) {
    h = sl_hash64(hr->strand_first, (hr->num_strands + 1) * sizeof(uint32_t), h);
    h = sl_hash64(hr->pos, (size_t)hr->num_points * 3 * sizeof(float), h);
    if (hr->radius)
        h = sl_hash64(hr->radius, (size_t)hr->num_points * sizeof(float), h);
    else
        h = sl_hash64(&hr->default_radius, sizeof(float), h);
    h = sl_hash64(&map_hash, sizeof map_hash, h);
    double mv[] = {m->model,      m->fresnel,     m->orders,       m->eta,
                   m->alpha[0],   m->alpha[1],    m->alpha[2],     m->beta[0],
                   m->beta[1],    m->beta[2],     m->sigma_a[0],   m->sigma_a[1],
                   m->sigma_a[2], m->sigma_a_rgb, m->eccentricity, m->caustic_width};
    h = sl_ref_hash_doubles(h, mv, sizeof mv / sizeof mv[0]);
    double cv[] = {c->eye[0],   c->eye[1],   c->eye[2], c->fwd[0], c->fwd[1],
                   c->fwd[2],   c->up[0],    c->up[1],  c->up[2],  c->right[0],
                   c->right[1], c->right[2], c->focal,  c->width,  c->height};
    return sl_ref_hash_doubles(h, cv, sizeof cv / sizeof cv[0]);
}

void sl_ref_integrity_add(cJSON *ref, sl_ref_digest d) {
    cJSON *in = cJSON_AddObjectToObject(ref, "integrity");
    char hash[32];
    snprintf(hash, sizeof hash, "%016llx", (unsigned long long)d.hash);
    cJSON_AddNumberToObject(in, "exr_bytes", (double)d.bytes);
    cJSON_AddStringToObject(in, "exr_fnv1a64", hash);
}

int sl_ref_integrity_matches(const cJSON *ref, sl_ref_digest d) {
    const cJSON *in = cJSON_GetObjectItemCaseSensitive(ref, "integrity");
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(in, "exr_bytes");
    const cJSON *h = cJSON_GetObjectItemCaseSensitive(in, "exr_fnv1a64");
    char want[32];
    snprintf(want, sizeof want, "%016llx", (unsigned long long)d.hash);
    return cJSON_IsNumber(b) && b->valuedouble == (double)d.bytes && cJSON_IsString(h) &&
           strcmp(h->valuestring, want) == 0;
}

int sl_ref_json_write(const char *path, cJSON *root, sl_err *e) {
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    if (!text) return sl_fail(e, "%s: cannot format the record", path);
    sl_atomic_file af;
    int rc = -1;
    if (sl_atomic_open(&af, path, e) == 0) {
        fputs(text, af.fp);
        fputc('\n', af.fp);
        rc = sl_atomic_commit(&af, e);
    }
    free(text);
    return rc;
}

cJSON *sl_ref_json_read(const char *path) {
    unsigned char *data = NULL;
    size_t size = 0;
    if (sl_read_file(path, &data, &size, 1 << 20, NULL)) return NULL;
    cJSON *root = sl_ref_json_parse(data, size);
    free(data);
    return root;
}

cJSON *sl_ref_json_parse(const void *data, size_t size) {
    return cJSON_ParseWithLength((const char *)data, size);
}

int sl_ref_scene_load(const sl_scene *s, int width, int height, sl_hair *hair, sl_camera *cam,
                      float **strand_sa, sl_err *e) {
    sl_scene_inputs_opts io = {.width = width, .height = height, .strand_sigma_a = 1};
    sl_scene_inputs in;
    *strand_sa = NULL;
    if (sl_scene_inputs_from_scene(s, &io, &in, e)) {
        sl_scene_inputs_free(&in);
        return -1;
    }
    *hair = in.hair;
    *cam = in.cam;
    *strand_sa = in.strand_sigma_a;
    memset(&in.hair, 0, sizeof in.hair);
    in.strand_sigma_a = NULL;
    sl_scene_inputs_free(&in);
    return 0;
}

uint64_t sl_ref_strand_hash(uint64_t h, const float *strand_sa, uint32_t n) {
    if (!strand_sa) return h;
    h = sl_hash64("strand_sigma_a", 14, h);
    return sl_hash64(strand_sa, 3 * (size_t)n * sizeof *strand_sa, h);
}

static void key_string(uint64_t key, char out[32]) {
    snprintf(out, 32, "%016llx", (unsigned long long)key);
}

cJSON *sl_ref_record_begin(uint64_t key, const char *scene, int w, int h, cJSON **ref) {
    cJSON *root = cJSON_CreateObject();
    *ref = cJSON_AddObjectToObject(root, "reference");
    char k[32];
    key_string(key, k);
    cJSON_AddStringToObject(*ref, "key", k);
    cJSON_AddStringToObject(*ref, "scene", scene);
    cJSON_AddNumberToObject(*ref, "width", w);
    cJSON_AddNumberToObject(*ref, "height", h);
    return root;
}

int sl_ref_key_matches(const cJSON *ref, uint64_t key) {
    const cJSON *k = cJSON_GetObjectItemCaseSensitive(ref, "key");
    char want[32];
    key_string(key, want);
    return cJSON_IsString(k) && strcmp(k->valuestring, want) == 0;
}

void sl_ref_add_mean(cJSON *ref, const double mean_rgb[3], double coverage) {
    cJSON *mean = cJSON_AddArrayToObject(ref, "mean_rgb");
    for (int c = 0; c < 3; c++)
        cJSON_AddItemToArray(mean, cJSON_CreateNumber(mean_rgb[c]));
    cJSON_AddNumberToObject(ref, "coverage", coverage);
}

int sl_ref_exr_write_planes(const char *path, int w, int h, const char *const *names, int n,
                            float *planes, sl_err *e) {
    size_t np = (size_t)w * h;
    sl_exr_channel *ch = sl_malloc((size_t)n * sizeof *ch);
    for (int c = 0; c < n; c++)
        ch[c].name = names[c], ch[c].data = planes + c * np;
    int rc = sl_exr_write(path, w, h, ch, n, 1, e);
    free(ch);
    free(planes);
    return rc;
}
