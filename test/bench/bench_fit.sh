#!/usr/bin/env bash
# bench_fit.sh BUILD_DIR: `strandlight fit` on every shared environment map.
#  1. lobes vs error vs time: N in {10, 20, 40, 80} for every map (2 threads);
#  2. the 40-lobe target (<= 5 s for a 1024 x 512 map on 2 cores);
#  3. LONG=1: the same optimiser with --effort 100 (100x the iteration budget) on LONG_MAPS,
#     to show how far the default stops from where it would converge.
# Prints a markdown table (also written to BUILD_DIR/bench_fit.md). Wall times are of the whole
# command (load + fit + errors); on a loaded machine they are upper bounds.
set -u
BUILD=${1:-build}
SL=${SL:-$BUILD/strandlight}
SHARED=${SL_SHARED_DATA:-../shared/data}
NS=${NS:-10 20 40 80}
OUT="$BUILD/bench_fit.md"
TMPD="$BUILD/bench-fit"
mkdir -p "$TMPD"
if [ ! -d "$SHARED/envmaps" ]; then echo "bench_fit: no $SHARED/envmaps, skipped"; exit 0; fi
field() { grep -o "\"$2\":[[:space:]]*[-0-9.e+]*" "$1" | head -1 | sed 's/.*:[[:space:]]*//'; }
now() { date +%s.%N; }
{
echo "| map | size | lobes | rel_l2 | lobe_conv_rel_l2 | sun lobes | time (s) |"
echo "|---|---|---|---|---|---|---|"
} > "$OUT"
maps=$(cd "$SHARED/envmaps" && find . -name '*.exr' -o -name '*.hdr' | sed 's|^\./||' | sort)
worst40=0
for m in $maps; do
    for n in $NS; do
        j="$TMPD/$(echo "$m" | tr '/' '_').$n.json"
        t0=$(now)
        if ! "$SL" fit "$SHARED/envmaps/$m" --lobes "$n" --threads 2 -q -o "$j" 2>/dev/null; then
            echo "| $m | | $n | FAILED | | | |" >> "$OUT"; continue
        fi
        t=$(echo "$(now) - $t0" | bc)
        size=$(grep -o '"map_size":[^]]*' "$j" | sed 's/.*\[//; s/[[:space:]]//g; s/,/x/')
        printf '| %s | %s | %s | %.4f | %.4f | %s | %.2f |\n' "$m" "$size" "$n" "$(field "$j" rel_l2)" \
            "$(field "$j" lobe_conv_rel_l2)" "$(field "$j" sun_lobes)" "$t" >> "$OUT"
        if [ "$n" = 40 ] && [ "$size" = 1024x512 ]; then
            worst40=$(echo "if ($t > $worst40) $t else $worst40" | bc)
        fi
    done
done
echo "" >> "$OUT"
echo "Slowest 40-lobe fit of a 1024x512 map: ${worst40} s (target 5 s)." >> "$OUT"
if [ "${LONG:-0}" = 1 ]; then
    {
    echo ""
    echo "| map | effort | rel_l2 | lobe_conv_rel_l2 | time (s) | rel_l2 / long run's |"
    echo "|---|---|---|---|---|---|"
    } >> "$OUT"
    for m in ${LONG_MAPS:-blender_rgbe/city.hdr pmndrs/venice.hdr blender_exr/sunrise.exr}; do
        declare -A R T C
        for ef in 1 100; do
            j="$TMPD/long.$(echo "$m" | tr '/' '_').$ef.json"
            t0=$(now)
            "$SL" fit "$SHARED/envmaps/$m" --lobes 40 --effort "$ef" --threads 2 -q -o "$j" 2>/dev/null
            T[$ef]=$(echo "$(now) - $t0" | bc); R[$ef]=$(field "$j" rel_l2); C[$ef]=$(field "$j" lobe_conv_rel_l2)
        done
        for ef in 1 100; do
            printf '| %s | %s | %.4f | %.4f | %.1f | %.3f |\n' "$m" "$ef" "${R[$ef]}" "${C[$ef]}" "${T[$ef]}" \
                "$(echo "${R[$ef]} / ${R[100]}" | bc -l)" >> "$OUT"
        done
    done
fi
cat "$OUT"
