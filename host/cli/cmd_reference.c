/* cmd_reference.c: `strandlight reference SCENE.json -o REF.exr --lights N [--fragments]`: the
 * brute-force reference render (host/verify/reference/reference.h, docs/reference.md), cached by content and
 * settings, with its own convergence (N vs 2N lights; pixel mode with another jitter seed,
 * fragment mode on the same fragments) on stderr and in REF.exr.json. */
#include "cli/cli.h"
#include "verify/reference/reference.h"
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *usage_text =
    "usage: strandlight reference SCENE.json [-o REF.exr] [options]\n"
    "\n"
    "Brute-force reference render of SCENE.json (docs/reference.md): environment.file cut into\n"
    "N directional lights (median cut, as `strandlight sample`), the exact double-precision\n"
    "fiber function per light, shadow rays through the actual fibers (Intel Embree), dual\n"
    "scattering along the traced shadow rays. Same camera and pixels as `strandlight render`.\n"
    "Writes REF.exr (float: R G B A Z, MS.R/G/B = multiple scattering, R_mode.*, TT.*, TRT.* =\n"
    "single scattering by mode; premultiplied, A = coverage) and REF.exr.json (settings, time,\n"
    "cache key, convergence). A second run with the same inputs and settings reuses REF.exr.\n"
    "--fragments: shade exactly the fast path's K-buffer entries (the view pass of `render`,\n"
    "quality.oit_layers entries per pixel) and composite them with its weights, so coverage,\n"
    "alpha and depth equal the fast path's and only the light cut is left as the reference's\n"
    "own error (convergence: the same fragments at N vs 2N lights).\n"
    "  -o, --output FILE   EXR output (default out/reference.exr)\n"
    "  --lights N          directional lights (default 256)\n"
    "  --fragments         fragment mode (above; --aa, --seed, --no-light-split unused)\n"
    "  --aa K              K x K jittered camera rays per pixel (default 2)\n"
    "  --seed S            jitter seed (default 1)\n"
    "  --no-light-split    every camera ray shades every light (default: the K x K rays of a\n"
    "                      pixel share the N lights, one subset each, so aa costs little)\n"
    "  --threads T         worker threads (default: all CPUs; the image does not depend on it)\n"
    "  --ms on|off|auto    multiple scattering (default: the scene's quality.multiple_scattering;\n"
    "                      auto = on for model marschner)\n"
    "  --width W, --height H   image size (default: the scene's)\n"
    "  --no-convergence    skip the 2N-light render that measures the N image's own error\n"
    "  --force             render even if a cached result exists\n"
    "  --clamp-nonfinite   replace NaN/Inf pixels of the environment map by 0 (else an error)\n";

int cmd_reference(int argc, char **argv) {
    const char *scene_path = NULL, *out = "out/reference.exr", *v, *ms = NULL;
    sl_reference_settings set;
    sl_reference_settings_default(&set);
    int missing = 0, conv = 1, force = 0;
    long n;
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(usage_text, stdout);
            return 0;
        } else if (cli_opt(argc, argv, &i, "-o", &out, &missing) ||
                   cli_opt(argc, argv, &i, "--output", &out, &missing)) {
            if (missing) return 2;
        } else if (cli_opt(argc, argv, &i, "--ms", &ms, &missing)) {
            if (missing) return 2;
            if (strcmp(ms, "on") == 0)
                set.ms = 1;
            else if (strcmp(ms, "off") == 0)
                set.ms = 0;
            else if (strcmp(ms, "auto") == 0)
                set.ms = -1;
            else
                return cli_usage_error("reference", "--ms: expected on, off or auto");
        } else if (cli_opt(argc, argv, &i, "--lights", &v, &missing)) {
            if (missing || cli_int("reference", "--lights", v, 1, 1000000, &n)) return 2;
            set.lights = (int)n;
        } else if (cli_opt(argc, argv, &i, "--aa", &v, &missing)) {
            if (missing || cli_int("reference", "--aa", v, 1, 64, &n)) return 2;
            set.aa = (int)n;
        } else if (cli_opt(argc, argv, &i, "--seed", &v, &missing)) {
            if (missing || cli_int("reference", "--seed", v, 0, 0x7fffffffL, &n)) return 2;
            set.seed = (uint64_t)n;
        } else if (cli_opt(argc, argv, &i, "--threads", &v, &missing)) {
            if (missing || cli_int("reference", "--threads", v, 1, 256, &n)) return 2;
            set.threads = (int)n;
        } else if (cli_opt(argc, argv, &i, "--width", &v, &missing)) {
            if (missing || cli_int("reference", "--width", v, 1, 16384, &n)) return 2;
            set.width = (int)n;
        } else if (cli_opt(argc, argv, &i, "--height", &v, &missing)) {
            if (missing || cli_int("reference", "--height", v, 1, 16384, &n)) return 2;
            set.height = (int)n;
        } else if (strcmp(argv[i], "--no-convergence") == 0) {
            conv = 0;
        } else if (strcmp(argv[i], "--force") == 0) {
            force = 1;
        } else if (strcmp(argv[i], "--clamp-nonfinite") == 0) {
            set.clamp_nonfinite = 1;
        } else if (strcmp(argv[i], "--fragments") == 0) {
            set.fragments = 1;
        } else if (strcmp(argv[i], "--no-light-split") == 0) {
            set.light_split = 0;
        } else if (argv[i][0] == '-') {
            return cli_usage_error("reference", "unknown option %s", argv[i]);
        } else if (!scene_path) {
            scene_path = argv[i];
        } else {
            return cli_usage_error("reference", "more than one scene given");
        }
    }
    if (!scene_path) return cli_usage_error("reference", "no scene file given");
    if (!out[0]) return cli_usage_error("reference", "-o: empty output path");

    sl_err e = {{0}};
    sl_scene *s = sl_malloc(sizeof *s);
    int rc = 1;
    if (sl_scene_load(scene_path, s, &e)) goto done;
    if (force) {
        char json[4200];
        snprintf(json, sizeof json, "%s.json", out);
        unlink(json); /* a missing record means no cache hit */
    }
    sl_reference_result r;
    if (sl_reference_run(s, &set, out, conv, &r, &e)) goto done;
    if (set.fragments)
        sl_note("reference: %s%s (fragments: %.0f entries, K %d; %d lights, %s multiple "
                "scattering, %.2f s%s)",
                r.cached ? "cached " : "", out, r.entries, r.oit_k, r.lights,
                r.ms ? "with" : "without", r.time_s, r.cached ? " when rendered" : "");
    else
        sl_note("reference: %s%s (%d lights, aa %d, %s multiple scattering, %.2f s%s)",
                r.cached ? "cached " : "", out, r.lights, set.aa, r.ms ? "with" : "without",
                r.time_s, r.cached ? " when rendered" : "");
    if (r.has_convergence)
        sl_note("reference: convergence: %d vs %d lights: rel RMSE %.4g, p99 rel err %.4g, "
                "4x4 blocks %.4g (2N render%s: %.2f s)",
                set.lights, 2 * set.lights, r.conv_rel_rmse, r.conv_p99, r.conv_rel_rmse_4x4,
                set.fragments ? " of the same fragments" : " with seed + 1", r.time_2n_s);
    rc = 0;
done:
    if (rc) fprintf(stderr, "strandlight: %s\n", e.msg);
    free(s);
    return rc;
}
