/* cmd_render.c: `strandlight render` (placeholder until its issue lands). */
#include "cli.h"

#include <stdio.h>

int cmd_render(int argc, char **argv) {
    (void)argc;
    (void)argv;
    fprintf(stderr, "strandlight render: not implemented yet\n");
    return 2;
}
