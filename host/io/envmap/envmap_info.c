/* envmap_info.c: `strandlight info` for environment maps (called by cmd_info.c for .exr/.hdr).
 *
 * Unlike sl_envmap_load, NaN/Inf values are not an error here: info reports how many there are
 * (and how many negative values the loader would clamp), and computes the statistics with both
 * replaced by 0, i.e. on the map exactly as `sl_envmap_load(..., clamp_nonfinite=1)` gives it. */
#include "io/envmap/envmap.h"

#include <inttypes.h>
#include <math.h>
#include <stdlib.h>

int sl_envmap_info(const char *path, FILE *out, sl_err *e) {
    unsigned char *data;
    size_t n;
    if (sl_read_file(path, &data, &n, SL_ENVMAP_MAX_FILE, e)) return -1;
    sl_envmap m;
    int rc = sl_envmap_decode_memory(data, n, path, &m, e);
    free(data);
    if (rc) return -1;
    sl_envmap_sanitize(&m, path, SL_NONFINITE_CLAMP_QUIET, e);
    sl_envmap_stats s;
    sl_envmap_stats_compute(&m, &s);
    fprintf(out, "file: %s\n", path);
    fprintf(out, "type: environment map (lat-long)\n");
    fprintf(out, "format: %s\n", m.format);
    fprintf(out, "size: %d x %d%s\n", m.width, m.height,
            m.width == 2 * m.height ? "" : " (not 2:1; a lat-long map is normally 2:1)");
    fprintf(out, "channels: %d (%s)\n", m.channels, m.channel_names);
    fprintf(out, "luminance min: %.6g\n", s.lum_min);
    fprintf(out,
            "luminance max: %.6g at pixel (%d, %d), elevation %.1f deg, dir (%.4f, %.4f, %.4f)\n",
            s.lum_max, s.max_x, s.max_y, s.max_elev_deg, s.max_dir[0], s.max_dir[1], s.max_dir[2]);
    fprintf(out, "luminance mean (per pixel): %.6g\n", s.lum_mean_pixel);
    fprintf(out, "luminance mean (solid angle): %.6g\n", s.lum_mean_solid_angle);
    fprintf(out, "rgb mean (solid angle): %.6g %.6g %.6g\n", s.rgb_mean_solid_angle[0],
            s.rgb_mean_solid_angle[1], s.rgb_mean_solid_angle[2]);
    fprintf(out, "negative values: %ld%s\n", m.negatives,
            m.negatives ? " (clamped to 0 at load)" : "");
    fprintf(out, "non-finite values: %ld%s\n", m.nonfinite,
            m.nonfinite ? " (loading fails unless --clamp-nonfinite)" : "");
    fprintf(out, "hash: %016" PRIx64 "\n", m.hash);
    sl_envmap_free(&m);
    return 0;
}
