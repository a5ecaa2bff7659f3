/* cmd_fit.c: `strandlight fit`: SRBF lobes for an environment map (envfit.h), written as the
 * lobes JSON of numerics.md sec. 4 with a "fit" record (map hash, settings, errors, time). */
#include "cli/cli.h"
#include "scene/env_lighting.h"
#include "lighting/envfit.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void usage(FILE *fp) {
    fprintf(
        fp,
        "usage: strandlight fit MAP.exr|MAP.hdr --lobes N|auto -o LOBES.json [options]\n\n"
        "Fits N spherical Gaussians (SRBF lobes, numerics.md sec. 4) to an environment map:\n"
        "greedy start on a coarse level, then bounded Levenberg-Marquardt over directions,\n"
        "bandwidths and non-negative rgb weights, coarse to fine on a solid-angle-weighted\n"
        "pyramid. Prints and records the solid-angle-weighted relative L2 error of the\n"
        "radiance (rel_l2) and of the map seen through a fiber-like lobe (lobe_conv_rel_l2).\n\n"
        "options:\n"
        "  --lobes N|auto          number of lobes (1..%d), or grow until --target-error\n"
        "  --target-error E        auto mode: stop when rel_l2 <= E (default 0.1)\n"
        "  --max-lobes M           auto mode: at most M lobes (default 256)\n"
        "  -o, --output FILE       lobes JSON to write (atomically)\n"
        "  --preview FILE.png      original | reconstruction | |error| side by side\n"
        "  --exposure STOPS        preview exposure (default 0)\n"
        "  --lambda-min L          narrowest lobe (default: one pixel, pi / height)\n"
        "  --lambda-max L          broadest lobe (default 1.0)\n"
        "  --effort X              iteration budget multiplier (default 1)\n"
        "  --threads T             worker threads (default 2; results do not depend on it)\n"
        "  --conv-lambda-deg D     width of the lobe for lobe_conv_rel_l2 (default 10)\n"
        "  --clamp-nonfinite       replace NaN/Inf pixels by 0 instead of failing\n"
        "  -v, --verbose           per-level iterations, errors and times on stderr\n"
        "  -q, --quiet             no summary line on stdout\n",
        SL_FIT_LOBES_MAX);
}

/* A lobe count for fit: 1..SL_FIT_LOBES_MAX, and above it a refusal that says why. */
static int fit_lobes_arg(const char *opt, const char *v, long *out) {
    if (cli_int("fit", opt, v, 1, 1000000000L, out)) return -1;
    if (*out > SL_FIT_LOBES_MAX) {
        cli_usage_error("fit",
                        "%s %ld: at most %d (the fit's cost grows about as n^3: 256 lobes take "
                        "~3 minutes on 2 cores, %d about 25; the frame also draws one shadow map "
                        "per lobe)",
                        opt, *out, SL_FIT_LOBES_MAX, SL_FIT_LOBES_MAX);
        return -1;
    }
    return 0;
}

