/* report_dir.c: see report_dir.h. */
#include "verify/report/report_dir.h"

#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ------------------------------------------------------------------ the manifest */

#define MANIFEST_HEAD "strandlight report directory: `report -o` replaces it whole"
#define MANIFEST_MAX 65536

typedef struct {
    int found;    /* the manifest exists and is a regular file */
    int has_list; /* it lists its files (reports from before the list: the fixed names) */
    char (*names)[64];
    int n;
} manifest;

static void manifest_free(manifest *m) {
    free(m->names);
    memset(m, 0, sizeof *m);
}

static void manifest_read(const char *dir, manifest *m) {
    memset(m, 0, sizeof *m);
    char p[4400];
    snprintf(p, sizeof p, "%s/%s", dir, SL_REPORT_MANIFEST);
    struct stat st;
    if (lstat(p, &st) != 0 || !S_ISREG(st.st_mode)) return;
    m->found = 1;
    unsigned char *data;
    size_t size;
    sl_err e = {{0}};
    if (st.st_size > MANIFEST_MAX || sl_read_file(p, &data, &size, MANIFEST_MAX, &e)) return;
    m->names = sl_calloc(SL_REPORT_MAX_FILES, sizeof *m->names);
    char *save = NULL;
    for (char *line = strtok_r((char *)data, "\n", &save); line; line = strtok_r(NULL, "\n", &save))
        if (!strncmp(line, "file ", 5) && strlen(line + 5) < 64 && m->n < SL_REPORT_MAX_FILES) {
            snprintf(m->names[m->n++], 64, "%s", line + 5);
            m->has_list = 1;
        }
    free(data);
}

/* The files of a report from before the manifest listed them. */
static int fixed_report_file(const char *name) {
    size_t n = strlen(name);
    if (!strcmp(name, "results.csv") || !strcmp(name, "report.md") ||
        !strcmp(name, "error_vs_time.svg") || !strcmp(name, "reference.png") ||
        !strcmp(name, "reference_fragments.png"))
        return 1;
    return !strncmp(name, "heat_", 5) && n > 9 && !strcmp(name + n - 4, ".png");
}

static int is_ours(const manifest *m, const char *name) {
    if (!strcmp(name, SL_REPORT_MANIFEST)) return 1;
    if (!m->has_list) return fixed_report_file(name);
    for (int i = 0; i < m->n; i++)
        if (!strcmp(m->names[i], name)) return 1;
    return 0;
}

/* 0 when dir is empty or a report directory with nothing but the files its manifest lists (all
 * regular files); else -1 with e naming what = the -o argument and the first stranger. */
static int check_report_dir(const char *dir, const char *what, sl_err *e) {
    manifest m;
    manifest_read(dir, &m);
    DIR *d = opendir(dir);
    if (!d) {
        manifest_free(&m);
        return sl_fail(e, "report: -o %s: %s", what, strerror(errno));
    }
    struct dirent *de;
    char stranger[300] = "";
    int any = 0;
    while ((de = readdir(d)) && !stranger[0]) {
        if (!strcmp(de->d_name, ".") || !strcmp(de->d_name, "..")) continue;
        any = 1;
        char p[4400];
        snprintf(p, sizeof p, "%s/%s", dir, de->d_name);
        struct stat st;
        if (!m.found || !is_ours(&m, de->d_name) || lstat(p, &st) != 0 || !S_ISREG(st.st_mode))
            snprintf(stranger, sizeof stranger, "%.255s", de->d_name);
    }
    closedir(d);
    int found = m.found;
    manifest_free(&m);
    if (any && !found)
        return sl_fail(e,
                       "report: -o %s: exists and is not a report directory (no %s in it): "
                       "nothing in it is touched; choose a new or empty directory",
                       what, SL_REPORT_MANIFEST);
    if (stranger[0])
        return sl_fail(e,
                       "report: -o %s: holds %s, which this command did not write: nothing in it "
                       "is touched; move it away or choose another directory",
                       what, stranger);
    return 0;
}

