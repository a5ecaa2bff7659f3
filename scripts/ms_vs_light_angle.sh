#!/usr/bin/env bash
# ms_vs_light_angle.sh [BUILD] [SPP]: the fast frame's multiple scattering against the path
# tracer's under one small sun (a disc of 1.5 deg radius, power 4.5, nothing else in the map) at
# elevations 0, 48 and 75 deg behind the default scene's hair (procedural wavy, 4000 strands,
# radius 0.04, chiang, sigma_a 0: every bit of light that is not single scattering is multiple
# scattering), 160 x 120. Prints, per elevation, the mean ratio ours / path tracer of the beauty
# and of the MS layer (`compare --layer MS`, two seeds, 4x4 blocks corrected). Used for the table
# in docs/results.md ("Multiple scattering under a compact source").
set -eu
BUILD=${1:-build}
SPP=${2:-256}
SL="$(cd "$(dirname "$BUILD/strandlight")" && pwd)/strandlight"
D=$(mktemp -d)
trap 'rm -rf "$D"' EXIT
PY=python3; [ -x /usr/bin/python3 ] && PY=/usr/bin/python3
for EL in 0 48 75; do
    # lat-long 512 x 256, flat RGBE; direction of pixel centre (theta from +y, phi):
    # (-sin th sin ph, cos th, sin th cos ph), the project's convention (docs/formats.md)
    $PY - "$D/sun$EL.hdr" "$EL" <<'PYEOF'
import math, sys
W, H = 512, 256
el = math.radians(float(sys.argv[2])); ax, az = 0.5630, -0.8265
d = (math.cos(el) * ax, math.sin(el), math.cos(el) * az)
c0 = math.cos(math.radians(1.5))
pix = []
for y in range(H):
    th = (y + 0.5) / H * math.pi
    for x in range(W):
        ph = (x + 0.5) / W * 2 * math.pi
        v = (-math.sin(th) * math.sin(ph), math.cos(th), math.sin(th) * math.cos(ph))
        if v[0] * d[0] + v[1] * d[1] + v[2] * d[2] > c0:
            pix.append((x, y, math.sin(th) * (math.pi / H) * (2 * math.pi / W)))
L = 4.5 / sum(p[2] for p in pix)
m, e = math.frexp(L)
texel = bytes([int(m * 256)] * 3 + [e + 128])
img = bytearray(4 * W * H)
for x, y, _ in pix:
    img[4 * (y * W + x):4 * (y * W + x) + 4] = texel
with open(sys.argv[1], 'wb') as f:
    f.write(b'#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n' % (H, W) + bytes(img))
PYEOF
    cat > "$D/s$EL.json" <<JSON
{"hair": {"procedural": {"style": "wavy", "strands": 4000, "points": 16, "seed": 1}, "radius": 0.04},
 "material": {"model": "chiang", "sigma_a": [0, 0, 0], "roughness": 0.3, "radial_roughness": 0.3},
 "environment": {"file": "sun$EL.hdr"}, "camera": {"fov_deg": 30},
 "image": {"width": 160, "height": 120},
 "quality": {"lobes": 4, "multiple_scattering": "on"}}
JSON
    (cd "$D" && "$SL" --quiet render "s$EL.json" --device c --aov MS -o "f$EL.exr" &&
        for S in 1 2; do
            "$SL" --quiet reference "s$EL.json" --path --spp "$SPP" --seed $S --threads 2 \
                -o "p$EL-$S.exr"
        done)
    B=$("$SL" compare "$D/f$EL.exr" "$D/p$EL-1.exr" "$D/p$EL-2.exr" --block 4 --csv |
        awk -F, '/^ratio/{r=$2} /^rel_rmse_blocks_corrected/{b=$5} END{printf "%.3f (4x4 %.3f)", r, b}')
    M=$("$SL" compare "$D/f$EL.exr" "$D/p$EL-1.exr" "$D/p$EL-2.exr" --block 4 --csv --layer MS |
        awk -F, '/^ratio/{r=$2} /^rel_rmse_blocks_corrected/{b=$5} END{printf "%.3f (4x4 %.3f)", r, b}')
    echo "elevation $EL deg: beauty ours/path $B, MS ours/path $M"
done
