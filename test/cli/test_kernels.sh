# test_kernels.sh: `strandlight kernels --check` / `--bench` tables (docs/frame.md, docs/opencl.md):
# the header columns, the K-buffer fill rows (specialised and generic builds, typical and extreme
# inputs, bit-exact against the C twin), times only with --bench, on the test device
# ($SL_CL_DEVICE, test/cli/lib.sh). SKIP without an OpenCL device.
. test/cli/lib.sh
if ! have_cl; then
    skip kernels_check_table "no OpenCL device"
else
    out=$("$SL" kernels --device "$SL_CL_DEVICE" --only kbuffer --check --size 32 --reps 1 2>/dev/null); rc=$?
    hdr=$(printf '%s\n' "$out" | grep '^kernel ')
    if [ $rc -eq 0 ] && printf '%s' "$hdr" | grep -q 'backend *cases *max_abs *max_rel *tolerance *result$'; then
        pass kernels_check_table
    else fail kernels_check_table "rc=$rc header '$hdr'"; fi
    n=$(printf '%s\n' "$out" | grep -c '^kbuffer .*\(typical\|extreme\) .* exact *PASS$')
    if [ "$n" -eq 2 ]; then pass kernels_check_kbuffer_rows; else fail kernels_check_kbuffer_rows "$n rows: $out"; fi
    if printf '%s\n' "$out" | grep -q '^extreme '; then pass kernels_check_runs_extreme_sweep
    else fail kernels_check_runs_extreme_sweep "no extreme lines"; fi
    out=$("$SL" kernels --device "$SL_CL_DEVICE" --only kbuffer_generic --bench --size 32 --reps 1 2>/dev/null); rc=$?
    if [ $rc -eq 0 ] && printf '%s\n' "$out" | grep '^kernel ' | grep -q 'C_ms *CL_ms *CL_wall$' &&
       [ "$(printf '%s\n' "$out" | grep -c '^kbuffer_generic .*PASS  *[0-9.]* *[0-9.]*w* *[0-9.]*$')" -eq 2 ]; then
        pass kernels_bench_times
    else fail kernels_bench_times "rc=$rc $out"; fi
fi
# without OpenCL: --check still exits 0 and says SKIP
out=$(OCL_ICD_VENDORS=/nonexistent "$SL" kernels --check --only kbuffer 2>&1); rc=$?
if [ $rc -eq 0 ] && printf '%s' "$out" | grep -q 'kbuffer .*SKIP'; then pass kernels_check_no_device
else fail kernels_check_no_device "rc=$rc $out"; fi
