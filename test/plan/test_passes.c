/* test_passes.c: the pass descriptors of host/plan/passes.h as data: every pass output read by a
 * pass is written by an earlier one (the table's order is a valid schedule), no output has two
 * writers, every pass has a run, and the one key rule depends on exactly the inputs a pass
 * declares (changing an undeclared input's hash must not change the key; a declared one must). */
#include "test.h"

#include "plan/passes.h"

#include <string.h>

/* The frame's own inputs (not made by any pass). */
static const uint32_t frame_inputs = SL_IN(SL_DATA_GEOMETRY) | SL_IN(SL_DATA_TRANSPARENCY) |
                                     SL_IN(SL_DATA_MATERIAL) | SL_IN(SL_DATA_STRAND_SIGMA) |
                                     SL_IN(SL_DATA_ENVIRONMENT) | SL_IN(SL_DATA_CAMERA) |
                                     SL_IN(SL_DATA_QUALITY);

TEST(passes_table_is_a_schedule) {
    uint32_t written = frame_inputs;
    for (int i = 0; i < SL_PASSID_COUNT; i++) {
        const sl_pass_desc *d = &sl_passes[i];
        CHECK_MSG(d->name && d->name[0], "pass %d has no name", i);
        CHECK_MSG(d->run != NULL, "pass %s has no run", d->name);
        uint32_t missing = d->inputs & ~written;
        CHECK_MSG(missing == 0, "pass %s reads %s before any pass writes it", d->name,
                  sl_frame_data_name(__builtin_ctz(missing ? missing : 1)));
        CHECK_MSG(
            (d->outputs & written) == 0, "pass %s writes %s, written before", d->name,
            sl_frame_data_name(__builtin_ctz((d->outputs & written) ? d->outputs & written : 1)));
        CHECK_MSG(d->outputs != 0, "pass %s writes nothing", d->name);
        written |= d->outputs;
    }
    /* every datum is produced (or is a frame input), and the frame is the last output */
    CHECK(written == (1u << SL_DATA_COUNT) - 1);
    CHECK(sl_passes[SL_PASSID_COUNT - 1].outputs == SL_IN(SL_DATA_FRAME));
}

TEST(passes_names_unique) {
    for (int i = 0; i < SL_PASSID_COUNT; i++)
        for (int j = i + 1; j < SL_PASSID_COUNT; j++)
            CHECK_MSG(strcmp(sl_passes[i].name, sl_passes[j].name) != 0, "two passes named %s",
                      sl_passes[i].name);
}

TEST(passes_key_reads_only_declared_inputs) {
    for (int i = 0; i < SL_PASSID_COUNT; i++) {
        const sl_pass_desc *d = &sl_passes[i];
        if (!d->keyed) continue;
        uint64_t h[SL_DATA_COUNT];
        for (int k = 0; k < SL_DATA_COUNT; k++)
            h[k] = 0x9e3779b97f4a7c15ull * (uint64_t)(k + 1);
        const uint64_t base = sl_pass_key(d, h, 7);
        CHECK(base != 0);
        CHECK_MSG(sl_pass_key(d, h, 8) != base, "pass %s: key ignores its settings", d->name);
        for (int k = 0; k < SL_DATA_COUNT; k++) {
            uint64_t g[SL_DATA_COUNT];
            memcpy(g, h, sizeof g);
            g[k] ^= 0x5555;
            const int declared = (d->inputs >> k) & 1u;
            const uint64_t key = sl_pass_key(d, g, 7);
            CHECK_MSG((key != base) == declared, "pass %s: key %s on %s", d->name,
                      declared ? "ignores" : "depends", sl_frame_data_name(k));
        }
    }
}
