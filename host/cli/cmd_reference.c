/* cmd_reference.c: `strandlight reference SCENE.json -o REF.exr --lights N [--fragments]`: the
 * brute-force reference render (host/verify/reference/reference.h, docs/reference.md), cached by
 * content and settings, with its own convergence (N vs 2N lights; pixel mode with another jitter
 * seed, fragment mode on the same fragments) on stderr and in REF.exr.json; `--path --spp N`: the
 * path tracer (host/verify/reference/reference_path.h), which a SIGINT stops without writing. */
#include "cli/cli.h"
#include "verify/reference/reference.h"
#include "verify/reference/reference_path.h"
#include "scene/scene.h"

#include <math.h>
#include <signal.h>

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
    "  --clamp-nonfinite   replace NaN/Inf pixels of the environment map by 0 (else an error)\n"
    "\n"
    "--path: the unbiased path tracer through the real fibers instead (every order of\n"
    "scattering; the map at full resolution, sampled by importance and combined with the\n"
    "fiber's own sampling by MIS; docs/reference.md \"Path tracer\"). Writes REF.exr (float:\n"
    "R G B A Z, direct.* = scattered once, indirect.* = more (also as MS.*), R_mode.*, TT.*,\n"
    "TRT.*, rest.* = by the first event's lobe) and REF.exr.json (spp, seed, wall and CPU time,\n"
    "the image's own noise from its even vs odd samples). Ctrl-C stops it and writes nothing.\n"
    "  --path              path tracer (not with --fragments, --lights, --aa, --ms,\n"
    "                      --no-light-split)\n"
    "  --spp N             samples per pixel (default 16; with --time: the most)\n"
    "  --time SECONDS      stop after the last whole sample pass that fits in the budget\n"
    "  --seed S            random streams (default 1); --width/--height/--threads as above\n";

static volatile sig_atomic_t interrupted;

static void on_sigint(int sig) {
    (void)sig;
    interrupted = 1;
}

/* The path tracer: SIGINT (handled from before the scene loads, see cmd_reference) sets a flag
 * the passes check, so an interrupted render returns before anything is written (outputs are
 * written to a temporary name and renamed, after the render: there is no partial EXR). */
static int run_path(const sl_scene *s, sl_path_settings *ps, const char *out, int force,
                    sl_err *e) {
    ps->cancel = &interrupted;
    sl_path_result r;
    memset(&r, 0, sizeof r);
    int rc = sl_path_run(s, ps, out, force, &r, e); /* the output was checked by cmd_reference */
    if (rc) return r.interrupted ? 130 : 1;
    char nz[64] = "n/a (fewer than 2 spp)";
    if (isfinite(r.noise))
        snprintf(nz, sizeof nz, "%.4g (4x4 %.4g, 8x8 %.4g)", r.noise, r.noise_4x4, r.noise_8x8);
    sl_note("reference: %s%s (path tracer: %d spp, seed %llu, %.2f s wall, %.2f s CPU%s; "
            "%.0f paths/s; noise %s)",
            r.cached ? "cached " : "", out, r.spp, (unsigned long long)ps->seed, r.wall_s, r.cpu_s,
            r.cached ? " when rendered" : "", r.paths_per_s, nz);
    return 0;
}

int cmd_reference(int argc, char **argv) {
    const char *scene_path = NULL, *out = "out/reference.exr", *v, *ms = NULL;
    sl_reference_settings set;
    sl_reference_settings_default(&set);
    int missing = 0, conv = 1, force = 0, path = 0, spp_given = 0, pixel_opt = 0;
    sl_path_settings ps;
    sl_path_settings_default(&ps);
    long n;
    double t;
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
            pixel_opt = 1;
        } else if (cli_opt(argc, argv, &i, "--lights", &v, &missing)) {
            if (missing || cli_int("reference", "--lights", v, 1, 1000000, &n)) return 2;
            set.lights = (int)n;
            pixel_opt = 1;
        } else if (cli_opt(argc, argv, &i, "--aa", &v, &missing)) {
            if (missing || cli_int("reference", "--aa", v, 1, 64, &n)) return 2;
            set.aa = (int)n;
            pixel_opt = 1;
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
        } else if (strcmp(argv[i], "--path") == 0) {
            path = 1;
        } else if (cli_opt(argc, argv, &i, "--spp", &v, &missing)) {
            if (missing || cli_int("reference", "--spp", v, 1, 1 << 24, &n)) return 2;
            ps.spp = (int)n;
            spp_given = 1;
        } else if (cli_opt(argc, argv, &i, "--time", &v, &missing)) {
            if (missing || cli_double("reference", "--time", v, &t)) return 2;
            if (!(t > 0) || !isfinite(t))
                return cli_usage_error("reference", "--time: expected seconds > 0");
            ps.time_s = t;
        } else if (strcmp(argv[i], "--fragments") == 0) {
            set.fragments = 1;
        } else if (strcmp(argv[i], "--no-light-split") == 0) {
            set.light_split = 0;
            pixel_opt = 1;
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
    if (path && set.fragments)
        return cli_usage_error("reference", "--path and --fragments exclude each other (the path "
                                            "tracer shoots its own camera rays)");
    if (path && pixel_opt)
        return cli_usage_error("reference", "--lights, --aa, --ms and --no-light-split are "
                                            "pixel-mode options; --path samples the map itself "
                                            "and every order of scattering");
    if (!path && (spp_given || ps.time_s > 0))
        return cli_usage_error("reference", "--spp and --time need --path");
    if (path && ps.time_s > 0 && !spp_given) ps.spp = 0; /* no sample limit */

    sl_err e = {{0}};
    struct sigaction sa, old;
    if (path) { /* from here on, so that a SIGINT while loading also ends with nothing written */
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_sigint;
        sigemptyset(&sa.sa_mask);
        interrupted = 0;
        sigaction(SIGINT, &sa, &old);
    }
    sl_scene *s = sl_malloc(sizeof *s);
    int rc = 1;
    if (sl_scene_load(scene_path, s, &e)) goto done;
    {
        /* before anything is removed or rendered: a writable output that is none of the inputs */
        const char *inputs[SL_SCENE_FILES];
        sl_scene_files(s, inputs);
        if (sl_output_precheck(out, "-o", &e) ||
            sl_output_not_input(out, "-o", inputs, SL_SCENE_FILES, &e))
            goto done;
    }
    if (force) {
        char json[4200];
        snprintf(json, sizeof json, "%s.json", out);
        unlink(json); /* a missing record means no cache hit */
    }
    if (path) {
        ps.seed = set.seed, ps.threads = set.threads, ps.width = set.width;
        ps.height = set.height, ps.clamp_nonfinite = set.clamp_nonfinite;
        rc = run_path(s, &ps, out, force, &e);
        goto done;
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
    if (path) sigaction(SIGINT, &old, NULL);
    if (rc) fprintf(stderr, "strandlight: %s\n", e.msg);
    (void)conv;
    free(s);
    return rc;
}
