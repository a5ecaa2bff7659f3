#!/usr/bin/env bash
# ms_vs_light_angle.sh [BUILD] [SPP]: the fast frame's multiple scattering against the path
# tracer's under one small sun (a disc of 1.5 deg radius, power 4.5, nothing else in the map) at
# elevations 0, 48 and 75 deg behind the default scene's hair (procedural wavy, 4000 strands,
# radius 0.04, chiang, sigma_a 0: every bit of light that is not single scattering is multiple
# scattering), 160 x 120. Prints, per elevation, the mean ratio ours / path tracer of the beauty
# and of the MS layer (`compare --layer MS`, two seeds, 4x4 blocks corrected). Used for the table
# in docs/results.md ("Multiple scattering under a compact source").
# REFDIR=DIR keeps the maps, scenes and path-traced references there and reuses them on the next
# run (they do not depend on the fast frame): only the fast frame is rendered again. QUALITY='"k": v,
# ...' adds keys to the scenes' "quality" (the fast frame only; the references ignore them).
set -eu
BUILD=${1:-build}
SPP=${2:-256}
SL="$(cd "$(dirname "$BUILD/strandlight")" && pwd)/strandlight"
if [ -n "${REFDIR:-}" ]; then
    mkdir -p "$REFDIR"
    D=$(cd "$REFDIR" && pwd)
else
    D=$(mktemp -d)
    trap 'rm -rf "$D"' EXIT
fi
QX=${QUALITY:+, $QUALITY}
PY=python3; [ -x /usr/bin/python3 ] && PY=/usr/bin/python3
for EL in ${ELEVATIONS:-0 48 75}; do
    if [ ! -s "$D/p$EL-2.exr" ]; then
    "$PY" "$(dirname "$0")/sun_map.py" "$D/sun$EL.hdr" "$EL" --scene "$D/s$EL.json" --size 160x120
    (cd "$D" && for S in 1 2; do
            "$SL" --quiet reference "s$EL.json" --path --spp "$SPP" --seed $S --threads 2 \
                -o "p$EL-$S.exr"
        done)
    fi
    sed "s/\"multiple_scattering\": \"on\"}/\"multiple_scattering\": \"on\"$QX}/" "$D/s$EL.json" \
        > "$D/q$EL.json"
    (cd "$D" && "$SL" --quiet render "q$EL.json" --device c --aov MS -o "f$EL.exr")
    B=$("$SL" compare "$D/f$EL.exr" "$D/p$EL-1.exr" "$D/p$EL-2.exr" --block 4 --csv |
        awk -F, '/^ratio/{r=$2} /^rel_rmse_blocks_corrected/{b=$5} END{printf "%.3f (4x4 %.3f)", r, b}')
    M=$("$SL" compare "$D/f$EL.exr" "$D/p$EL-1.exr" "$D/p$EL-2.exr" --block 4 --csv --layer MS |
        awk -F, '/^ratio/{r=$2} /^rel_rmse_blocks_corrected/{b=$5} END{printf "%.3f (4x4 %.3f)", r, b}')
    echo "elevation $EL deg: beauty ours/path $B, MS ours/path $M"
done
