/* fuzz_scene.c: libFuzzer target for the scene loader (JSON -> validated sl_scene). Any input
 * must either parse or fail with a message; never crash, leak or read out of bounds.
 * FUZZ_SOURCES: host/scene/scene.c host/base/json_util.c host/scene/material.c host/base/common.c */
#include "scene/scene.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static sl_scene s;
    sl_err e;
    sl_scene_parse((const char *)data, size, "fuzz.json", &s, &e);
    return 0;
}
