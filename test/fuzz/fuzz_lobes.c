/* fuzz_lobes.c: libFuzzer target for the SRBF lobe file parser (sl_lobes_parse, lobes_json.h).
 * Any input must either parse into lobes that satisfy the documented invariants (1 <= count <=
 * SL_LOBES_MAX, unit dir, lambda > 0, finite rgb >= 0) or fail with a one-line message naming
 * the file and leave the struct zeroed; never crash, leak or read past the given length (exact-
 * size copy, no terminating NUL). Seeds: test/fuzz/corpus/fuzz_lobes/.
 * FUZZ_SOURCES: host/lighting/lobes_json.c host/base/json_util.c host/base/common.c */
#include "lighting/lobes_json.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = malloc(size ? size : 1);
    if (size) memcpy(text, data, size);
    sl_lobes l;
    sl_err e = {{0}};
    if (sl_lobes_parse(text, size, "fuzz.json", &l, &e) == 0) {
        if (l.count < 1 || l.count > SL_LOBES_MAX || !l.lobe) __builtin_trap();
        for (int i = 0; i < l.count; i++) {
            const sl_lobe *b = &l.lobe[i];
            double n = sqrt(b->dir[0] * b->dir[0] + b->dir[1] * b->dir[1] + b->dir[2] * b->dir[2]);
            /* The loader normalises dirs within 1e-3 of unit length: after that the length is
             * 1 up to a few ulps; 1e-12 is far above that and far below any real deviation. */
            if (!(fabs(n - 1) < 1e-12)) __builtin_trap();
            if (!(b->lambda > 0) || !isfinite(b->lambda)) __builtin_trap();
            for (int k = 0; k < 3; k++)
                if (!(b->rgb[k] >= 0) || !isfinite(b->rgb[k])) __builtin_trap();
            if (!isfinite(sl_lobe_integral(b->lambda))) __builtin_trap();
        }
        sl_lobes_free(&l);
    } else {
        if (e.msg[0] == 0 || strchr(e.msg, '\n') || strncmp(e.msg, "fuzz.json", 9) != 0)
            __builtin_trap();
        if (l.count || l.lobe || l.fit_json) __builtin_trap(); /* zeroed on failure */
    }
    free(text);
    return 0;
}
