#!/usr/bin/env bash
# bench.sh BUILD_DIR: runs every test/bench/bench_*.sh (benchmarks are never part of `make test`).
# Absolute times are noisy on shared machines: each benchmark reports ratios measured in one run.
set -u
BUILD=${1:-build}
export SL="$BUILD/strandlight" BUILD
for b in test/bench/bench_*.sh; do
    [ -e "$b" ] || continue
    echo "== $b"
    bash "$b" "$BUILD" || echo "bench: $b failed"
done
