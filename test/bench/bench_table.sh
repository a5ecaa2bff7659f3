#!/usr/bin/env bash
# bench_table.sh [BUILD_DIR]: what Ren's precomputed SRBF table buys a chiang frame
# (docs/srbf_ren.md, "Models deon and chiang"; docs/performance.md, session 17). The goal scene
# (data/bench_goal.json, needs ../shared; else the default scene) as an orbit of 2 frames, C path,
# `--method fast` against `--method table` (the table built once first into a cache directory of
# this run's own, then loaded as a later session would), ROUNDS (default 2) alternated rounds:
# the shade pass and frame times of both frames as --explain prints them, process CPU seconds,
# and how far the table's frames are from fast's (`strandlight compare`). Ratios within a round
# are the figures to quote on a shared machine.
set -eu
BUILD=${1:-build}
SL="$BUILD/strandlight"
ROUNDS=${ROUNDS:-2}
D=$(mktemp -d "${TMPDIR:-/tmp}/sl-bench-table-XXXXXX")
trap 'rm -rf "$D"' EXIT
SCENE=data/bench_goal.json
[ -e ../shared/data/hair/straight.hair ] || SCENE=data/default.json
export SL_CACHE_DIR="$D/cache"
echo "# bench_table ($(date -u +%F), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)): $SCENE"
"$SL" --quiet render "$SCENE" --device c --method table -o "$D/warm.exr" 2>/dev/null # builds
echo "| round | method | shade 1 (s) | frame 1 (s) | shade 2 (s) | frame 2 (s) | CPU (s) |"
echo "|---|---|---|---|---|---|---|"
for r in $(seq 1 "$ROUNDS"); do
    for m in fast table; do
        out=$( { /usr/bin/time -f "cpu %U %S" "$SL" render "$SCENE" --device c --method "$m" \
            --orbit 2 --explain -o "$D/$m.exr"; } 2>&1)
        printf '%s\n' "$out" | awk -v r="$r" -v m="$m" '
            $1 == "shade" {s[++ns] = $3}
            $1 == "total" {t[++nt] = $2}
            $1 == "cpu" {c = $2 + $3}
            END {printf "| %s | %s | %s | %s | %s | %s | %.2f |\n", r, m, s[1], t[1], s[2], t[2], c}'
    done
done
for f in 0000 0001; do
    echo "frame $f, table against fast:"
    "$SL" compare "$D/table_$f.exr" "$D/fast_$f.exr" 2>&1 | grep -E "^(ratio|rel RMSE pixels, raw)"
done
