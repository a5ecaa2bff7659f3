/* main.c: the `strandlight` binary: dispatches to one subcommand per host/cli/cmd_*.c. */
#include "cli/cli.h"
#include "base/common.h"

#include <stdio.h>
#include <string.h>

typedef struct command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} command;

static const command commands[] = {
    {"render", cmd_render, "render a scene to EXR (+ PNG preview)"},
    {"info", cmd_info, "describe a hair file or an environment map"},
    {"eval", cmd_eval, "evaluate fiber scattering quantities from CSV (numerics contract)"},
    {"devices", cmd_devices, "list OpenCL platforms and devices"},
    {"kernels", cmd_kernels, "run each OpenCL kernel against its C twin"},
    {"fit", cmd_fit, "fit SRBF lobes to an environment map"},
    {"sample", cmd_sample, "directional lights sampled from an environment map"},
    {"reference", cmd_reference, "brute-force reference render (ray-traced fibers)"},
    {"view", cmd_view, "interactive viewer: live editing and painting (GLFW + OpenGL)"},
    {"report", cmd_report, "error against run time (kernels, scenes)"},
    {"export", cmd_export, "the scene's strands as a .hair file + its camera (for Cycles)"},
    {"compare", cmd_compare, "an image against one or two references (mean colour, rel. RMSE)"},
};
#define NUM_COMMANDS (sizeof commands / sizeof commands[0])

static void usage(FILE *fp) {
    fprintf(fp,
            "usage: strandlight COMMAND [options]   (strandlight COMMAND --help for details)\n\n"
            "Renders strand hair under SRBF environment lighting (OpenCL, with a C path).\n\n"
            "commands:\n");
    for (size_t i = 0; i < NUM_COMMANDS; i++)
        fprintf(fp, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(fp,
            "\n  help COMMAND   the options of COMMAND (same as COMMAND --help)\n"
            "  -V, --version  print the version\n"
            "  --quiet        (any command) no notes, status lines or progress bars on stderr\n");
}

int main(int argc, char **argv) {
    /* a killed run leaves no temporary output behind (issue 21) */
    sl_install_temp_cleanup();
    /* --quiet, for every command: no notes, status lines or progress bars on stderr (warnings
     * and errors stay); taken out before the command parses its options. */
    int n = 1;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--quiet") == 0)
            sl_set_quiet(1);
        else
            argv[n++] = argv[i];
    }
    argc = n;
    argv[argc] = NULL;
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    if (cli_is_help(argv[1])) {
        usage(stdout);
        return 0;
    }
    if (strcmp(argv[1], "help") == 0 && argc >= 3) {
        for (size_t i = 0; i < NUM_COMMANDS; i++)
            if (strcmp(argv[2], commands[i].name) == 0) {
                char *hargv[] = {argv[2], "--help", NULL};
                return commands[i].run(2, hargv);
            }
        fprintf(stderr, "strandlight: help: unknown command '%s' (see 'strandlight --help')\n",
                argv[2]);
        return 2;
    }
    if (strcmp(argv[1], "help") == 0) {
        usage(stdout);
        return 0;
    }
    if (strcmp(argv[1], "--version") == 0 || strcmp(argv[1], "-V") == 0 ||
        strcmp(argv[1], "version") == 0) {
        printf("strandlight %s\n", SL_VERSION);
        return 0;
    }
    for (size_t i = 0; i < NUM_COMMANDS; i++)
        if (strcmp(argv[1], commands[i].name) == 0) return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "strandlight: unknown command '%s' (see 'strandlight --help')\n", argv[1]);
    return 2;
}
