/* cmd_fit.c: `strandlight fit` (placeholder until the environment-fitting work lands). */
#include "cli.h"

#include <stdio.h>

int cmd_fit(int argc, char **argv) {
    (void)argc;
    (void)argv;
    fprintf(stderr, "strandlight fit: not implemented yet\n");
    return 2;
}
