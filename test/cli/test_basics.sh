# test_basics.sh: the binary's top-level behaviour.
. test/cli/lib.sh
expect_output version_prints "strandlight " "$SL" --version
expect_output help_lists_commands "render" "$SL" --help
out=$("$SL" nosuchcommand 2>&1); rc=$?
if [ $rc -eq 2 ] && printf '%s' "$out" | grep -q "unknown command"; then pass unknown_command_is_usage_error; else fail unknown_command_is_usage_error "rc=$rc $out"; fi
