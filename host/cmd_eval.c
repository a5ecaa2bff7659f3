/* cmd_eval.c: `strandlight eval` (placeholder until its issue lands). */
#include "cli.h"

#include <stdio.h>

int cmd_eval(int argc, char **argv) {
    (void)argc;
    (void)argv;
    fprintf(stderr, "strandlight eval: not implemented yet\n");
    return 2;
}
