/* srbf_stiff_fixture.h: the stiff sample with its exact values, as test_srbf.c and
 * test_srbf_ren.c read it: the 150 configurations of host/verify/report/srbf_sample.c (SL_SRBF_SAMPLE_SEED) and
 * the values the independent double reference (cpu/reference/srbf_ref.c) wrote to
 * test/test_srbf_stiff.csv. Static inline: every test file includes it into the one unit_tests
 * binary. */
#ifndef SL_TEST_SRBF_STIFF_FIXTURE_H
#define SL_TEST_SRBF_STIFF_FIXTURE_H

#include "test.h"

#include "verify/report/report_srbf.h"
#include "verify/report/srbf_sample.h"

#include <stdlib.h>

enum { SRBF_STIFF_N = 150 };

/* Allocates and fills *cfg and *x (the caller frees both, whatever the result); a read failure
 * is a FAIL of the calling test. Returns sl_srbf_exact_read's result. */
static inline int srbf_stiff_read(sl_srbf_config **cfg, sl_srbf_exact **x) {
    *cfg = malloc(SRBF_STIFF_N * sizeof **cfg);
    *x = malloc(SRBF_STIFF_N * sizeof **x);
    sl_srbf_sample(SL_SRBF_SAMPLE_SEED, SRBF_STIFF_N, *cfg);
    sl_err e = {{0}};
    int rc = sl_srbf_exact_read("test/test_srbf_stiff.csv", *cfg, SRBF_STIFF_N, *x, &e);
    CHECK_MSG(rc == 0, "%s", e.msg);
    return rc;
}

#endif