/* Removes a report directory: the files its manifest lists, the manifest, then the directory.
 * Anything else stays (and so does the directory, with a note). */
static void remove_report_dir(const char *dir, int noisy) {
    if (!dir) return; /* callers pass a path; -O1's inlining cannot see that (format-truncation) */
    manifest m;
    manifest_read(dir, &m);
    DIR *d = opendir(dir);
    if (d) {
        struct dirent *de;
        char p[4400];
        while ((de = readdir(d))) {
            if (!is_ours(&m, de->d_name)) continue;
            snprintf(p, sizeof p, "%s/%s", dir, de->d_name);
            struct stat st;
            if (strcmp(de->d_name, SL_REPORT_MANIFEST) && lstat(p, &st) == 0 &&
                S_ISREG(st.st_mode)) {
                unlink(p);
                sl_kill_point("report: removing the old report's files");
            }
        }
        closedir(d);
    }
    manifest_free(&m);
    char p[4400];
    snprintf(p, sizeof p, "%s/%s", dir, SL_REPORT_MANIFEST); /* last: it says what is ours */
    unlink(p);
    if (rmdir(dir) != 0 && errno != ENOENT && noisy)
        sl_note("report: %s holds files this command did not write: kept", dir);
}

/* -------------------------------------------------------------- links (fallback) */

static const char *base_name(const char *path) {
    const char *b = strrchr(path, '/');
    return b ? b + 1 : path;
}

/* DIR -> DIR.report-XXXXXX (a plain name beside it): a link this command made. Its target's
 * path (beside DIR) in out. */
static int own_link(const char *out_dir, char *out, size_t n) {
    char t[512];
    ssize_t len = readlink(out_dir, t, sizeof t - 1);
    if (len <= 0) return 0;
    t[len] = 0;
    const char *b = base_name(out_dir);
    size_t bl = strlen(b);
    if (strchr(t, '/') || strncmp(t, b, bl) || strncmp(t + bl, ".report-", 8) ||
        strlen(t) != bl + 8 + 6)
        return 0;
    char parent[4096];
    sl_dirname(out_dir, parent, sizeof parent);
    snprintf(out, n, "%s/%s", parent, t);
    return 1;
}

/* A new link to target (a plain name beside DIR) under an unpredictable name in ln. */
static int link_make(const char *out_dir, const char *target, char *ln, size_t n, sl_err *e) {
    for (int attempt = 0;; attempt++) {
        sl_temp_name(out_dir, ln, n); /* removed by the signal cleanup if left */
        if (symlink(target, ln) == 0) break;
        if (errno != EEXIST || attempt == 15)
            return sl_fail(e, "report: -o %s: cannot create a link: %s", out_dir, strerror(errno));
    }
    sl_kill_point("report: new link created");
    return 0;
}

/* Puts the link ln in place of DIR (a link, or nothing): one rename. */
static int link_put(const char *out_dir, const char *ln, sl_err *e) {
    if (rename(ln, out_dir) != 0) {
        int err = errno;
        unlink(ln);
        return sl_fail(e, "report: -o %s: cannot rename the new link into place: %s", out_dir,
                       strerror(err));
    }
    return 0;
}

static int link_install(const char *out_dir, const char *target, sl_err *e) {
    char ln[4400];
    if (link_make(out_dir, target, ln, sizeof ln, e)) return -1;
    return link_put(out_dir, ln, e);
}

/* ------------------------------------------------------------------------ API */

int sl_report_dir_check(const char *out_dir, sl_err *e) {
    struct stat st;
    if (lstat(out_dir, &st) != 0) return 0; /* new */
    if (S_ISLNK(st.st_mode)) {
        char target[4400];
        if (own_link(out_dir, target, sizeof target) && lstat(target, &st) == 0 &&
            S_ISDIR(st.st_mode))
            return check_report_dir(target, out_dir, e);
        return sl_fail(e, "report: -o %s: is a symbolic link (neither followed nor replaced)",
                       out_dir);
    }
    if (!S_ISDIR(st.st_mode))
        return sl_fail(e, "report: -o %s: exists and is not a directory", out_dir);
    return check_report_dir(out_dir, out_dir, e);
}

