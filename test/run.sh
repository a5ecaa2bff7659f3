#!/usr/bin/env bash
# run.sh BUILD_DIR: runs the whole test suite against BUILD_DIR/strandlight and
# BUILD_DIR/unit_tests, then every test/cli/*.sh, and ends with "N passed, N failed".
set -u
BUILD=${1:-build}
export SL="$BUILD/strandlight" TMP="$BUILD/test-tmp/cli" SL_TEST_TMP="$BUILD/test-tmp"
export SHARED=${SL_SHARED_DATA:-../shared/data}
rm -rf "$BUILD/test-tmp"; mkdir -p "$TMP"
log="$BUILD/test-log.txt"
: > "$log"
start=$(date +%s)
t0=$(date +%s)
"$BUILD/unit_tests" 2>&1 | tee -a "$log" | grep -v '^PASS'
rc=${PIPESTATUS[0]}
# A crash (signal) or a non-zero exit without a FAIL line is itself a failure.
if [ "$rc" -ne 0 ] && ! grep -q '^FAIL' "$log"; then echo "FAIL unit_tests: exit status $rc" | tee -a "$log"; fi
echo "== unit tests $BUILD/unit_tests ($(( $(date +%s) - t0 )) s)"
for t in test/cli/test_*.sh; do
    t0=$(date +%s)
    bash "$t" 2>&1 | tee -a "$log" | grep -v '^PASS'
    echo "== $t ($(( $(date +%s) - t0 )) s)"
done
passed=$(grep -c '^PASS' "$log")
failed=$(grep -c '^FAIL' "$log")
skipped=$(grep -c '^SKIP' "$log")
echo "($(( $(date +%s) - start )) s; log in $log)"
echo "$passed passed, $failed failed, $skipped skipped"
[ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]
