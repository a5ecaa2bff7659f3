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