int sl_report_dir_begin(sl_report_dir *d, const char *out_dir, sl_err *e) {
    memset(d, 0, sizeof *d);
    if (strlen(out_dir) + 64 >= sizeof d->out_dir)
        return sl_fail(e, "report: -o %s: path too long", out_dir);
    snprintf(d->out_dir, sizeof d->out_dir, "%s", out_dir);
    if (sl_make_parent_dirs(out_dir, e)) return -1;
    sl_signals_hold(&d->hold);
    d->held = 1;
    /* an unpredictable name of our own (mkdtemp: created 0700, then opened up as the umask
     * allows), never an existing directory or link */
    snprintf(d->tmpdir, sizeof d->tmpdir, "%s.report-XXXXXX", out_dir);
    if (!mkdtemp(d->tmpdir)) {
        int err = errno;
        d->tmpdir[0] = 0;
        sl_signals_release(&d->hold);
        d->held = 0;
        return sl_fail(e, "report: -o %s: cannot create a temporary directory: %s", out_dir,
                       strerror(err));
    }
    mode_t um = umask(022);
    umask(um);
    chmod(d->tmpdir, 0777 & ~um);
    return 0;
}

const char *sl_report_dir_file(sl_report_dir *d, const char *name, char *path, size_t n,
                               sl_err *e) {
    if (!name[0] || name[0] == '.' || strchr(name, '/') || strlen(name) >= 64 ||
        d->n >= SL_REPORT_MAX_FILES) {
        sl_fail(e, "report: cannot add '%s' to the report directory", name);
        return NULL;
    }
    for (int i = 0; i < d->n; i++)
        if (!strcmp(d->names[i], name)) goto have;
    snprintf(d->names[d->n++], 64, "%s", name);
have:
    snprintf(path, n, "%s/%s", d->tmpdir, name);
    return path;
}

static void release(sl_report_dir *d) {
    if (d->held) sl_signals_release(&d->hold);
    d->held = 0;
}

void sl_report_dir_abort(sl_report_dir *d) {
    if (d->tmpdir[0]) {
        /* only the names recorded (the manifest may not be written yet) */
        char p[4400];
        for (int i = 0; i < d->n; i++) {
            snprintf(p, sizeof p, "%s/%s", d->tmpdir, d->names[i]);
            unlink(p);
        }
        snprintf(p, sizeof p, "%s/%s", d->tmpdir, SL_REPORT_MANIFEST);
        unlink(p);
        rmdir(d->tmpdir);
        d->tmpdir[0] = 0;
    }
    release(d);
}

/* DIR is missing: is RENAME_EXCHANGE available here? Tried on a scratch directory of our own
 * (the answer decides between a real directory and the link fallback for all later swaps). */
static int exchange_works(sl_report_dir *d, sl_err *e) {
    char probe[4200];
    snprintf(probe, sizeof probe, "%s.report-XXXXXX", d->out_dir);
    if (!mkdtemp(probe))
        return sl_fail(e, "report: -o %s: cannot create a directory: %s", d->out_dir,
                       strerror(errno));
    int ok = sl_dir_exchange(d->tmpdir, probe) == 0, err = errno;
    if (ok) {
        /* the names swapped: the report is under probe's name, the empty one under ours */
        rmdir(d->tmpdir);
        snprintf(d->tmpdir, sizeof d->tmpdir, "%s", probe);
        return 1;
    }
    rmdir(probe);
    if (sl_exchange_unsupported(err)) return 0;
    return sl_fail(e, "report: -o %s: cannot rename: %s", d->out_dir, strerror(err));
}

