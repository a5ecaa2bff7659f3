#!/usr/bin/env bash
# bench_shadow.sh [BUILD_DIR]: light-pass time (docs/shadow.md) of `strandlight eval
# transmittance` on the default procedural hair (wavy, 10000 strands x 16 points) for 1, 16 and
# 40 lobes (16 per launch: 1, 1 and 3 launches) at 256^2 and 512^2, on the C twin and on the
# OpenCL device (PoCL here). One query row per lobe, so the lookup is negligible; the times come
# from the SL_SHADOW_TIMES line of the light pass (device profiling events for OpenCL, wall clock
# for C) plus the build's wall clock. Prints one line per run and the PoCL / C ratio of the
# build's wall time. LOBES / SIZES override the lists.
set -eu
BUILD=${1:-build}
SL="$BUILD/strandlight"
TMP="$BUILD/bench-shadow"
mkdir -p "$TMP"
LOBES=${LOBES:-"1 16 40"}
SIZES=${SIZES:-"256 512"}
python3 - "$TMP" <<'PY'
import json, math, random, sys
d = sys.argv[1]
r = random.Random(7)
lobes = []
for j in range(40):
    z = r.uniform(-1, 1); p = r.uniform(0, 2 * math.pi); s = math.sqrt(1 - z * z)
    lobes.append({"dir": [s * math.cos(p), s * math.sin(p), z], "lambda": r.uniform(0.1, 0.5),
                  "rgb": [1, 1, 1]})
json.dump({"lobes": lobes}, open(d + "/lobes.json", "w"))
for size in (256, 512):
    json.dump({"hair": {"procedural": {}}, "environment": {"lobes": "lobes.json"},
               "quality": {"shadow_size": size}}, open("%s/scene%d.json" % (d, size), "w"))
for n in (1, 16, 40):
    with open("%s/q%d.csv" % (d, n), "w") as f:
        f.write("x,y,z,lobe\n")
        for j in range(n):
            f.write("0,0,0,%d\n" % j)
PY
have_cl=0
if "$SL" devices 2>/dev/null | grep -q 'PoCL\|GPU'; then have_cl=1; fi
# Warm the OpenCL program cache so no kernel compilation is timed.
if [ $have_cl = 1 ]; then
    SL_SHADOW_TIMES=0 "$SL" eval transmittance --scene "$TMP/scene256.json" --backend opencl \
        < "$TMP/q1.csv" > /dev/null
fi
field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" "$2"; }
printf "%-7s %5s %6s %9s %9s %9s %9s %9s\n" backend lobes size build_s upload_s project_s \
    raster_s tables_s
for size in $SIZES; do
    for n in $LOBES; do
        c_wall=
        for b in c opencl; do
            [ $b = opencl ] && [ $have_cl = 0 ] && continue
            SL_SHADOW_TIMES=1 "$SL" eval transmittance --scene "$TMP/scene$size.json" \
                --backend $b < "$TMP/q$n.csv" > /dev/null 2> "$TMP/times"
            w=$(field wall_build "$TMP/times")
            printf "%-7s %5d %6d %9s %9s %9s %9s %9s" $b "$n" "$size" "$w" \
                "$(field upload "$TMP/times")" "$(field project "$TMP/times")" \
                "$(field raster "$TMP/times")" "$(field tables "$TMP/times")"
            if [ $b = c ]; then
                c_wall=$w
                echo
            else
                echo "   PoCL/C $(echo "$w / $c_wall" | bc -l | cut -c1-5)x"
            fi
        done
    done
done
