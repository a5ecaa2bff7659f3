# test_ms_direction.sh: the frame's multiple scattering under one small sun against the path
# tracer's, at two elevations (issue 19; docs/volume.md "Where the scattered light goes"). The
# default scene's hair (procedural wavy, 4000 strands, radius 0.04), white chiang (sigma_a 0: all
# light that is not single scattering is multiple scattering), 80 x 60, C path; path tracer 32 spp
# x 2 seeds. The truth's multiple scattering changes 2.6x between the sun across the hanging
# fibers (0 deg) and 48 deg above them; the fast frame that kept the light on the lobe's cone
# changed 7x and more (docs/results.md: ours / path 2.11 and 0.29 at 160 x 120). Checked: mean
# MS ours / path tracer within [0.75, 1.35] at both elevations (measured at this size: see the
# PASS line's figures with SL_TEST_VERBOSE=1), and their ratio (how much the direction moves the
# MS) within a factor 1.35 of the path tracer's.
. test/cli/lib.sh
D="$TMP/ms_direction"
rm -rf "$D"; mkdir -p "$D"
PY=python3; [ -x /usr/bin/python3 ] && PY=/usr/bin/python3
ratio() { # ratio OURS.exr REF1.exr REF2.exr: mean MS ours / path tracer (grey: channel R)
    "$SL" compare "$1" "$2" "$3" --csv --layer MS 2>/dev/null | awk -F, '$1 == "ratio" {print $2}'
}
declare -A R
for EL in 0 48; do
    "$PY" scripts/sun_map.py "$D/sun$EL.hdr" "$EL" --scene "$D/s$EL.json" --size 80x60
    "$SL" --quiet render "$D/s$EL.json" --device c --aov MS -o "$D/f$EL.exr" 2>/dev/null
    for S in 1 2; do
        "$SL" --quiet reference "$D/s$EL.json" --path --spp 32 --seed $S --threads 2 \
            -o "$D/p$EL-$S.exr" 2>/dev/null
    done
    R[$EL]=$(ratio "$D/f$EL.exr" "$D/p$EL-1.exr" "$D/p$EL-2.exr")
done
if [ -n "${SL_TEST_VERBOSE:-}" ]; then echo "  MS ours / path tracer: 0 deg ${R[0]}, 48 deg ${R[48]}"; fi
for EL in 0 48; do
    n="ms_direction_sun_${EL}deg"
    if [ -n "${R[$EL]}" ] && awk -v r="${R[$EL]}" 'BEGIN {exit !(r >= 0.75 && r <= 1.35)}'; then
        pass "$n"
    else
        fail "$n" "multiple scattering ours / path tracer '${R[$EL]}', want within [0.75, 1.35]"
    fi
done
if [ -n "${R[0]}" ] && [ -n "${R[48]}" ] &&
    awk -v a="${R[0]}" -v b="${R[48]}" 'BEGIN {q = a / b; exit !(q >= 1 / 1.35 && q <= 1.35)}'; then
    pass ms_direction_follows_the_light
else
    fail ms_direction_follows_the_light "ours / path tracer at 0 and 48 deg: '${R[0]}' and '${R[48]}': the direction moves our MS by more than 1.35x the truth's"
fi

# The default scene (data/default.json: the same hair, melanin 0.3, the shipped city map) at
# the report's 160 x 120: mean colour ours / path tracer (32 spp x 2) within issue 19's 3 % per
# channel. Measured 1.002 / 1.000 / 0.988; with the view pass's old tent filter 1.023 / 1.029 /
# 1.032 (session 17, docs/coverage.md "Pixel filter"), before the spread 0.78 / 0.83 / 0.92; both
# fail. (At 80 x 60, where this ran before, strands are ~0.1 px wide and segments shorter than a
# pixel: 1.052 / 1.037 / 1.017 with the box filter, 1.035 / 1.019 / 1.010 with the tent.)
"$PY" - "$D/default.json" "$PWD/data/default.json" "$PWD/data/env/city_256.hdr" <<'PY'
import json, sys
s = json.load(open(sys.argv[2]))
s["environment"]["file"] = sys.argv[3]
s.pop("output", None)
s["image"] = {"width": 160, "height": 120}
json.dump(s, open(sys.argv[1], "w"))
PY
"$SL" --quiet render "$D/default.json" --device c -o "$D/fd.exr" 2>/dev/null
for S in 1 2; do
    "$SL" --quiet reference "$D/default.json" --path --spp 32 --seed $S --threads 2 \
        -o "$D/pd-$S.exr" 2>/dev/null
done
M=$("$SL" compare "$D/fd.exr" "$D/pd-1.exr" "$D/pd-2.exr" --csv 2>/dev/null |
    awk -F, '$1 == "ratio" {print $2, $3, $4}')
if [ -n "${SL_TEST_VERBOSE:-}" ]; then echo "  default scene mean ours / path tracer: $M"; fi
if [ -n "$M" ] && echo "$M" | awk '{exit !($1 >= 0.97 && $1 <= 1.03 && $2 >= 0.97 && $2 <= 1.03 && $3 >= 0.97 && $3 <= 1.03)}'; then
    pass ms_default_scene_mean
else
    fail ms_default_scene_mean "mean colour ours / path tracer '$M', want each within 3 %"
fi
