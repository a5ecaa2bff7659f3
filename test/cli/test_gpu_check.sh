# test_gpu_check.sh: scripts/gpu_check.sh (`make gpu-check`, issue 20) in smoke mode on the test
# machine's PoCL device, without building (the binary under test, $SL): it exits 0, runs the
# kernel check and a first frame with --explain on PoCL, prints one figures block, writes it
# into --out replacing an older block there (the text around it kept), and leaves
# docs/performance.md alone. SKIP without a PoCL device (the script needs one in smoke mode).
. test/cli/lib.sh
D="$TMP/gpu_check"
rm -rf "$D"; mkdir -p "$D"
expect_exit_2() {
    out=$(bash scripts/gpu_check.sh "$@" 2>&1); rc=$?
    if [ $rc -eq 2 ] && printf '%s' "$out" | grep -q 'usage: scripts/gpu_check.sh'; then pass "gpu_check_usage $*"
    else fail "gpu_check_usage $*" "rc=$rc $out"; fi
}
expect_exit_2 --bogus
expect_exit_2 --out
if ! "$SL" devices 2>/dev/null | grep -q '\[PoCL\]'; then
    cl_skip gpu_check_smoke "no PoCL device"
    exit 0
fi
# an --out file with text around an older block: the block is replaced, the text kept
printf 'before\n<!-- gpu-check: begin old -->\nOLD FIGURES\n<!-- gpu-check: end -->\nafter\n' >"$D/perf.md"
docsum=$(cksum <docs/performance.md)
# the step limits raised: the 5-minute budget is for a real run, not for a loaded or sanitized CI
GPU_CHECK_KERNELS_S=300 GPU_CHECK_RENDER_S=300 SL="$SL" bash scripts/gpu_check.sh --smoke --no-build --out "$D/perf.md" >"$D/out.txt" 2>"$D/err.txt"; rc=$?
if [ $rc -eq 0 ]; then pass gpu_check_smoke_exit
else fail gpu_check_smoke_exit "rc=$rc $(tail -3 "$D/err.txt")"; fi
if grep -q '^| kernels --check .* | PASS: 1 passed, 0 failed' "$D/out.txt" &&
   grep -q '^raster .*PoCL.* PASS$' "$D/out.txt"; then pass gpu_check_smoke_kernels
else fail gpu_check_smoke_kernels "$(grep -i kernels "$D/out.txt" | head -3)"; fi
# the frame ran on PoCL (the view pass says where its K-buffer ran) and its passes are timed
if grep -q '^| render data/default.json .* | PASS: first frame [0-9.]*s |$' "$D/out.txt" &&
   grep -q '^view  *run .*K-buffer on OpenCL' "$D/out.txt" && grep -q '^total  *[0-9.]*s$' "$D/out.txt" &&
   grep -q 'Device `--device pocl`' "$D/out.txt"; then pass gpu_check_smoke_frame
else fail gpu_check_smoke_frame "$(grep -E '^(\| render|view|total)' "$D/out.txt")"; fi
nb=$(grep -c '^<!-- gpu-check: begin' "$D/out.txt")
if [ "$nb" -eq 1 ] && [ "$(tail -1 "$D/out.txt")" = '<!-- gpu-check: end -->' ]; then pass gpu_check_smoke_block
else fail gpu_check_smoke_block "$nb begin markers; last line $(tail -1 "$D/out.txt")"; fi
# --out: the old block replaced by exactly the printed one, text around it kept
want=$(printf 'before\n%s\nafter' "$(cat "$D/out.txt")")
if [ "$(cat "$D/perf.md")" = "$want" ] && ! grep -q 'OLD FIGURES' "$D/perf.md"; then pass gpu_check_out_replaces_block
else fail gpu_check_out_replaces_block "$(head -5 "$D/perf.md")"; fi
if [ "$(cksum <docs/performance.md)" = "$docsum" ]; then pass gpu_check_smoke_leaves_docs
else fail gpu_check_smoke_leaves_docs "docs/performance.md changed"; fi
