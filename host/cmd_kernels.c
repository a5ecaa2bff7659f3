/* cmd_kernels.c: `strandlight kernels` (placeholder until its issue lands). */
#include "cli.h"

#include <stdio.h>

int cmd_kernels(int argc, char **argv) {
    (void)argc;
    (void)argv;
    fprintf(stderr, "strandlight kernels: not implemented yet\n");
    return 2;
}
