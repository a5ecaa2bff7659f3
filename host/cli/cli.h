/* cli.h: the subcommand table and small argument helpers shared by every host/cli/cmd_*.c. */
#ifndef SL_CLI_H
#define SL_CLI_H

/* Each subcommand lives in host/cli/cmd_NAME.c and returns the process exit code
 * (0 success, 1 bad input or failure, 2 usage error). argv[0] is the subcommand name. */
int cmd_render(int argc, char **argv);
int cmd_info(int argc, char **argv);
int cmd_eval(int argc, char **argv);
int cmd_devices(int argc, char **argv);
int cmd_kernels(int argc, char **argv);
int cmd_fit(int argc, char **argv);
int cmd_sample(int argc, char **argv);
int cmd_report(int argc, char **argv);
int cmd_reference(int argc, char **argv);
int cmd_view(int argc, char **argv);
int cmd_export(int argc, char **argv);
int cmd_compare(int argc, char **argv);

/* True when argv[*i] is `name` (then *value = argv[*i+1], *i advanced) or `name=value`.
 * A missing value prints a usage error and sets *missing. */
int cli_opt(int argc, char **argv, int *i, const char *name, const char **value, int *missing);
/* True when argv[i] is -h or --help. */
int cli_is_help(const char *arg);
/* Prints "strandlight CMD: MSG" and returns 2 (usage error). */
int cli_usage_error(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Parses an integer/float option value; on failure prints a usage error and returns -1. */
int cli_int(const char *cmd, const char *opt, const char *value, long lo, long hi, long *out);
int cli_double(const char *cmd, const char *opt, const char *value, double *out);

#endif
