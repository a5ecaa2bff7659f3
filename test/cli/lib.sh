# lib.sh: helpers for CLI tests (sourced). Each check prints PASS/FAIL/SKIP lines for test/run.sh.
# SL is the binary under test; SHARED the shared data dir (may be absent); TMP a scratch dir.
: "${SL:=build/strandlight}"
: "${SHARED:=../shared/data}"
: "${TMP:=build/test-tmp/cli}"
mkdir -p "$TMP"

pass() { echo "PASS $1"; }
fail() { echo "FAIL $1: $2"; }
skip() { echo "SKIP $1: $2"; }
have_shared() { [ -d "$SHARED" ]; }

# The OpenCL device of every OpenCL check, chosen once (as the unit tests' test/cl_fixture.h):
# $SL_TEST_DEVICE when set, else gpu when `strandlight devices` lists a GPU, else pocl when it
# lists a PoCL platform, else opencl (any device). SL_CL_LISTED=1 when it lists any OpenCL device
# (or SL_TEST_DEVICE names one): an OpenCL check that could not use the device then fails
# instead of skipping (cl_skip). test/run.sh exports both, so the scripts need not ask again.
if [ -z "${SL_CL_DEVICE:-}" ]; then
    _devs=$("$SL" devices 2>/dev/null)
    SL_CL_LISTED=0
    if printf '%s\n' "$_devs" | grep -q '^\* device '; then SL_CL_LISTED=1; fi
    if [ -n "${SL_TEST_DEVICE:-}" ]; then SL_CL_DEVICE=$SL_TEST_DEVICE; SL_CL_LISTED=1
    elif printf '%s\n' "$_devs" | grep -q '^ *type GPU'; then SL_CL_DEVICE=gpu
    elif printf '%s\n' "$_devs" | grep -q '\[PoCL\]'; then SL_CL_DEVICE=pocl
    else SL_CL_DEVICE=opencl; fi
    if [ "$SL_CL_DEVICE" = c ]; then SL_CL_LISTED=0; fi # SL_TEST_DEVICE=c: no OpenCL checks
    unset _devs
fi
: "${SL_CL_LISTED:=0}"
have_cl() { [ "$SL_CL_LISTED" = 1 ]; }
# cl_skip NAME WHY: an OpenCL check that did not run: SKIP without an OpenCL device, FAIL when
# one is listed (the check should have used it).
cl_skip() {
    if have_cl; then fail "$1" "an OpenCL device is listed (--device $SL_CL_DEVICE) but the check could not use it: $2"
    else skip "$1" "$2"; fi
}

# expect_error NAME EXPECTED_SUBSTRING CMD...: CMD must exit 1 with one stderr line containing
# the substring, must not crash (no signal exit) and must print nothing else to stderr.
expect_error() {
    local name=$1 want=$2; shift 2
    local out rc lines
    out=$("$@" 2>&1 >/dev/null); rc=$?
    lines=$(printf '%s' "$out" | grep -c '' || true)
    if [ "$rc" -ne 1 ]; then fail "$name" "exit $rc (want 1): $out"; return; fi
    if ! printf '%s' "$out" | grep -qF -- "$want"; then fail "$name" "stderr '$out' lacks '$want'"; return; fi
    if [ "$lines" -ne 1 ]; then fail "$name" "want a one-line error, got $lines lines: $out"; return; fi
    pass "$name"
}

# expect_ok NAME CMD...: CMD must exit 0.
expect_ok() {
    local name=$1; shift
    local out rc
    out=$("$@" 2>&1); rc=$?
    if [ "$rc" -ne 0 ]; then fail "$name" "exit $rc: $(printf '%s' "$out" | tail -3)"; return; fi
    pass "$name"
}

# expect_output NAME EXPECTED_SUBSTRING CMD...: CMD exits 0 and stdout contains the substring.
expect_output() {
    local name=$1 want=$2; shift 2
    local out rc
    out=$("$@" 2>/dev/null); rc=$?
    if [ "$rc" -ne 0 ]; then fail "$name" "exit $rc"; return; fi
    if ! printf '%s' "$out" | grep -qF -- "$want"; then fail "$name" "stdout lacks '$want'"; return; fi
    pass "$name"
}

# no_leftovers NAME DIR: DIR holds no temporary output files.
no_leftovers() {
    local name=$1 dir=$2
    if ls "$dir" 2>/dev/null | grep -q '\.tmp'; then fail "$name" "temporary files left in $dir"; else pass "$name"; fi
}

# white_hdr FILE W H: a W x H Radiance map of one constant white (flat RGBE 128 128 128 129 =
# 1.0 per channel): the neutral map of the colour and furnace checks.
white_hdr() {
    local n=$(($2 * $3)) i
    {
        printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n' "$3" "$2"
        for ((i = 0; i < n; i++)); do printf '\200\200\200\201'; done
    } > "$1"
}
