/* cmd_sample.c: `strandlight sample` (placeholder until the environment-fitting work lands). */
#include "cli.h"

#include <stdio.h>

int cmd_sample(int argc, char **argv) {
    (void)argc;
    (void)argv;
    fprintf(stderr, "strandlight sample: not implemented yet\n");
    return 2;
}
