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

# --quiet (any command, any position): no notes on stderr
D="$TMP/quiet"; mkdir -p "$D"
printf '{"hair": {"procedural": {"strands": 20, "points": 6}}, "environment": {"lobes": "l.json"}, "image": {"width": 16, "height": 12}}\n' > "$D/s.json"
printf '{"lobes": [{"dir": [0, 1, 0], "lambda": 0.5, "rgb": [1, 1, 1]}]}\n' > "$D/l.json"
err=$("$SL" render "$D/s.json" --device c -o "$D/a.exr" --quiet 2>&1 >/dev/null); rc=$?
if [ "$rc" -eq 0 ] && [ -z "$err" ] && [ -s "$D/a.exr" ]; then pass cli_quiet_render
else fail cli_quiet_render "exit $rc, stderr: $err"; fi
err=$("$SL" render "$D/s.json" --device c -o "$D/b.exr" 2>&1 >/dev/null)
if printf '%s' "$err" | grep -q 'render: done'; then pass cli_notes_without_quiet
else fail cli_notes_without_quiet "no note without --quiet: $err"; fi
