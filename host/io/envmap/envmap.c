/* envmap.c: environment-map loading (format dispatch by magic bytes, clamping of negative and
 * non-finite values, hash), the lat-long frame of numerics.md sec. 4 and per-map statistics.
 * The decoders live in envmap_exr.c (+ exr_cxx_shim.cpp) and envmap_hdr.c. */
#include "io/envmap/envmap.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

int sl_envmap_size_ok(long long w, long long h, size_t n, double max_pixels_per_byte) {
    if (w < 1 || h < 1 || w > SL_ENVMAP_MAX_DIM || h > SL_ENVMAP_MAX_DIM) return 0;
    long long px = w * h;
    if (px > SL_ENVMAP_MAX_PIXELS) return 0;
    return px <= (1LL << 20) || (double)px <= max_pixels_per_byte * (double)n;
}

/* A positive number from the environment, else def. */
static double env_limit(const char *var, double def) {
    const char *v = getenv(var);
    if (!v || !*v) return def;
    char *end;
    double x = strtod(v, &end);
    return *end == 0 && x > 0 && x < 1e15 ? x : def;
}

int sl_decode_budget_ok(const char *name, const char *what, long long w, long long h,
                        double raw_bytes_per_px, double out_bytes_per_px, size_t file_bytes,
                        sl_err *e) {
    double px = (double)w * (double)h;
    double max_mb = env_limit("SL_IMAGE_MAX_MB", SL_IMAGE_MAX_MB_DEFAULT);
    double mem = px * out_bytes_per_px;
    if (mem > max_mb * 1048576.0)
        return !sl_fail(e,
                        "%s: %s: decoding %lld x %lld needs %.0f MiB, over the limit of %.0f MiB "
                        "(SL_IMAGE_MAX_MB raises it)",
                        name, what, w, h, mem / 1048576.0, max_mb);
    double ratio = env_limit("SL_IMAGE_MAX_RATIO", SL_IMAGE_MAX_RATIO_DEFAULT);
    double raw = px * raw_bytes_per_px;
    if (raw > SL_IMAGE_RATIO_FLOOR && raw > ratio * (double)file_bytes)
        return !sl_fail(e,
                        "%s: %s: %lld x %lld decompresses to %.0f MiB from a %zu-byte file, over "
                        "%.0f bytes per file byte (SL_IMAGE_MAX_RATIO raises it)",
                        name, what, w, h, raw / 1048576.0, file_bytes, ratio);
    return 1;
}

static int is_exr(const unsigned char *d, size_t n) {
    return n >= 4 && d[0] == 0x76 && d[1] == 0x2f && d[2] == 0x31 && d[3] == 0x01;
}

static int is_radiance(const unsigned char *d, size_t n) {
    return n >= 2 && d[0] == '#' && d[1] == '?';
}

int sl_envmap_decode_memory(const unsigned char *data, size_t n, const char *name, sl_envmap *out,
                            sl_err *e) {
    memset(out, 0, sizeof *out);
    if (n == 0) return sl_fail(e, "%s: empty file, expected an OpenEXR or Radiance .hdr map", name);
    if (is_exr(data, n)) return sl_envmap_decode_exr(data, n, name, 0, out, e);
    if (is_radiance(data, n)) return sl_envmap_decode_hdr(data, n, name, out, e);
    return sl_fail(e, "%s: not an OpenEXR or Radiance .hdr file (unrecognised magic bytes)", name);
}

int sl_envmap_sanitize(sl_envmap *m, const char *name, int nonfinite_mode, sl_err *e) {
    size_t nv = (size_t)m->width * (size_t)m->height * 3;
    long neg = 0, bad = 0;
    for (size_t i = 0; i < nv; i++) {
        float v = m->rgb[i];
        if (!isfinite(v))
            bad++;
        else if (v < 0.0f)
            neg++;
    }
    if (bad && nonfinite_mode == SL_NONFINITE_ERROR)
        return sl_fail(e,
                       "%s: %ld non-finite values (NaN/Inf) in the map; use --clamp-nonfinite to "
                       "replace them by 0",
                       name, bad);
    if (bad || neg)
        for (size_t i = 0; i < nv; i++)
            if (!isfinite(m->rgb[i]) || m->rgb[i] < 0.0f) m->rgb[i] = 0.0f;
    m->negatives = neg;
    m->nonfinite = bad;
    if (nonfinite_mode != SL_NONFINITE_CLAMP_QUIET) {
        if (neg)
            sl_warn("%s: %ld negative values (lossy-compression ringing) clamped to 0", name, neg);
        if (bad) sl_warn("%s: %ld non-finite values (NaN/Inf) replaced by 0", name, bad);
    }
    int32_t dims[2] = {m->width, m->height};
    uint64_t h = sl_hash64(dims, sizeof dims, 0x656e766d6170ull /* "envmap" */);
    m->hash = sl_hash64(m->rgb, nv * sizeof(float), h);
    return 0;
}

