/* cmd_report.c: `strandlight report`. Forms:
 *   report --kernel srbf [options]   error against run time of the SRBF closed forms (issue 5,
 *                                    host/verify/report/report_srbf.c)
 *   report SCENE.json [options]      reference against the fast pipeline over a sweep of
 *                                    settings (issue 10, host/verify/report/report_scene.c)
 * Arguments are parsed in two steps: the form is decided first (--kernel K, or one positional
 * scene file), then the form's own options, so a scene form can be added beside --kernel. */
#include "cli/cli.h"
#include "base/common.h"
#include "verify/report/report_scene.h"
#include "verify/report/report_srbf.h"

#include <stdio.h>
#include <string.h>

static void help(void) {
    printf(
        "usage: strandlight report --kernel srbf [--n N] [--exact FILE.csv] [--write-exact "
        "FILE.csv]\n"
        "                          [--csv OUT.csv] [--svg OUT.svg] [--device SPEC|none] "
        "[--min-time S]\n"
        "\n"
        "--kernel srbf: the SRBF closed forms (--method xu with m = 1..8, --method fast) on the\n"
        "C path and on OpenCL against the exact reference, over the fixed seeded stiff sample\n"
        "of host/verify/report/srbf_sample.c (docs/srbf.md): median, 95th percentile and maximum "
        "of the\n"
        "error of numerics.md sec. 5 and lobe evaluations per second, as a Markdown table on\n"
        "stdout, a CSV and an SVG plot of error against time.\n"
        "  --n N              sample size (default 150; any prefix of the sequence)\n"
        "  --exact FILE       exact values of the sample from FILE (written by --write-exact)\n"
        "                     instead of computing them (minutes: eccentric rows take ~5 s)\n"
        "  --write-exact FILE save the exact values computed (or read) here\n"
        "  --csv, --svg       outputs (written atomically)\n"
        "  --device SPEC      OpenCL device for the opencl rows (default: any); none: C only\n"
        "  --min-time S       time each method for at least S seconds (default 0.3)\n"
        "\n"
        "\n"
        "usage: strandlight report SCENE.json [--quick] [--tiny] [-o DIR] [--lights N] [--aa K]\n"
        "                          [--frag-lights N] [--width W] [--device SPEC|none] "
        "[--threads T]\n"
        "\n"
        "SCENE.json: renders two brute-force references once (cached in DIR/../.reference/): the\n"
        "pixel reference (camera rays) and the fragment reference (the fast path's own K-buffer\n"
        "entries shaded by the reference: shading error only), then the fast pipeline over a\n"
        "sweep of settings (lobes, layers K, m, kappa, voxels, multiple scattering, backend\n"
        "c/opencl), each measured against both, and writes DIR (default report/NAME):\n"
        "results.csv (rel_rmse...: pixel reference, rel_rmse_frag...: fragment reference),\n"
        "report.md (table, Pareto fronts, speed-ups, the target) and error_vs_time.svg\n"
        "(docs/results.md).\n"
        "  --quick            small sweep, 80 px wide, pixel reference 256 lights aa 8, fragment\n"
        "                     reference 32 lights (minutes)\n"
        "  --tiny             48 px wide, references 8 lights (pixel: aa 2), smallest sweep (CI)\n"
        "  (neither)          full sweep, 128 px wide, pixel reference 512 lights aa 12,\n"
        "                     fragment reference 96 lights (~15 min for data/default.json)\n"
        "  -o DIR             report directory (replaced atomically)\n"
        "  --lights N, --aa K pixel reference settings (default by mode; the K x K rays of a\n"
        "                     pixel share the N lights)\n"
        "  --frag-lights N    fragment reference lights (default by mode)\n"
        "  --width W          image width (height keeps the scene's aspect)\n"
        "  --device SPEC      OpenCL device for the opencl rows (default: opencl); none: C only\n"
        "  --threads T        threads (default: every CPU)\n"
        "  --reference R      pixel reference: auto (default: the path tracer for deon and\n"
        "                     chiang, the direct-light reference for marschner), path, direct\n"
        "  --spp N            path-traced reference samples per pixel (default 256; quick 64;\n"
        "                     tiny 8)\n");
}

