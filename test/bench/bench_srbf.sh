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
