/* test.h: a minimal unit-test harness (one binary, build/.../unit_tests, for all test/test_*.c).
 *
 *   TEST(name) { CHECK(x == 1); CHECK_NEAR(a, b, tol); CHECK_REL(a, b, rtol); }
 *
 * Tests register themselves (constructor attribute), run in file/registration order, and print
 * "PASS name" / "FAIL name: why" / "SKIP name: why"; test/run.sh counts those lines.
 * `unit_tests FILTER` runs the tests whose name contains FILTER. */
#ifndef SL_TEST_H
#define SL_TEST_H

#include <math.h>
#include <stdio.h>

typedef void (*sl_test_fn)(void);
void sl_test_register(const char *name, sl_test_fn fn);
void sl_test_fail(const char *file, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
void sl_test_skip(const char *why);
/* Directory of ../shared/data (env SL_SHARED_DATA, default ../shared/data from the repo root),
 * or NULL when it is absent; tests that need it call SKIP. */
const char *sl_test_shared_data(void);
/* A fresh scratch directory for this test run (under build dir). */
const char *sl_test_tmpdir(void);
/* out = a new empty directory sl_test_tmpdir()/name-PID (emptied if it exists); out[0] = 0 when
 * it cannot be made. */
void sl_test_fresh_dir(const char *name, char *out, size_t n);
/* Files in dir whose name contains part (dot files aside), or -1 when dir cannot be read. */
int sl_test_count_files(const char *dir, const char *part);
int sl_test_failed_now(void);

#define TEST(name)                                                                                 \
    static void test_##name(void);                                                                 \
    __attribute__((constructor)) static void register_##name(void) {                               \
        sl_test_register(#name, test_##name);                                                      \
    }                                                                                              \
    static void test_##name(void)

#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (!(cond)) sl_test_fail(__FILE__, __LINE__, "CHECK(%s)", #cond);                         \
    } while (0)
#define CHECK_MSG(cond, ...)                                                                       \
    do {                                                                                           \
        if (!(cond)) sl_test_fail(__FILE__, __LINE__, __VA_ARGS__);                                \
    } while (0)
#define CHECK_NEAR(a, b, tol)                                                                      \
    do {                                                                                           \
        double a_ = (double)(a), b_ = (double)(b);                                                 \
        if (!(fabs(a_ - b_) <= (tol)))                                                             \
            sl_test_fail(__FILE__, __LINE__, "%s = %.9g, %s = %.9g, |diff| > %g", #a, a_, #b, b_,  \
                         (double)(tol));                                                           \
    } while (0)
#define CHECK_REL(a, b, rtol)                                                                      \
    do {                                                                                           \
        double a_ = (double)(a), b_ = (double)(b);                                                 \
        if (!(fabs(a_ - b_) <= (rtol) * fabs(b_)))                                                 \
            sl_test_fail(__FILE__, __LINE__, "%s = %.9g, %s = %.9g, rel diff > %g", #a, a_, #b,    \
                         b_, (double)(rtol));                                                      \
    } while (0)
/* Marks the current test skipped (with a reason) and returns from it. */
#define SKIP(why)                                                                                  \
    do {                                                                                           \
        sl_test_skip(why);                                                                         \
        return;                                                                                    \
    } while (0)

#endif
