/* cmd_view.c: `strandlight view` (issue 11), a placeholder until the viewer lands. */
#include "cli.h"

#include <stdio.h>

int cmd_view(int argc, char **argv) {
    (void)argc;
    (void)argv;
    fprintf(stderr, "strandlight: view: not built yet; use `strandlight render`\n");
    return 1;
}
