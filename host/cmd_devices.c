/* cmd_devices.c: `strandlight devices` (placeholder until its issue lands). */
#include "cli.h"

#include <stdio.h>

int cmd_devices(int argc, char **argv) {
    (void)argc;
    (void)argv;
    fprintf(stderr, "strandlight devices: not implemented yet\n");
    return 2;
}
