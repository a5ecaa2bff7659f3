#!/usr/bin/env bash
# bench_path.sh [BUILD_DIR]: the path tracer's speed (`strandlight reference --path`,
# docs/reference.md "Path tracer") on the default scene (data/default.json: model marschner,
# whose width-averaged f costs ~45 us an evaluation) and on the same scene with models deon and
# chiang (per-hit fibers). One line each: image, spp, wall and CPU seconds, camera paths
# (pixel samples) per second, scattering events per path. SIZE, SPP and THREADS override.
set -eu
BUILD=${1:-build}
SL="$BUILD/strandlight"
TMP="$BUILD/bench-path"
mkdir -p "$TMP"
W=${W:-160}
H=${H:-120}
SPP=${SPP:-4}
THREADS=${THREADS:-2}
ENV="$(pwd)/data/env/city_256.hdr"
for m in default deon chiang; do
    scene=data/default.json
    if [ "$m" != default ]; then
        scene="$TMP/$m.json"
        if [ "$m" = deon ]; then mat='{"model": "deon", "eta": 1.55, "sigma_a": [0.18, 0.32, 0.62]}'
        else mat='{"model": "chiang", "melanin": 0.3}'; fi
        cat > "$scene" <<JSON
{"hair": {"procedural": {"style": "wavy", "strands": 4000, "points": 16, "seed": 1}, "radius": 0.04},
 "material": $mat, "environment": {"file": "$ENV"}, "camera": {"fov_deg": 30},
 "image": {"width": 640, "height": 480}}
JSON
    fi
    "$SL" reference "$scene" --path --spp "$SPP" --width "$W" --height "$H" --threads "$THREADS" \
        --force -o "$TMP/$m.exr" 2>/dev/null
    python3 - "$TMP/$m.exr.json" "$m" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["reference"]
print("%-8s %dx%d %3d spp %7.2f s wall %7.2f s CPU %9.0f paths/s %6.2f events/path (%.2f per hit)" % (
    sys.argv[2], r["width"], r["height"], r["spp"], r["time_s"], r["cpu_s"], r["paths_per_s"],
    r["events_per_path"], r["events_per_path"] / max(r["coverage"], 1e-9)))
PY
done