static int swap_in(sl_report_dir *d, sl_err *e) {
    const char *out = d->out_dir;
    struct stat st;
    if (lstat(out, &st) != 0) {
        int ex = exchange_works(d, e);
        if (ex < 0) return -1;
        if (ex) {
            sl_kill_point("report: before the rename into place");
            if (sl_rename_noreplace(d->tmpdir, out) != 0)
                return sl_fail(e, "report: -o %s: cannot rename %s into place: %s", out, d->tmpdir,
                               strerror(errno));
            d->tmpdir[0] = 0;
            return 0;
        }
        if (link_install(out, base_name(d->tmpdir), e)) return -1;
        d->tmpdir[0] = 0;
        return 0;
    }
    if (S_ISLNK(st.st_mode)) { /* ours (checked): one rename of a new link */
        char old[4400];
        if (!own_link(out, old, sizeof old))
            return sl_fail(e, "report: -o %s: is a symbolic link (neither followed nor replaced)",
                           out);
        if (link_install(out, base_name(d->tmpdir), e)) return -1;
        d->tmpdir[0] = 0;
        sl_kill_point("report: link swapped");
        remove_report_dir(old, 1);
        return 0;
    }
    sl_kill_point("report: before the exchange");
    if (sl_dir_exchange(d->tmpdir, out) == 0) {
        /* one step: DIR is the new report, the old one is under the temporary name */
        sl_kill_point("report: exchanged");
        char old[4200];
        snprintf(old, sizeof old, "%s", d->tmpdir);
        d->tmpdir[0] = 0;
        remove_report_dir(old, 1);
        return 0;
    }
    if (!sl_exchange_unsupported(errno))
        return sl_fail(e, "report: -o %s: cannot swap in %s: %s", out, d->tmpdir, strerror(errno));
    /* No exchange here and a real directory from before: it becomes a link to the versioned
     * directory, once; the two renames below are the one window of this fallback. */
    char old[4200], ln[4400];
    if (link_make(out, base_name(d->tmpdir), ln, sizeof ln, e)) return -1;
    snprintf(old, sizeof old, "%s.report-XXXXXX", out);
    if (!mkdtemp(old)) {
        unlink(ln);
        return sl_fail(e, "report: -o %s: cannot create a directory: %s", out, strerror(errno));
    }
    if (rename(out, old) != 0) { /* over the empty directory just made */
        int err = errno;
        rmdir(old);
        unlink(ln);
        return sl_fail(e, "report: -o %s: cannot move the old report aside: %s", out,
                       strerror(err));
    }
    sl_kill_point("report: old directory moved aside (no exchange)");
    if (link_put(out, ln, e)) {
        rename(old, out); /* back: the old report stays */
        return -1;
    }
    d->tmpdir[0] = 0;
    remove_report_dir(old, 1);
    return 0;
}

int sl_report_dir_commit(sl_report_dir *d, sl_err *e) {
    char p[4400], parent[4096];
    snprintf(p, sizeof p, "%s/%s", d->tmpdir, SL_REPORT_MANIFEST);
    sl_atomic_file mf;
    if (sl_atomic_open(&mf, p, e)) goto fail;
    fprintf(mf.fp, "%s\n", MANIFEST_HEAD);
    for (int i = 0; i < d->n; i++)
        fprintf(mf.fp, "file %s\n", d->names[i]);
    if (sl_atomic_commit(&mf, e)) goto fail; /* fsynced, as every file of the report */
    sl_fsync_dir(d->tmpdir);
    sl_kill_point("report: complete in the temporary directory");
    /* the check again: DIR may have changed during the sweep */
    if (sl_report_dir_check(d->out_dir, e)) goto fail;
    if (swap_in(d, e)) goto fail;
    sl_dirname(d->out_dir, parent, sizeof parent);
    sl_fsync_dir(parent);
    release(d);
    return 0;
fail:
    sl_report_dir_abort(d);
    return -1;
}
