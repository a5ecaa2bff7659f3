/* cmd_compare.c: `strandlight compare OURS.exr REF_A.exr [REF_B.exr] [--ours-noise X2.exr]`:
 * mean colour and relative RMSE (per pixel and on K x K blocks) of our image against an outside
 * reference such as Blender Cycles, corrected for both sides' noise (verify/report/compare.h,
 * docs/validation.md). Exit 0, 1 on bad input (one line naming the file), 2 on usage. */
#include "cli/cli.h"
#include "verify/report/compare.h"

#include <stdio.h>
#include <string.h>

static const char *usage_text =
    "usage: strandlight compare OURS.exr REF_A.exr [REF_B.exr] [options]\n"
    "\n"
    "Compares OURS.exr with a reference render (e.g. Blender Cycles, docs/validation.md) over\n"
    "hair pixels (alpha > 0 in any image): mean premultiplied colour per channel of each image\n"
    "and the ratio ours / reference; relative RMSE sqrt(sum (x - ref)^2 / sum ref^2) per pixel\n"
    "and on the means of K x K blocks (blocks holding hair), per channel and averaged. With\n"
    "REF_B (the same render with another seed) the reference is (A + B) / 2, its noise variance\n"
    "(A - B)^2 / 4 per pixel or block; with --ours-noise likewise for ours; the corrected RMSE\n"
    "subtracts both: sqrt(max(0, sum (x - ref)^2 - sum var) / sum ref^2).\n"
    "Images: EXR with channels R, G, B, A (premultiplied), all the same size.\n"
    "  --ours-noise X2.exr  a second image of ours, independent of OURS (another seed, same\n"
    "                      settings): ours becomes (OURS + X2) / 2, var (OURS - X2)^2 / 4\n"
    "  --ours-half X2.exr   instead: X2 is OURS's own first half of samples: ours stays OURS,\n"
    "                      var (OURS - X2)^2\n"
    "  --layer L           compare the AOV L instead of the beauty: channels L.R, L.G, L.B of\n"
    "                      every image (e.g. MS: ours and the path tracer's multiple scattering)\n"
    "  --ref-layer L       the reference images' layer only (e.g. direct: the path tracer's\n"
    "                      single scattering, against ours rendered with multiple scattering off)\n"
    "  --block K           block size (default 8)\n"
    "  --csv               machine form: quantity,r,g,b,avg\n";

int cmd_compare(int argc, char **argv) {
    const char *files[3] = {NULL, NULL, NULL}, *ours2 = NULL, *v, *layer = NULL, *ref_layer = NULL;
    int nfiles = 0, csv = 0, missing = 0, mode = SL_OURS_INDEPENDENT, half = 0;
    long block = 8;
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(usage_text, stdout);
            return 0;
        } else if (cli_opt(argc, argv, &i, "--ours-noise", &v, &missing) ||
                   (half = cli_opt(argc, argv, &i, "--ours-half", &v, &missing))) {
            if (missing) return 2;
            if (ours2) return cli_usage_error("compare", "--ours-noise / --ours-half given twice");
            mode = half ? SL_OURS_HALF : SL_OURS_INDEPENDENT;
            ours2 = v;
        } else if (cli_opt(argc, argv, &i, "--layer", &v, &missing)) {
            if (missing) return 2;
            layer = v;
        } else if (cli_opt(argc, argv, &i, "--ref-layer", &v, &missing)) {
            if (missing) return 2;
            ref_layer = v;
        } else if (cli_opt(argc, argv, &i, "--block", &v, &missing)) {
            if (missing || cli_int("compare", "--block", v, 1, 4096, &block)) return 2;
        } else if (strcmp(argv[i], "--csv") == 0) {
            csv = 1;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return cli_usage_error("compare", "unknown option '%s'", argv[i]);
        } else if (nfiles < 3) {
            files[nfiles++] = argv[i];
        } else {
            return cli_usage_error("compare", "unexpected argument '%s'", argv[i]);
        }
    }
    if (nfiles < 2) return cli_usage_error("compare", "need OURS.exr and REF_A.exr");

    sl_image img[4];
    memset(img, 0, sizeof img);
    const char *paths[4] = {files[0], ours2, files[1], files[2]};
    sl_err e = {{0}};
    int rc = 1;
    for (int k = 0; k < 4; k++) {
        const char *l = k >= 2 && ref_layer ? ref_layer : layer;
        if (paths[k] && sl_image_read_exr_layer(paths[k], l, &img[k], &e)) goto done;
    }
    sl_compare_in in = {
        .ours = &img[0],
        .ours2 = ours2 ? &img[1] : NULL,
        .ours2_mode = mode,
        .ref_a = &img[2],
        .ref_b = files[2] ? &img[3] : NULL,
        .block = (int)block,
        .names = {paths[0], paths[1], paths[2], paths[3]},
    };
    sl_compare_result r;
    if (sl_compare(&in, &r, &e)) goto done;
    if (csv)
        sl_compare_csv(stdout, &in, &r);
    else
        sl_compare_print(stdout, &in, &r);
    rc = 0;
done:
    if (rc) fprintf(stderr, "strandlight: %s\n", e.msg[0] ? e.msg : "compare failed");
    for (int k = 0; k < 4; k++)
        sl_image_free(&img[k]);
    return rc;
}
