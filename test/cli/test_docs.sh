# test_docs.sh: the docs cite only files that exist and README's index lists every doc
# (scripts/check_docs.py; issue 22 found cited files that had gone and a doc missing from the index).
. test/cli/lib.sh
if out=$(python3 scripts/check_docs.py 2>&1); then pass docs_cite_existing_files
else fail docs_cite_existing_files "$(printf '%s' "$out" | head -5 | tr '\n' ';')"; fi
# the checker can fail: a doc citing a missing file is reported
T=$(mktemp -d); mkdir -p "$T/scripts" "$T/docs"; cp scripts/check_docs.py "$T/scripts/"
printf '# r\n| `docs/a.md` | a |\n' > "$T/README.md"; printf 'see `host/no/such.c`\n' > "$T/docs/a.md"
printf 'x\n' > "$T/docs/b.md"
out=$(python3 "$T/scripts/check_docs.py" 2>&1); rc=$?
if [ "$rc" -eq 1 ] && printf '%s' "$out" | grep -q 'docs/a.md:1: cites host/no/such.c' && printf '%s' "$out" | grep -q 'does not list docs/b.md'; then
    pass docs_checker_reports_missing
else fail docs_checker_reports_missing "exit $rc: $out"; fi
rm -rf "$T"

# README's examples run as written (issue 22). `make run` (the set-up block and the line below
# it): its recipe, when the binary is up to date (make -n prints only the render), runs and
# writes the two files README names, the EXR with RGBA and depth Z as it says. `make deps`,
# `make test` and the other make targets install packages or run whole suites: not run here.
B=$(dirname "$SL")
recipe=$(make -s -n run BUILD="$B" 2>/dev/null)
if [ "$(printf '%s\n' "$recipe" | grep -c '')" -ne 1 ] || ! printf '%s' "$recipe" | grep -q "^$B/strandlight render data/default.json "; then
    skip readme_make_run "make run would build first ($B is not up to date): $(printf '%s' "$recipe" | head -1)"
else
    rm -f out/default.exr out/default.png
    if out=$(sh -c "$recipe" 2>&1) && [ -s out/default.exr ] && [ -s out/default.png ] &&
       "$SL" info out/default.exr 2>/dev/null | grep -q '^channels: 5 (A,B,G,R,Z)'; then
        pass readme_make_run
    else fail readme_make_run "$(printf '%s' "$out" | tail -2)"; fi
fi
# `strandlight view data/default.json` without a display says so and points to render
err=$(env -u DISPLAY -u WAYLAND_DISPLAY "$SL" view data/default.json 2>&1 >/dev/null); rc=$?
if [ "$rc" -eq 1 ] && printf '%s' "$err" | grep -q 'no display.*strandlight render'; then pass readme_view_without_display
else fail readme_view_without_display "exit $rc: $err"; fi
# the Commands table: `strandlight COMMAND --help` documents each, and every option a row
# names is in that help (a row citing an option the binary lacks is a stale example)
bad=""
while IFS= read -r row; do
    cmd=$(printf '%s' "$row" | sed -n 's/^| `\([a-z]*\).*/\1/p')
    [ -n "$cmd" ] || continue
    help=$("$SL" "$cmd" --help 2>&1) || { bad="$bad $cmd(--help exit)"; continue; }
    cell=$(printf '%s' "$row" | cut -d'`' -f2)
    for opt in $(printf '%s' "$cell" | grep -o -- '--*[a-z][a-z-]*' | sort -u); do
        printf '%s' "$help" | grep -q -- "$opt" || bad="$bad $cmd:$opt"
    done
done < <(sed -n '/^## Commands/,/^## /p' README.md | grep '^| `[a-z]')
if [ -z "$bad" ]; then pass readme_commands_options_exist; else fail readme_commands_options_exist "not in --help:$bad"; fi
# the Scenes section's error example has the form it shows
T=$(mktemp -d)
printf '{"hair": {"procedural": {}}, "environment": {"file": "a.hdr"}, "camera": {"fov_deg": "wide"}}\n' > "$T/scene.json"
expect_error readme_scene_error_form "scene.json: camera.fov_deg: expected a number" "$SL" render "$T/scene.json" --device c -o "$T/x.exr"
rm -rf "$T"
