/* cmd_sample.c: `strandlight sample`: N directional lights that stand for an environment map
 * (median cut, envsample.h), for the brute-force reference renderer. */
#include "cli/cli.h"
#include "lighting/envfit.h"
#include "lighting/envsample.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void usage(FILE *fp) {
    fprintf(fp,
            "usage: strandlight sample MAP.exr|MAP.hdr --lights N -o LIGHTS.json [options]\n\n"
            "Cuts the map into N regions of equal power (median cut, stratified by power) and\n"
            "writes one directional light per region: its power-weighted mean direction and\n"
            "its power (radiance integrated over the region). Prints the same errors as `fit`:\n"
            "lobe_conv_rel_l2 (the lights seen through a fiber-like lobe) and rel_l2 (each\n"
            "light's power spread evenly over its region).\n\n"
            "options:\n"
            "  --lights N              number of lights (1..%d)\n"
            "  -o, --output FILE       lights JSON to write (atomically)\n"
            "  --conv-lambda-deg D     width of the lobe for lobe_conv_rel_l2 (default 10)\n"
            "  --threads T             worker threads for the error (default 2)\n"
            "  --clamp-nonfinite       replace NaN/Inf pixels by 0 instead of failing\n"
            "  -q, --quiet             no summary line on stdout\n",
            SL_LOBES_MAX);
}

int cmd_sample(int argc, char **argv) {
    const char *map_path = NULL, *out_path = NULL, *v;
    long nlights = 0, threads = 2;
    double conv_deg = 10;
    int clamp = 0, quiet = sl_is_quiet(), missing = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (cli_is_help(a)) {
            usage(stdout);
            return 0;
        } else if (cli_opt(argc, argv, &i, "--lights", &v, &missing)) {
            if (missing || cli_int("sample", "--lights", v, 1, SL_LOBES_MAX, &nlights)) return 2;
        } else if (cli_opt(argc, argv, &i, "-o", &v, &missing) ||
                   cli_opt(argc, argv, &i, "--output", &v, &missing)) {
            if (missing) return 2;
            out_path = v;
        } else if (cli_opt(argc, argv, &i, "--conv-lambda-deg", &v, &missing)) {
            if (missing || cli_double("sample", "--conv-lambda-deg", v, &conv_deg)) return 2;
            if (!(conv_deg > 0) || conv_deg > 180)
                return cli_usage_error("sample", "--conv-lambda-deg: must be in (0, 180]");
        } else if (cli_opt(argc, argv, &i, "--threads", &v, &missing)) {
            if (missing || cli_int("sample", "--threads", v, 1, 16, &threads)) return 2;
        } else if (strcmp(a, "--clamp-nonfinite") == 0) {
            clamp = 1;
        } else if (strcmp(a, "-q") == 0 || strcmp(a, "--quiet") == 0) {
            quiet = 1;
        } else if (a[0] == '-' && a[1]) {
            return cli_usage_error("sample", "unknown option '%s'", a);
        } else if (!map_path) {
            map_path = a;
        } else {
            return cli_usage_error("sample", "unexpected argument '%s'", a);
        }
    }
    if (!map_path) return cli_usage_error("sample", "missing the environment map");
    if (!nlights) return cli_usage_error("sample", "missing --lights N");
    if (!out_path) return cli_usage_error("sample", "missing -o LIGHTS.json");

    sl_err e = {{0}};
    sl_envmap map;
    /* on a terminal, what it is doing (about 1.6 s on the largest shared map, forest.exr, at
     * any light count: too short for a bar with an ETA) */
    sl_status("sample: reading %s", map_path);
    if (sl_envmap_load(map_path, clamp, &map, &e)) {
        sl_status_clear();
        fprintf(stderr, "strandlight: %s\n", e.msg);
        return 1;
    }
    double t0 = sl_now(), rel = 0, conv = 0, conv_lambda = conv_deg * M_PI / 180;
    sl_envlights L;
    int rc = 1;
    sl_status("sample: %ld lights and their errors", nlights);
    int src = sl_envsample(&map, (int)nlights, conv_lambda, (int)threads, &L, &rel, &conv, &e);
    sl_status_clear();
    if (src) goto fail;
    double t = sl_now() - t0;
    cJSON *rec = cJSON_CreateObject();
    char hash[32];
    snprintf(hash, sizeof hash, "%016llx", (unsigned long long)map.hash);
    cJSON_AddStringToObject(rec, "map_hash", hash);
    cJSON_AddStringToObject(rec, "map", map_path);
    cJSON *st = cJSON_AddObjectToObject(rec, "settings");
    cJSON_AddNumberToObject(st, "lights", (double)nlights);
    cJSON_AddNumberToObject(st, "conv_lambda_deg", conv_deg);
    cJSON_AddBoolToObject(st, "clamp_nonfinite", clamp);
    cJSON_AddStringToObject(rec, "method", "median cut (equal-power regions)");
    cJSON_AddNumberToObject(rec, "lights", L.count);
    cJSON_AddNumberToObject(rec, "rel_l2", rel);
    cJSON_AddNumberToObject(rec, "lobe_conv_rel_l2", conv);
    cJSON_AddNumberToObject(rec, "time_s", round(t * 1000) / 1000);
    cJSON_AddStringToObject(rec, "version", SL_VERSION);
    L.record_json = cJSON_PrintUnformatted(rec);
    cJSON_Delete(rec);
    if (sl_envlights_save(out_path, &L, &e)) goto fail_lights;
    if (!quiet)
        printf("%s: %d lights, lobe_conv_rel_l2 %.4g (%.0f deg lobe), rel_l2 %.4g (piecewise "
               "constant), %.2f s -> %s\n",
               map_path, L.count, conv, conv_deg, rel, t, out_path);
    rc = 0;
fail_lights:
    sl_envlights_free(&L);
fail:
    if (rc) fprintf(stderr, "strandlight: %s\n", e.msg);
    sl_envmap_free(&map);
    return rc;
}