int cmd_fit(int argc, char **argv) {
    const char *map_path = NULL, *out_path = NULL, *preview = NULL, *v;
    sl_envfit_settings s;
    sl_envfit_default_settings(&s);
    s.progress = 1;
    int clamp = 0, quiet = sl_is_quiet(), have_lobes = 0, missing = 0;
    double exposure = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        long lv;
        double dv;
        if (cli_is_help(a)) {
            usage(stdout);
            return 0;
        } else if (cli_opt(argc, argv, &i, "--lobes", &v, &missing)) {
            if (missing) return 2;
            if (strcmp(v, "auto") == 0)
                s.lobes = 0;
            else if (fit_lobes_arg("--lobes", v, &lv))
                return 2;
            else
                s.lobes = (int)lv;
            have_lobes = 1;
        } else if (cli_opt(argc, argv, &i, "--target-error", &v, &missing)) {
            if (missing || cli_double("fit", "--target-error", v, &dv)) return 2;
            if (!(dv > 0)) return cli_usage_error("fit", "--target-error: must be > 0");
            s.target_error = dv;
        } else if (cli_opt(argc, argv, &i, "--max-lobes", &v, &missing)) {
            if (missing || fit_lobes_arg("--max-lobes", v, &lv)) return 2;
            s.max_lobes = (int)lv;
        } else if (cli_opt(argc, argv, &i, "-o", &v, &missing) ||
                   cli_opt(argc, argv, &i, "--output", &v, &missing)) {
            if (missing) return 2;
            out_path = v;
        } else if (cli_opt(argc, argv, &i, "--preview", &v, &missing)) {
            if (missing) return 2;
            preview = v;
        } else if (cli_opt(argc, argv, &i, "--exposure", &v, &missing)) {
            if (missing || cli_double("fit", "--exposure", v, &exposure)) return 2;
        } else if (cli_opt(argc, argv, &i, "--lambda-min", &v, &missing)) {
            if (missing || cli_double("fit", "--lambda-min", v, &dv)) return 2;
            if (!(dv > 0)) return cli_usage_error("fit", "--lambda-min: must be > 0");
            s.lambda_min = dv;
        } else if (cli_opt(argc, argv, &i, "--lambda-max", &v, &missing)) {
            if (missing || cli_double("fit", "--lambda-max", v, &dv)) return 2;
            if (!(dv > 0) || dv > 100)
                return cli_usage_error("fit", "--lambda-max: must be in (0, 100]");
            s.lambda_max = dv;
        } else if (cli_opt(argc, argv, &i, "--effort", &v, &missing)) {
            if (missing || cli_double("fit", "--effort", v, &dv)) return 2;
            if (!(dv > 0) || dv > 10000)
                return cli_usage_error("fit", "--effort: must be in (0, 10000]");
            s.effort = dv;
        } else if (cli_opt(argc, argv, &i, "--threads", &v, &missing)) {
            if (missing || cli_int("fit", "--threads", v, 1, 16, &lv)) return 2;
            s.threads = (int)lv;
        } else if (cli_opt(argc, argv, &i, "--conv-lambda-deg", &v, &missing)) {
            if (missing || cli_double("fit", "--conv-lambda-deg", v, &dv)) return 2;
            if (!(dv > 0) || dv > 180)
                return cli_usage_error("fit", "--conv-lambda-deg: must be in (0, 180]");
            s.conv_lambda = dv * M_PI / 180;
        } else if (strcmp(a, "--clamp-nonfinite") == 0) {
            clamp = 1;
        } else if (strcmp(a, "-v") == 0 || strcmp(a, "--verbose") == 0) {
            s.verbose = 1;
        } else if (strcmp(a, "-q") == 0 || strcmp(a, "--quiet") == 0) {
            quiet = 1;
        } else if (a[0] == '-' && a[1]) {
            return cli_usage_error("fit", "unknown option '%s'", a);
        } else if (!map_path) {
            map_path = a;
        } else {
            return cli_usage_error("fit", "unexpected argument '%s'", a);
        }
    }
    if (!map_path) return cli_usage_error("fit", "missing the environment map");
    if (!have_lobes) return cli_usage_error("fit", "missing --lobes N|auto");
    if (!out_path) return cli_usage_error("fit", "missing -o LOBES.json");
    if (s.lambda_min > 0 && s.lambda_min > s.lambda_max)
        return cli_usage_error("fit", "--lambda-min %g exceeds --lambda-max %g", s.lambda_min,
                               s.lambda_max);

    sl_err e = {{0}};
    sl_envmap map;
    if (sl_envmap_load(map_path, clamp, &map, &e)) {
        fprintf(stderr, "strandlight: %s\n", e.msg);
        return 1;
    }
    sl_lobes lobes;
    sl_envfit_report rep;
    int rc = 1;
    if (sl_envfit(&map, &s, &lobes, &rep, &e)) goto fail;
    lobes.fit_json = sl_envfit_record(map_path, &map, &s, clamp, &rep, lobes.count);
    if (sl_lobes_save(out_path, &lobes, &e)) goto fail_lobes;
    if (preview && sl_envfit_preview(preview, &map, lobes.lobe, lobes.count, exposure, &e))
        goto fail_lobes;
    if (!quiet)
        printf("%s: %d lobes, rel_l2 %.4g, lobe_conv_rel_l2 %.4g (%.0f deg lobe), %.2f s, %d LM "
               "iterations on %d levels -> %s\n",
               map_path, lobes.count, rep.rel_l2, rep.lobe_conv_rel_l2, s.conv_lambda * 180 / M_PI,
               rep.time_s, rep.iterations, rep.levels, out_path);
    rc = 0;
fail_lobes:
    sl_lobes_free(&lobes);
fail:
    if (rc) fprintf(stderr, "strandlight: %s\n", e.msg);
    sl_envmap_free(&map);
    return rc;
}