static int report_srbf_args(int argc, char **argv) {
    sl_report_srbf_opts o;
    memset(&o, 0, sizeof o);
    for (int i = 1; i < argc; i++) {
        int missing = 0;
        const char *v;
        if (cli_opt(argc, argv, &i, "--kernel", &v, &missing))
            continue; /* checked by the caller */
        else if (cli_opt(argc, argv, &i, "--n", &v, &missing)) {
            long n;
            if (cli_int("report", "--n", v, 5, 100000, &n)) return 2;
            o.n = (int)n;
        } else if (cli_opt(argc, argv, &i, "--exact", &v, &missing))
            o.exact_in = v;
        else if (cli_opt(argc, argv, &i, "--write-exact", &v, &missing))
            o.exact_out = v;
        else if (cli_opt(argc, argv, &i, "--csv", &v, &missing))
            o.csv = v;
        else if (cli_opt(argc, argv, &i, "--svg", &v, &missing))
            o.svg = v;
        else if (cli_opt(argc, argv, &i, "--device", &v, &missing))
            o.device = v;
        else if (cli_opt(argc, argv, &i, "--min-time", &v, &missing)) {
            if (cli_double("report", "--min-time", v, &o.min_time_s)) return 2;
            if (!(o.min_time_s > 0.0 && o.min_time_s <= 60.0))
                return cli_usage_error("report", "--min-time: expected 0 < S <= 60, got '%s'", v);
        } else
            return cli_usage_error("report", "--kernel srbf: unexpected argument '%s'", argv[i]);
        if (missing) return 2;
    }
    sl_err e = {{0}};
    if (sl_report_srbf(&o, &e)) {
        fprintf(stderr, "strandlight: %s\n", e.msg);
        return 1;
    }
    return 0;
}

static int report_scene_args(int argc, char **argv, const char *scene) {
    sl_report_scene_opts o;
    memset(&o, 0, sizeof o);
    o.scene = scene;
    for (int i = 1; i < argc; i++) {
        int missing = 0;
        const char *v;
        long n;
        if (argv[i] == scene)
            continue;
        else if (strcmp(argv[i], "--quick") == 0)
            o.quick = 1;
        else if (strcmp(argv[i], "--tiny") == 0)
            o.tiny = 1;
        else if (cli_opt(argc, argv, &i, "-o", &v, &missing))
            o.out_dir = v;
        else if (cli_opt(argc, argv, &i, "--device", &v, &missing))
            o.opencl = v;
        else if (cli_opt(argc, argv, &i, "--lights", &v, &missing)) {
            if (cli_int("report", "--lights", v, 1, 100000, &n)) return 2;
            o.lights = (int)n;
        } else if (cli_opt(argc, argv, &i, "--frag-lights", &v, &missing)) {
            if (cli_int("report", "--frag-lights", v, 1, 100000, &n)) return 2;
            o.frag_lights = (int)n;
        } else if (cli_opt(argc, argv, &i, "--aa", &v, &missing)) {
            if (cli_int("report", "--aa", v, 1, 16, &n)) return 2;
            o.aa = (int)n;
        } else if (cli_opt(argc, argv, &i, "--width", &v, &missing)) {
            if (cli_int("report", "--width", v, 4, 16384, &n)) return 2;
            o.width = (int)n;
        } else if (cli_opt(argc, argv, &i, "--threads", &v, &missing)) {
            if (cli_int("report", "--threads", v, 1, 256, &n)) return 2;
            o.threads = (int)n;
        } else if (cli_opt(argc, argv, &i, "--reference", &v, &missing)) {
            if (missing) return 2;
            if (strcmp(v, "auto") == 0)
                o.reference = 0;
            else if (strcmp(v, "path") == 0)
                o.reference = 1;
            else if (strcmp(v, "direct") == 0)
                o.reference = 2;
            else
                return cli_usage_error("report",
                                       "--reference: expected auto, path or direct, got \"%s\"", v);
        } else if (cli_opt(argc, argv, &i, "--spp", &v, &missing)) {
            if (cli_int("report", "--spp", v, 1, 1000000, &n)) return 2;
            o.spp = (int)n;
        } else
            return cli_usage_error("report", "SCENE.json: unexpected argument '%s'", argv[i]);
        if (missing) return 2;
    }
    sl_err e = {{0}};
    if (sl_report_scene(&o, &e)) {
        fprintf(stderr, "strandlight: %s\n", e.msg);
        return 1;
    }
    return 0;
}

int cmd_report(int argc, char **argv) {
    const char *kernel = NULL, *scene = NULL;
    for (int i = 1; i < argc; i++) {
        int missing = 0;
        const char *v;
        if (cli_is_help(argv[i])) {
            help();
            return 0;
        }
        if (cli_opt(argc, argv, &i, "--kernel", &v, &missing)) {
            if (kernel) return cli_usage_error("report", "--kernel given twice");
            kernel = v;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            /* a form's option with a value: skip the value (checked by the form's parser);
             * the scene form's flags take none */
            if (strcmp(argv[i], "--quick") && strcmp(argv[i], "--tiny") && i + 1 < argc &&
                !strchr(argv[i], '=') && argv[i + 1][0] != '-')
                i++;
        } else if (!scene)
            scene = argv[i];
        else
            return cli_usage_error("report", "unexpected argument '%s'", argv[i]);
        if (missing) return 2;
    }
    if (kernel && scene)
        return cli_usage_error("report", "give either --kernel K or a scene file, not both");
    if (kernel) {
        if (strcmp(kernel, "srbf") != 0)
            return cli_usage_error("report", "--kernel: unknown kernel '%s' (expected srbf)",
                                   kernel);
        return report_srbf_args(argc, argv);
    }
    if (scene) return report_scene_args(argc, argv, scene);
    return cli_usage_error("report", "expected --kernel srbf or SCENE.json");
}