int sl_envmap_load_memory(const unsigned char *data, size_t n, const char *name,
                          int clamp_nonfinite, sl_envmap *out, sl_err *e) {
    if (sl_envmap_decode_memory(data, n, name, out, e)) return -1;
    int mode = clamp_nonfinite ? SL_NONFINITE_CLAMP_WARN : SL_NONFINITE_ERROR;
    if (sl_envmap_sanitize(out, name, mode, e)) {
        sl_envmap_free(out);
        return -1;
    }
    return 0;
}

int sl_envmap_load(const char *path, int clamp_nonfinite, sl_envmap *out, sl_err *e) {
    unsigned char *data;
    size_t n;
    memset(out, 0, sizeof *out);
    if (sl_read_file(path, &data, &n, SL_ENVMAP_MAX_FILE, e)) return -1;
    int rc = sl_envmap_load_memory(data, n, path, clamp_nonfinite, out, e);
    free(data);
    return rc;
}

void sl_envmap_free(sl_envmap *m) {
    free(m->rgb);
    m->rgb = NULL;
    m->width = m->height = 0;
}

void sl_envmap_dir(int w, int h, double x, double y, double dir[3]) {
    double th = PI * (y + 0.5) / h, ph = 2.0 * PI * (x + 0.5) / w - PI;
    dir[0] = sin(th) * sin(ph);
    dir[1] = cos(th);
    dir[2] = -sin(th) * cos(ph);
}

void sl_envmap_dir_to_pixel(int w, int h, const double dir[3], double *x, double *y) {
    double r = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    double c = r > 0 ? dir[1] / r : 1.0;
    if (c > 1) c = 1;
    if (c < -1) c = -1;
    double th = acos(c);
    double ph = atan2(dir[0], -dir[2]); /* in (-pi, pi]: ph = 0 looks down -Z */
    double u = (ph + PI) / (2.0 * PI);  /* in (0, 1] */
    if (u >= 1.0) u -= 1.0;
    *x = u * w - 0.5;
    *y = th / PI * h - 0.5;
}

double sl_envmap_pixel_solid_angle(int w, int h, int y) {
    return 2.0 * PI / w * (cos(PI * y / h) - cos(PI * (y + 1) / h));
}

void sl_envmap_stats_compute(const sl_envmap *m, sl_envmap_stats *s) {
    memset(s, 0, sizeof *s);
    int w = m->width, h = m->height;
    double sum_y = 0, sum_yw = 0, sum_c[3] = {0, 0, 0}, sum_cw[3] = {0, 0, 0}, sum_w = 0;
    s->lum_min = INFINITY;
    s->lum_max = -INFINITY;
    for (int y = 0; y < h; y++) {
        double om = sl_envmap_pixel_solid_angle(w, h, y);
        double row_y = 0, row_c[3] = {0, 0, 0};
        for (int x = 0; x < w; x++) {
            const float *p = m->rgb + 3 * ((size_t)y * w + x);
            double lum = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            if (lum < s->lum_min) s->lum_min = lum;
            if (lum > s->lum_max) {
                s->lum_max = lum;
                s->max_x = x;
                s->max_y = y;
            }
            row_y += lum;
            for (int c = 0; c < 3; c++)
                row_c[c] += p[c];
        }
        sum_y += row_y;
        sum_yw += row_y * om;
        for (int c = 0; c < 3; c++) {
            sum_c[c] += row_c[c];
            sum_cw[c] += row_c[c] * om;
        }
        sum_w += om * w;
    }
    double np = (double)w * h;
    s->lum_mean_pixel = sum_y / np;
    s->lum_mean_solid_angle = sum_yw / sum_w;
    for (int c = 0; c < 3; c++) {
        s->rgb_mean_pixel[c] = sum_c[c] / np;
        s->rgb_mean_solid_angle[c] = sum_cw[c] / sum_w;
    }
    sl_envmap_dir(w, h, s->max_x, s->max_y, s->max_dir);
    s->max_elev_deg = 90.0 - 180.0 * (s->max_y + 0.5) / h;
}
