/* cmd_reference.c: `strandlight reference` (placeholder until its issue lands). */
#include "cli.h"

#include <stdio.h>

int cmd_reference(int argc, char **argv) {
    (void)argc;
    (void)argv;
    fprintf(stderr, "strandlight reference: not implemented yet\n");
    return 2;
}
