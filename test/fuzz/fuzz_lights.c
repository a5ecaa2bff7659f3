/* fuzz_lights.c: libFuzzer target for the lights JSON of `strandlight sample` / `reference`
 * (sl_envlights_parse, lighting/envsample.h; sl_envlights_load is it plus the file read).
 * Any input must either parse into 1..SL_LOBES_MAX lights with a unit dir, finite rgb >= 0 and
 * a finite solid_angle, and a "sample" record that is JSON again when present, or fail with one
 * non-empty line that starts with the file name and leave the struct zeroed; never crash, leak
 * or read past the given length (exact-size copy, no terminating NUL).
 * envsample.c also holds the median-cut sampler, which needs the map and the fitter's error;
 * those three functions are stubs here (a trap: the parser must not call them), which keeps
 * the map decoders and the fitter out of this target. Seeds: test/fuzz/corpus/fuzz_lights/.
 */
// clang-format off
/* FUZZ_SOURCES: host/lighting/envsample.c host/base/json_util.c host/base/common.c */
// clang-format on
#include "lighting/envfit.h"
#include "lighting/envsample.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

double sl_envfit_conv_rel_l2(const sl_envmap *map, const sl_lobe *lobes, int n, double conv_lambda,
                             int threads) {
    (void)map, (void)lobes, (void)n, (void)conv_lambda, (void)threads;
    __builtin_trap();
}
void sl_envmap_dir(int w, int h, double x, double y, double dir[3]) {
    (void)w, (void)h, (void)x, (void)y, (void)dir;
    __builtin_trap();
}
double sl_envmap_pixel_solid_angle(int w, int h, int y) {
    (void)w, (void)h, (void)y;
    __builtin_trap();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = malloc(size ? size : 1);
    if (size) memcpy(text, data, size);
    sl_envlights l;
    sl_err e = {{0}};
    if (sl_envlights_parse(text, size, "fuzz.json", &l, &e) == 0) {
        if (l.count < 1 || l.count > SL_LOBES_MAX || !l.light) __builtin_trap();
        for (int i = 0; i < l.count; i++) {
            const sl_envlight *L = &l.light[i];
            double n = sqrt(L->dir[0] * L->dir[0] + L->dir[1] * L->dir[1] + L->dir[2] * L->dir[2]);
            /* normalised by the loader from within 1e-3 of unit length: 1 up to a few ulps */
            if (!(fabs(n - 1) < 1e-12)) __builtin_trap();
            for (int k = 0; k < 3; k++)
                if (!(L->rgb[k] >= 0) || !isfinite(L->rgb[k])) __builtin_trap();
            if (!isfinite(L->solid_angle)) __builtin_trap();
        }
        if (l.record_json) {
            cJSON *r = cJSON_Parse(l.record_json); /* sl_envlights_save parses it again */
            if (!r) __builtin_trap();
            cJSON_Delete(r);
        }
        sl_envlights_free(&l);
    } else {
        if (e.msg[0] == 0 || strchr(e.msg, '\n') || strncmp(e.msg, "fuzz.json", 9) != 0)
            __builtin_trap();
        if (l.count || l.light || l.record_json) __builtin_trap();
    }
    free(text);
    return 0;
}
