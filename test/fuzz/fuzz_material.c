/* fuzz_material.c: libFuzzer target for the material file parser (sl_material_parse: JSON ->
 * validated sl_material, numerics.md sec. 2). Any input must either parse into a material that
 * satisfies the documented invariants or fail with a one-line, non-empty message naming the
 * file; never crash, leak or read out of bounds. The input is copied to an exact-size buffer
 * without a terminating NUL, so that ASan sees any read past the given length.
 * Seeds: test/fuzz/corpus/fuzz_material/.
 * FUZZ_SOURCES: host/scene/material.c host/base/json_util.c host/base/common.c */
#include "scene/material.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = malloc(size ? size : 1);
    if (size) memcpy(text, data, size);
    sl_material m;
    sl_err e = {{0}};
    if (sl_material_parse(text, size, "fuzz.json", &m, &e) == 0) {
        /* numerics.md sec. 2: eta > 1, widths > 0, finite absorption >= 0, orders >= 2. */
        if (!(m.eta > 1) || !isfinite(m.eta)) __builtin_trap();
        if (m.orders < 2 || m.orders > SL_MATERIAL_MAX_ORDERS) __builtin_trap();
        for (int k = 0; k < 3; k++) {
            if (!isfinite(m.alpha[k]) || !(m.beta[k] > 0) || !isfinite(m.beta[k])) __builtin_trap();
            if (!(m.sigma_a[k] >= 0) || !isfinite(m.sigma_a[k])) __builtin_trap();
        }
        sl_fiber_params fp;
        sl_material_to_fiber(&m, 1, &fp);
    } else {
        if (e.msg[0] == 0 || strchr(e.msg, '\n') || strncmp(e.msg, "fuzz.json", 9) != 0)
            __builtin_trap();
    }
    free(text);
    return 0;
}
