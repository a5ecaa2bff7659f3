#!/usr/bin/env bash
# gpu_check.sh [--smoke] [--no-build] [--build DIR] [--scene FILE] [--out FILE]: the GPU check of
# issue 20 (`make gpu-check`), one script under 5 minutes:
#   1. builds (make all into DIR, relative to the repository, default build; --no-build: use $SL,
#      else DIR/strandlight);
#   2. picks the device: the first GPU OpenCL device (`--device gpu`), else, or with --smoke,
#      the PoCL CPU device (`--device pocl`);
#   3. runs `strandlight kernels --check` on it (every kernel against its C twin, then the
#      extreme sweep; smoke: the raster check only);
#   4. renders the goal scene (data/bench_goal.json when ../shared holds its hair, else
#      data/default.json; smoke: data/default.json at 160x120, first frame only) on it, two
#      orbit frames (the first frame and one with the light passes cached), with
#      --method fast --explain (per-pass seconds);
#   5. prints a figures block (device, each step's wall seconds and result, the kernels table,
#      both frames' --explain) and writes it into docs/performance.md between the
#      "gpu-check: begin/end" markers (replacing the previous block, or appending one) — only
#      when it ran for real on a GPU, or into --out FILE when given. Smoke runs (PoCL) and runs
#      without a GPU print the block and write nothing in docs/.
# Never part of the build or of `make test` except as test/cli/test_gpu_check.sh's smoke run.
# Step limits (s): GPU_CHECK_BUILD_S (120), GPU_CHECK_KERNELS_S (90), GPU_CHECK_RENDER_S (80).
# Exit status: 0 all passed; 1 a step failed (build, a kernel check, the render, a step past its
# time limit); 2 usage; 3 no device for the mode (no GPU and no PoCL device).
set -u
BUILD=build SMOKE=0 NOBUILD=0 SCENE="" OUT=""
usage() {
    echo "usage: scripts/gpu_check.sh [--smoke] [--no-build] [--build DIR] [--scene FILE] [--out FILE]" >&2
    exit 2
}
while [ $# -gt 0 ]; do
    case $1 in
    --smoke) SMOKE=1 ;;
    --no-build) NOBUILD=1 ;;
    --build) [ $# -ge 2 ] || usage; BUILD=$2; shift ;;
    --scene) [ $# -ge 2 ] || usage; SCENE=$2; shift ;;
    --out) [ $# -ge 2 ] || usage; OUT=$2; shift ;;
    -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "gpu_check: unknown option '$1'" >&2; usage ;;
    esac
    shift
done
if [ -n "$SCENE" ] && [ ! -f "$SCENE" ]; then echo "gpu_check: --scene $SCENE: no such file" >&2; exit 2; fi
# paths given from the caller's directory stay valid after the cd to the repository
[ -n "$SCENE" ] && SCENE=$(realpath "$SCENE")
[ -n "$OUT" ] && OUT=$(realpath -m "$OUT")
[ -n "${SL:-}" ] && SL=$(realpath -m "$SL")
cd "$(dirname "$0")/.." || exit 1
SCENE=${SCENE#"$PWD/"} # a scene inside the repository is named as the docs name it
if [ -x /usr/bin/python3 ]; then PY=/usr/bin/python3; else PY=python3; fi
T0=$SECONDS
WORK=$(mktemp -d "${TMPDIR:-/tmp}/gpu_check.XXXXXX") || exit 1
trap 'rm -rf "$WORK"' EXIT
# Time limits per step (s): together under the issue's 5 minutes with room for the device's
# first program builds. A step past its limit is a failure, not a hang.
LIM_BUILD=${GPU_CHECK_BUILD_S:-120} LIM_KERNELS=${GPU_CHECK_KERNELS_S:-90} LIM_RENDER=${GPU_CHECK_RENDER_S:-80}
failed=0
rows=""
row() { rows="$rows| $1 | $2 | $3 |"$'\n'; }

# 1. build
if [ "$NOBUILD" = 0 ]; then
    t=$SECONDS
    if timeout "$LIM_BUILD" make -j"$(nproc)" BUILD="$BUILD" all >"$WORK/build.log" 2>&1; then
        row build $((SECONDS - t)) "make all (BUILD=$BUILD)"
    else
        tail -20 "$WORK/build.log" >&2
        echo "gpu_check: build failed (log above)" >&2
        exit 1
    fi
    SL=$BUILD/strandlight
else
    SL=${SL:-$BUILD/strandlight}
fi
[ -x "$SL" ] || { echo "gpu_check: $SL: no such binary (build first or drop --no-build)" >&2; exit 1; }

# 2. the device
devs=$("$SL" devices 2>/dev/null)
if [ "$SMOKE" = 0 ] && printf '%s\n' "$devs" | grep -q '^ *type GPU'; then
    DEV=gpu
    # the first GPU device's name line: "* device P:D (#N): NAME" just above its "type GPU"
    label=$(printf '%s\n' "$devs" | grep -B1 -m1 '^ *type GPU' | head -1 | sed 's/^[* ]*device //; s/ *<- auto$//')
elif printf '%s\n' "$devs" | grep -q '\[PoCL\]'; then
    [ "$SMOKE" = 1 ] || echo "gpu_check: no GPU OpenCL device; smoke mode on PoCL (nothing written in docs/)" >&2
    SMOKE=1 DEV=pocl
    label="PoCL: $(printf '%s\n' "$devs" | grep -A1 -m1 '\[PoCL\]' | tail -1 | sed 's/^[* ]*device //; s/ *<- auto$//')"
else
    echo "gpu_check: no GPU and no PoCL OpenCL device (strandlight devices: $(printf '%s' "$devs" | tail -1))" >&2
    exit 3
fi
if [ -z "$SCENE" ]; then
    if [ "$SMOKE" = 0 ] && [ -f ../shared/data/hair/straight.hair ] &&
       [ -f ../shared/data/envmaps/blender_rgbe/forest.hdr ]; then
        SCENE=data/bench_goal.json
    else
        SCENE=data/default.json
    fi
fi
if [ "$SMOKE" = 1 ]; then
    # the CI smoke run (< 60 s on 2 loaded cores): one kernel check, the first frame only
    KARGS=(--only raster --reps 1)
    RARGS=(--width 160 --height 120 --frames 0:1)
    NFR=1
else
    KARGS=()
    RARGS=()
    NFR=2
fi

# 3. kernels --check
t=$SECONDS
timeout "$LIM_KERNELS" "$SL" kernels --check --device "$DEV" "${KARGS[@]}" >"$WORK/kernels.txt" 2>&1
rc=$?
summary=$(grep -E '^[0-9]+ passed, [0-9]+ failed' "$WORK/kernels.txt" | head -1)
nfail_ext=$(grep -c '^extreme .* FAIL' "$WORK/kernels.txt")
if [ $rc -eq 0 ]; then res="PASS: $summary; extreme sweep: $nfail_ext FAIL lines"
elif [ $rc -eq 124 ]; then res="FAIL: past ${LIM_KERNELS} s"; failed=1
else res="FAIL (exit $rc): $summary"; failed=1; fi
row "kernels --check ${KARGS[*]}" $((SECONDS - t)) "$res"

# 4. the goal-scene frames
t=$SECONDS
timeout "$LIM_RENDER" "$SL" render "$SCENE" -o "$WORK/frame.exr" --device "$DEV" --method fast \
    --orbit 2 --explain "${RARGS[@]}" >"$WORK/render.txt" 2>"$WORK/render.err"
rc=$?
totals=$(grep '^total ' "$WORK/render.txt" | awk '{print $2}' | paste -sd' ')
set -- $totals
if [ $rc -eq 0 ] && [ $# -eq "$NFR" ]; then res="PASS: first frame $1${2:+, orbit frame $2}"
elif [ $rc -eq 124 ]; then res="FAIL: past ${LIM_RENDER} s"; failed=1
else res="FAIL (exit $rc): $(tail -1 "$WORK/render.err")"; failed=1; fi
row "render $SCENE --orbit 2 ${RARGS[*]}" $((SECONDS - t)) "$res"

# 5. the figures block
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
{
    echo "<!-- gpu-check: begin (written by scripts/gpu_check.sh; rerun it rather than edit) -->"
    echo "### GPU check $(date -u '+%Y-%m-%d %H:%M UTC'), commit $commit$([ "$SMOKE" = 1 ] && echo ', smoke mode')"
    echo
    echo "Device \`--device $DEV\`: $label. Host: $(nproc) CPUs, load average $(cut -d' ' -f1-3 /proc/loadavg)."
    echo "Command: \`bash scripts/gpu_check.sh$([ "$SMOKE" = 1 ] && echo ' --smoke')\` (\`make gpu-check\`); $((SECONDS - T0)) s in all."
    echo
    echo "| step | wall s | result |"
    echo "|---|---|---|"
    printf '%s' "$rows"
    echo
    echo "\`strandlight kernels --check --device $DEV ${KARGS[*]}\`:"
    echo
    echo '```'
    grep -v '^extreme ' "$WORK/kernels.txt"
    echo '```'
    echo
    echo "\`strandlight render $SCENE --device $DEV --method fast --orbit 2 --explain ${RARGS[*]}\` (seconds per pass):"
    echo
    echo '```'
    cat "$WORK/render.txt"
    echo '```'
    echo "<!-- gpu-check: end -->"
} >"$WORK/block.md"
cat "$WORK/block.md"

target=$OUT
if [ -z "$target" ] && [ "$SMOKE" = 0 ]; then target=docs/performance.md; fi
if [ -n "$target" ]; then
    # Replace the block between the markers (or append it), through a temporary file renamed over
    # the target: an interrupted run leaves the old file whole.
    "$PY" - "$target" "$WORK/block.md" <<'PY' || { echo "gpu_check: cannot write $target" >&2; exit 1; }
import os, re, sys
target, block = sys.argv[1], open(sys.argv[2]).read()
old = open(target).read() if os.path.exists(target) else ""
pat = re.compile(r"<!-- gpu-check: begin.*?<!-- gpu-check: end -->\n?", re.S)
if pat.search(old):
    new = pat.sub(lambda m: block, old, count=1)
else:
    new = old + ("" if old.endswith("\n") or not old else "\n") + ("\n" if old else "") + block
tmp = target + ".tmp%d" % os.getpid()
with open(tmp, "w") as f:
    f.write(new)
os.replace(tmp, target)
PY
    echo "gpu_check: figures written to $target" >&2
fi
[ "$failed" = 0 ] || { echo "gpu_check: FAILED (see the block above)" >&2; exit 1; }
echo "gpu_check: all passed on --device $DEV in $((SECONDS - T0)) s" >&2
