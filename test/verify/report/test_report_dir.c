/* test_report_dir.c: the report directory's swap (host/verify/report/report_dir.h, issue 21).
 * A forked child writes a report over an old one and is SIGKILLed at its k-th kill point
 * (sl_kill_at), for every k until it finishes; after each, DIR must hold the old report or the
 * new one, whole (every file its manifest lists, all with the same tag), and a user's file
 * beside DIR is untouched. Run with RENAME_EXCHANGE and with the link fallback
 * (SL_NO_RENAME_EXCHANGE=1), from a missing DIR, a report directory and a report link. */
#include "test.h"
#include "verify/report/report_dir.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static const char *const files[] = {"results.csv", "report.md", "heat_01.png"};
#define NFILES 3

/* A report of NFILES files, each holding tag; 0 on success. */
static int write_report(const char *out, const char *tag) {
    sl_report_dir d;
    sl_err e = {{0}};
    if (sl_report_dir_check(out, &e) || sl_report_dir_begin(&d, out, &e)) return -1;
    for (int i = 0; i < NFILES; i++) {
        char p[4500];
        if (!sl_report_dir_file(&d, files[i], p, sizeof p, &e)) {
            sl_report_dir_abort(&d);
            return -1;
        }
        FILE *f = fopen(p, "w");
        if (!f) {
            sl_report_dir_abort(&d);
            return -1;
        }
        fprintf(f, "%s\n", tag);
        fclose(f);
    }
    return sl_report_dir_commit(&d, &e);
}

/* The tag of the whole report at dir ("" when missing or incomplete or mixed). */
static void report_tag(const char *dir, char *tag, size_t n) {
    tag[0] = 0;
    char p[4500], got[64], first[64] = "";
    snprintf(p, sizeof p, "%s/%s", dir, SL_REPORT_MANIFEST);
    FILE *m = fopen(p, "r");
    if (!m) return;
    int listed = 0;
    char line[256];
    while (fgets(line, sizeof line, m))
        if (!strncmp(line, "file ", 5)) listed++;
    fclose(m);
    if (listed != NFILES) return;
    for (int i = 0; i < NFILES; i++) {
        snprintf(p, sizeof p, "%s/%s", dir, files[i]);
        FILE *f = fopen(p, "r");
        if (!f) return;
        if (!fgets(got, sizeof got, f)) got[0] = 0;
        fclose(f);
        if (i == 0) snprintf(first, sizeof first, "%s", got);
        if (strcmp(got, first) != 0) return;
    }
    first[strcspn(first, "\n")] = 0;
    snprintf(tag, n, "%s", first);
}

/* Entries of dir whose name starts with prefix. */
static int count_prefix(const char *dir, const char *prefix) {
    DIR *d = opendir(dir);
    if (!d) return -1;
    int c = 0;
    struct dirent *de;
    while ((de = readdir(d)))
        if (!strncmp(de->d_name, prefix, strlen(prefix))) c++;
    closedir(d);
    return c;
}

enum { START_MISSING, START_DIR, START_LINK };

/* Kills the swap at every point; returns the number of points seen. */
static int kill_sweep(const char *name, int start, int no_exchange) {
    char base[4096];
    sl_test_fresh_dir(name, base, sizeof base);
    if (!base[0]) return 0;
    int k;
    for (k = 1; k < 64; k++) {
        char root[4200], out[4300], p[4400], tag[64];
        snprintf(root, sizeof root, "%s/k%d", base, k);
        mkdir(root, 0777);
        snprintf(out, sizeof out, "%s/rep", root);
        snprintf(p, sizeof p, "%s/notes.txt", root);
        FILE *u = fopen(p, "w");
        fputs("mine\n", u);
        fclose(u);
        if (start == START_LINK) setenv("SL_NO_RENAME_EXCHANGE", "1", 1);
        if (start != START_MISSING) CHECK(write_report(out, "old") == 0);
        unsetenv("SL_NO_RENAME_EXCHANGE");
        struct stat st;
        CHECK(start != START_LINK || (lstat(out, &st) == 0 && S_ISLNK(st.st_mode)));
        char log[4400];
        snprintf(log, sizeof log, "%s/points.log", base);
        fflush(stdout);
        pid_t pid = fork();
        if (pid == 0) {
            FILE *lf = freopen(log, "w", stderr);
            (void)lf;
            if (no_exchange) setenv("SL_NO_RENAME_EXCHANGE", "1", 1);
            sl_kill_at(k, 1);
            _exit(write_report(out, "new") == 0 ? 0 : 3);
        }
        int ws = 0;
        waitpid(pid, &ws, 0);
        /* the last point passed (the one that killed it) */
        char last[256] = "", line[256];
        FILE *lf = fopen(log, "r");
        while (lf && fgets(line, sizeof line, lf))
            if (strstr(line, "kill point")) snprintf(last, sizeof last, "%s", line);
        if (lf) fclose(lf);
        int killed = WIFSIGNALED(ws) && WTERMSIG(ws) == SIGKILL;
        report_tag(out, tag, sizeof tag);
        u = fopen(p, "r");
        char mine[16] = "";
        if (u) {
            if (!fgets(mine, sizeof mine, u)) mine[0] = 0;
            fclose(u);
        }
        CHECK_MSG(!strcmp(mine, "mine\n"), "%s k=%d: the user's file changed", name, k);
        if (!killed) {
            CHECK_MSG(WIFEXITED(ws) && WEXITSTATUS(ws) == 0, "%s k=%d: status %d", name, k, ws);
            CHECK_MSG(!strcmp(tag, "new"), "%s: finished but DIR holds '%s'", name, tag);
            /* nothing left beside DIR: at most the link's versioned directory */
            int left = count_prefix(root, "rep.");
            int is_link = lstat(out, &st) == 0 && S_ISLNK(st.st_mode);
            CHECK_MSG(left == is_link, "%s: %d entries rep.* left beside DIR", name, left);
            break;
        }
        if (strstr(last, "moved aside")) {
            /* the one window of the fallback's first conversion: DIR missing, both reports
             * whole beside it */
            CHECK_MSG(tag[0] == 0, "%s k=%d: DIR exists in the conversion window", name, k);
            CHECK_MSG(count_prefix(root, "rep.report-") == 2, "%s k=%d: reports beside DIR", name,
                      k);
            continue;
        }
        int ok = !strcmp(tag, "new") || (start != START_MISSING && !strcmp(tag, "old")) ||
                 (start == START_MISSING && tag[0] == 0 && lstat(out, &st) != 0);
        CHECK_MSG(ok, "%s: killed at %d (%.*s): DIR holds '%s'", name, k, (int)strcspn(last, "\n"),
                  last, tag);
    }
    sl_kill_at(0, 0);
    return k - 1;
}

