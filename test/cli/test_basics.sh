# test_basics.sh: the binary's top-level behaviour.
. test/cli/lib.sh
expect_output version_prints "strandlight " "$SL" --version
expect_output help_lists_commands "render" "$SL" --help
out=$("$SL" nosuchcommand 2>&1); rc=$?
if [ $rc -eq 2 ] && printf '%s' "$out" | grep -q "unknown command"; then pass unknown_command_is_usage_error; else fail unknown_command_is_usage_error "rc=$rc $out"; fi

# -V is --version; `help COMMAND` is COMMAND --help
if [ "$("$SL" -V)" = "$("$SL" --version)" ]; then pass cli_dash_V; else fail cli_dash_V "differs"; fi
if [ "$("$SL" help render)" = "$("$SL" render --help)" ]; then pass cli_help_command
else fail cli_help_command "help render differs from render --help"; fi
err=$("$SL" help nope 2>&1 >/dev/null); rc=$?
if [ "$rc" -eq 2 ] && printf '%s' "$err" | grep -q "help: unknown command 'nope'"; then
    pass cli_help_unknown # a usage error, exit 2 like an unknown command
else fail cli_help_unknown "exit $rc: $err"; fi
