/* cmd_report.c: `strandlight report` (placeholder until its issue lands). */
#include "cli.h"

#include <stdio.h>

int cmd_report(int argc, char **argv) {
    (void)argc;
    (void)argv;
    fprintf(stderr, "strandlight report: not implemented yet\n");
    return 2;
}
