# test_fuzz.sh: builds every libFuzzer target (test/fuzz/build.sh, into <build dir>/fuzz) and runs
# each briefly on a copy of its seed corpus (test/fuzz/corpus/<target>/), one PASS/FAIL line per
# target. SKIP lines when clang-15 is missing. FUZZ_SECONDS sets the time per target: default 2
# (it was 3 with six targets; thirteen targets x 2 s plus an up-to-date build take about 45 s
# on the 2-core machine).
. test/cli/lib.sh
FB=${FUZZ_BUILD:-$(dirname "$SL")/fuzz}
secs=${FUZZ_SECONDS:-2}
targets=$(ls test/fuzz/fuzz_*.c 2>/dev/null)
if ! command -v clang-15 >/dev/null 2>&1; then
    for t in $targets; do skip "$(basename "$t" .c)" "clang-15 not installed"; done
    exit 0
fi
start=$(date +%s)
if ! out=$(bash test/fuzz/build.sh "$FB" 2>&1); then
    fail fuzz_build "$(printf '%s' "$out" | grep -m3 -E 'error|Error' | tr '\n' ' ')"
    exit 0
fi
pass "fuzz_build ($(( $(date +%s) - start )) s)"
W="$TMP/fuzz"
rm -rf "$W"; mkdir -p "$W"
for t in $targets; do
    name=$(basename "$t" .c)
    corpus="$W/$name.corpus"
    mkdir -p "$corpus"
    [ -d "test/fuzz/corpus/$name" ] && cp -r "test/fuzz/corpus/$name/." "$corpus/"
    log="$W/$name.log"
    # A libFuzzer dictionary (test/fuzz/corpus/<target>.dict: key names, special values) when
    # there is one.
    dict=()
    [ -f "test/fuzz/corpus/$name.dict" ] && dict=(-dict="test/fuzz/corpus/$name.dict")
    # -rss_limit_mb: a loader that allocates from an absurd header count fails here;
    # artifacts (crashing inputs) land in $W, not in the repository.
    if "$FB/$name" -max_total_time="$secs" -rss_limit_mb=1024 -timeout=10 -print_final_stats=1 \
        -artifact_prefix="$W/$name-" "${dict[@]}" "$corpus" >"$log" 2>&1; then
        runs=$(grep -o 'number_of_executed_units: [0-9]*' "$log" | grep -o '[0-9]*$')
        pass "$name (${runs:-?} inputs in $secs s)"
    else
        why=$(grep -m1 -E 'ERROR:|runtime error|SUMMARY|out-of-memory|timeout' "$log")
        fail "$name" "${why:-exit status $?}; log and crashing input in $W"
    fi
done
