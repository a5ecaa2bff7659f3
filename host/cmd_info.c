/* cmd_info.c: `strandlight info` (placeholder until its issue lands). */
#include "cli.h"

#include <stdio.h>

int cmd_info(int argc, char **argv) {
    (void)argc;
    (void)argv;
    fprintf(stderr, "strandlight info: not implemented yet\n");
    return 2;
}
