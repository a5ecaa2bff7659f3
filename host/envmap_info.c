/* envmap_info.c: `strandlight info` for environment maps (placeholder; the env-map I/O work fills it). */
#include "envmap.h"

int sl_envmap_info(const char *path, FILE *out, sl_err *e) {
    (void)out;
    return sl_fail(e, "%s: environment maps are not supported yet", path);
}
