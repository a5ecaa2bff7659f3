#!/usr/bin/env bash
# bench_volume.sh [BUILD_DIR]: issue 8's `make bench` figures (docs/volume.md, "Timing"): the
# voxelization, the shadow-path march and the multiple-scattering response (read from the
# per-material response table since session 3: kernels/ms_table.h, docs/volume.md "The
# response table"; before it, the direct evaluation took 13-15x longer on C) on the C twin and
# on the OpenCL device (PoCL here, a GPU where there is one), as `strandlight kernels --only
# NAME --size N` reports them (best of REPS repetitions, kernel time without transfers, and the
# OpenCL wall time with them), and the OpenCL / C ratio. Sizes: procedural wavy strands for
# voxel and march (2000 and 10000; SIZES overrides), 16384 rows for ms. Absolute times are noisy on a
# shared machine; the ratio of one run is the figure to quote.
set -eu
BUILD=${1:-build}
SL="$BUILD/strandlight"
REPS=${REPS:-3}
SIZES=${SIZES:-"2000 10000"}
if ! "$SL" devices 2>/dev/null | grep -q 'PoCL\|GPU'; then
    echo "bench_volume: no OpenCL device: C only, no ratio"
fi
run() { # NAME SIZE
    out=$("$SL" kernels --only "$1" --size "$2" --reps "$REPS" 2>/dev/null | grep "^$1 " || true)
    if [ -z "$out" ]; then
        echo "bench_volume: kernels --only $1 --size $2 gave no row"
        return 1
    fi
    # The row as `kernels` prints it, then C_ms, CL_ms (kernel only) and their ratio from its
    # last three columns (C_ms, CL_ms, CL_wall; non-numeric marks stripped).
    echo "$out"
    echo "$out" | awk -v k="$1" -v n="$2" '{
        c = $(NF-2); cl = $(NF-1); gsub(/[^0-9.]/, "", c); gsub(/[^0-9.]/, "", cl);
        printf "  -> %s size %s: C %s ms, OpenCL %s ms, OpenCL/C %s\n", k, n, c, cl,
               (c > 0) ? sprintf("%.2fx", cl / c) : "-" }'
}
for n in $SIZES; do
    run voxel "$n"
    run march "$n"
done
run ms 16384
