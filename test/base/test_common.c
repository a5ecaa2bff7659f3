/* test_common.c: path helpers and atomic output of host/base/common.c. */
#include "base/common.h"
#include "test.h"

#include <string.h>
#include <sys/stat.h>

TEST(common_path_helpers) {
    char buf[256];
    sl_dirname("a/b/c.json", buf, sizeof buf);
    CHECK(strcmp(buf, "a/b") == 0);
    sl_dirname("c.json", buf, sizeof buf);
    CHECK(strcmp(buf, ".") == 0);
    sl_path_join("a/b", "x.hair", buf, sizeof buf);
    CHECK(strcmp(buf, "a/b/x.hair") == 0);
    sl_path_join("a/b", "/abs/x.hair", buf, sizeof buf);
    CHECK(strcmp(buf, "/abs/x.hair") == 0);
    CHECK(sl_ext_is("x/y.Hair", "hair"));
    CHECK(!sl_ext_is("x.hair/y", "hair"));
}

TEST(common_atomic_abort_leaves_nothing) {
    char path[512];
    snprintf(path, sizeof path, "%s/atomic/out.txt", sl_test_tmpdir());
    remove(path); /* a run before this one (same test directory) left its committed file */
    sl_atomic_file af;
    sl_err e;
    CHECK(sl_atomic_open(&af, path, &e) == 0);
    fputs("half", af.fp);
    sl_atomic_abort(&af);
    struct stat st;
    CHECK(stat(path, &st) != 0);
    CHECK(stat(af.tmp_path, &st) != 0);
    CHECK(sl_atomic_open(&af, path, &e) == 0);
    fputs("whole", af.fp);
    CHECK(sl_atomic_commit(&af, &e) == 0);
    CHECK(stat(path, &st) == 0 && st.st_size == 5);
}
