/* cmd_report.c: `strandlight report`. Forms:
 *   report --kernel srbf [options]   error against run time of the SRBF closed forms (issue 5,
 *                                    host/report_srbf.c)
 *   report SCENE.json                (a later issue; a clear usage error until then)
 * Arguments are parsed in two steps: the form is decided first (--kernel K, or one positional
 * scene file), then the form's own options, so a scene form can be added beside --kernel. */
#include "cli.h"
#include "common.h"
#include "report_srbf.h"

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
        "of host/srbf_sample.c (docs/srbf.md): median, 95th percentile and maximum of the\n"
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
        "report SCENE.json (frame statistics of a scene) comes with a later issue.\n");
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
            /* a form's option with a value: skip the value (checked by the form's parser) */
            if (i + 1 < argc && !strchr(argv[i], '=') && argv[i + 1][0] != '-') i++;
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
    if (scene)
        return cli_usage_error("report",
                               "report SCENE.json is not implemented yet (a later issue); "
                               "use report --kernel srbf");
    return cli_usage_error("report", "expected --kernel srbf (see strandlight report --help)");
}
