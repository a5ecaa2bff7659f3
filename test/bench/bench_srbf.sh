#!/usr/bin/env bash
# bench_srbf.sh [BUILD_DIR] [DEVICE]: regenerates the SRBF error-vs-time figures of docs/srbf.md:
# `strandlight report --kernel srbf` on the 150-row stiff sample with the committed exact values
# (test/test_srbf_stiff.csv; add --write-exact to a run without --exact to regenerate those, ~7
# minutes on one core), C path and the OpenCL device DEVICE (default: any; "none": C only).
# Writes docs/srbf_report.csv, docs/srbf_report.svg and prints the Markdown table (rates wall-clock
# and per CPU second = per core, which survives a loaded machine), then the fast path's extra
# rates: C with 1 and 2 threads, the RGB batch (3 sigma_a per row), and on OpenCL the RGB kernel
# generic vs -D specialised (docs/srbf.md, "Speed").
set -eu
BUILD=${1:-build}
DEVICE=${2:-opencl}
"$BUILD/strandlight" report --kernel srbf --exact test/test_srbf_stiff.csv --device "$DEVICE" \
    --min-time 0.5 --csv docs/srbf_report.csv --svg docs/srbf_report.svg

# Rows (point, lobe, RGB) per second per core of the renderer's batches, scalar reference vs
# batched, in one run (test/bench/bench_srbf_rows.c, built here against the library: it is no
# unit test, it prints timings): chiang (the default material's model, data/bench_goal.json's
# material), d'Eon and the Marschner fast path.
ROWS="$BUILD/bench_srbf_rows"
${CC:-cc} -std=c11 -O2 -Wall -Wextra -Werror -Ihost -Ikernels -Icpu -D_DEFAULT_SOURCE \
    -D_POSIX_C_SOURCE=200809L -o "$ROWS" test/bench/bench_srbf_rows.c "$BUILD/libstrandlight.a" \
    -lOpenCL -lOpenEXR-3_1 -lOpenEXRCore-3_1 -lIex-3_1 -lImath-3_1 -lcjson -lstb -lembree3 \
    -limgui -lglfw -lGL -lstdc++ -lpthread -lm
echo
for m in '{"model": "chiang", "melanin": 0.3, "roughness": 0.3, "radial_roughness": 0.3}' \
    '{"model": "deon"}' '{"model": "marschner"}'; do
    "$ROWS" "$m" 1
done
# The chiang batch on the x86-64 baseline instead of AVX2 + FMA (cpu/srbf_deon_c_avx2.c; the same
# bits): the ratio to the first chiang line is what the wider vectors give.
echo "chiang on the baseline (SL_SIMD=base):"
SL_SIMD=base "$ROWS" '{"model": "chiang", "melanin": 0.3, "roughness": 0.3, "radial_roughness": 0.3}' 1
