/* report_dir.h: the report directory of `report -o DIR` (issue 21, docs/robustness.md sec. 5).
 *
 * The report is written into a fresh directory beside DIR (mkdtemp: DIR.report-XXXXXX), with a
 * manifest (.strandlight-report) that lists every file the report wrote, and is then swapped in:
 *   - DIR missing: renamed to DIR (RENAME_NOREPLACE);
 *   - DIR a report directory: renameat2(RENAME_EXCHANGE) swaps the two in one step, then the old
 *     report (now under the temporary name) is removed: only the files its manifest lists;
 *   - where the filesystem has no RENAME_EXCHANGE (NFS, some FUSE), DIR is a symbolic link to a
 *     versioned directory DIR.report-XXXXXX beside it, and a swap is one rename of a new link
 *     over it. A real directory from before becomes such a link once: that one swap is two
 *     renames (the only moment a SIGKILL can leave DIR missing, both reports then complete
 *     beside it).
 * A kill at any other moment leaves DIR holding the old report or the new one, never neither,
 * and nothing deletes a file the report did not write: an existing DIR that holds anything its
 * manifest does not list is refused before the work (sl_report_dir_check) and again at the swap.
 * Between begin and commit/abort SIGINT, SIGTERM and SIGHUP are held off: writing the files takes
 * well under a second, and a ^C then cannot leave a half-written temporary directory. */
#ifndef SL_REPORT_DIR_H
#define SL_REPORT_DIR_H

#include "base/common.h"
#include "base/output_set.h"

#define SL_REPORT_MANIFEST ".strandlight-report"
#define SL_REPORT_MAX_FILES 128

typedef struct {
    char out_dir[4096];
    char tmpdir[4200];
    char names[SL_REPORT_MAX_FILES][64]; /* files written into tmpdir, for the manifest */
    int n;
    sl_signal_hold hold;
    int held;
} sl_report_dir;

/* An existing DIR must be empty, a report directory (its manifest; nothing it does not list) or
 * a link this command made (to DIR.report-* beside it, itself a report directory); anything else
 * is refused with one line, nothing touched. A missing DIR is fine. */
int sl_report_dir_check(const char *out_dir, sl_err *e);

/* Creates the temporary directory (parents as needed) and holds the signals. */
int sl_report_dir_begin(sl_report_dir *d, const char *out_dir, sl_err *e);

/* The path of a report file in the temporary directory (name: a plain name), recorded for the
 * manifest; NULL with e set when the name is not plain or too many files. */
const char *sl_report_dir_file(sl_report_dir *d, const char *name, char *path, size_t n, sl_err *e);

/* Writes the manifest, flushes, swaps the report in (see above) and releases the signals. On
 * failure the temporary directory is removed and DIR is as it was. */
int sl_report_dir_commit(sl_report_dir *d, sl_err *e);

/* Removes the temporary directory (the files recorded) and releases the signals. */
void sl_report_dir_abort(sl_report_dir *d);

#endif