TEST(report_dir_kill_exchange) {
    int n = kill_sweep("rdk_exchange", START_DIR, 0);
    CHECK_MSG(n >= 5, "%d kill points", n); /* written, before, exchanged, removals */
}

TEST(report_dir_kill_new) {
    int n = kill_sweep("rdk_new", START_MISSING, 0);
    CHECK_MSG(n >= 2, "%d kill points", n);
}

TEST(report_dir_kill_link_fallback) {
    int n = kill_sweep("rdk_link", START_LINK, 1);
    CHECK_MSG(n >= 5, "%d kill points", n);
}

TEST(report_dir_kill_new_link_fallback) {
    int n = kill_sweep("rdk_newlink", START_MISSING, 1);
    CHECK_MSG(n >= 2, "%d kill points", n);
}

TEST(report_dir_kill_convert_fallback) {
    int n = kill_sweep("rdk_convert", START_DIR, 1);
    CHECK_MSG(n >= 5, "%d kill points", n);
}

/* A stranger in a report directory (a user's file) refuses the report, before and at the swap;
 * the stranger and the old report stay. */
TEST(report_dir_refuses_stranger) {
    char base[4096], out[4200], p[4400], tag[64];
    sl_test_fresh_dir("rd_stranger", base, sizeof base);
    snprintf(out, sizeof out, "%s/rep", base);
    CHECK(write_report(out, "old") == 0);
    snprintf(p, sizeof p, "%s/mine.txt", out);
    FILE *f = fopen(p, "w");
    fputs("x", f);
    fclose(f);
    sl_err e = {{0}};
    CHECK(sl_report_dir_check(out, &e) != 0);
    CHECK_MSG(strstr(e.msg, "holds mine.txt, which this command did not write"), "%s", e.msg);
    CHECK(write_report(out, "new") != 0);
    struct stat st;
    CHECK(stat(p, &st) == 0);
    report_tag(out, tag, sizeof tag);
    CHECK(!strcmp(tag, "old"));
    CHECK(count_prefix(base, "rep.") == 0);
}

/* A report from before the manifest listed its files: its fixed names are ours. */
TEST(report_dir_old_manifest) {
    char base[4096], out[4200], p[4400], tag[64];
    sl_test_fresh_dir("rd_oldmanifest", base, sizeof base);
    snprintf(out, sizeof out, "%s/rep", base);
    mkdir(out, 0777);
    snprintf(p, sizeof p, "%s/%s", out, SL_REPORT_MANIFEST);
    FILE *f = fopen(p, "w");
    fputs("strandlight report directory: `report -o` replaces it whole\n", f);
    fclose(f);
    snprintf(p, sizeof p, "%s/report.md", out);
    f = fopen(p, "w");
    fputs("old\n", f);
    fclose(f);
    CHECK(write_report(out, "new") == 0);
    report_tag(out, tag, sizeof tag);
    CHECK(!strcmp(tag, "new"));
    CHECK(count_prefix(base, "rep.") == 0);
}

/* A link this command did not make is refused, the link and its target kept. */
TEST(report_dir_foreign_link) {
    char base[4096], out[4200], t[4200];
    sl_test_fresh_dir("rd_link", base, sizeof base);
    snprintf(out, sizeof out, "%s/rep", base);
    snprintf(t, sizeof t, "%s/elsewhere", base);
    mkdir(t, 0777);
    CHECK(symlink("elsewhere", out) == 0);
    sl_err e = {{0}};
    CHECK(sl_report_dir_check(out, &e) != 0);
    CHECK_MSG(strstr(e.msg, "is a symbolic link"), "%s", e.msg);
    struct stat st;
    CHECK(lstat(out, &st) == 0 && S_ISLNK(st.st_mode));
}
