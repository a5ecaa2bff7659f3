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
# The OpenCL device of the CLI checks, chosen once here (test/cli/lib.sh: $SL_TEST_DEVICE, else a
# GPU, else PoCL) and passed to every script.
. test/cli/lib.sh
export SL_CL_DEVICE SL_CL_LISTED
echo "== OpenCL test device: $SL_CL_DEVICE (listed: $SL_CL_LISTED)"
# A script that exits non-zero (a crash, a syntax error, an unexpected `exit`) is a failure
# even when every line it printed was PASS: its checks may not have run.
for t in test/cli/test_*.sh; do
    t0=$(date +%s)
    bash "$t" 2>&1 | tee -a "$log" | grep -v '^PASS'
    rc=${PIPESTATUS[0]}
    if [ "$rc" -ne 0 ]; then echo "FAIL $t: exit status $rc" | tee -a "$log"; fi
    echo "== $t ($(( $(date +%s) - t0 )) s)"
done
passed=$(grep -c '^PASS' "$log")
failed=$(grep -c '^FAIL' "$log")
skipped=$(grep -c '^SKIP' "$log")
echo "($(( $(date +%s) - start )) s; log in $log)"
echo "$passed passed, $failed failed, $skipped skipped"
[ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]
