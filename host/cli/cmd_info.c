/* cmd_info.c: `strandlight info FILE`: describes a hair file (.hair, .tfx, .tfxproj, .data) or an
 * environment map (.exr, .hdr). Exit 0, 1 on bad input (one line on stderr), 2 on usage error. */
#include "cli/cli.h"
#include "io/envmap/envmap.h"
#include "io/hair/hair.h"

#include <stdio.h>
#include <string.h>

static void usage(FILE *fp) {
    fprintf(
        fp,
        "usage: strandlight info FILE\n\n"
        "Describes a hair file or an environment map.\n\n"
        "  hair (.hair cyHair, .tfx TressFX 3/4, .tfxproj TressFX project, .data USC-HairSalon):\n"
        "    format, strands, points, segments, bounding box, strand lengths, thickness,\n"
        "    and whether per-point thickness / transparency / color are present.\n"
        "    A .tfxproj is loaded with the follow strands its groups ask for.\n"
        "  environment map (.exr, .hdr): size, channels, luminance statistics.\n\n"
        "Exit status: 0 ok, 1 bad input (one-line message on stderr), 2 usage error.\n");
}

int cmd_info(int argc, char **argv) {
    const char *path = NULL;
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            usage(stdout);
            return 0;
        }
        if (argv[i][0] == '-' && argv[i][1] != 0)
            return cli_usage_error("info", "unknown option '%s'", argv[i]);
        if (path)
            return cli_usage_error("info", "expected one FILE, got '%s' and '%s'", path, argv[i]);
        path = argv[i];
    }
    if (!path) return cli_usage_error("info", "missing FILE");
    sl_err e;
    e.msg[0] = 0;
    int rc;
    if (sl_ext_is(path, "exr") || sl_ext_is(path, "hdr"))
        rc = sl_envmap_info(path, stdout, &e);
    else
        rc = sl_hair_info(path, stdout, &e);
    if (rc != 0) {
        fprintf(stderr, "strandlight: %s\n", e.msg[0] ? e.msg : "info failed");
        return 1;
    }
    return 0;
}
