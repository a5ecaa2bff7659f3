# test_strand_ms.sh: per-strand sigma_a under multiple scattering (material.strand_sigma_a,
# docs/frame.md "Per-strand sigma_a"). A dense slab of blond fibers whose file carries their
# colour (colour_hair.py) on a dark material (melanin 0.8), under a constant white map:
#  - "colors" renders the frame the material with the colour's own sigma_a renders (the
#    strands' sigma_a, computed here from Chiang 2016 Eq. 9 as docs/formats.md gives it, not by
#    the renderer): MS follows the strands, not the material (before, MS kept the material's
#    sigma_a, and the frame was several times darker in blue);
#  - the path tracer (ground truth, every order) follows the strands too, and the frame's hue
#    agrees with it.
. test/cli/lib.sh
if [ -z "${PY:-}" ]; then
    if [ -x /usr/bin/python3 ]; then PY=/usr/bin/python3; else PY=python3; fi
fi
D="$TMP/strand_ms"
rm -rf "$D"; mkdir -p "$D"
"$PY" test/cli/colour_hair.py "$D/blond.hair" 1500 0.02 1.0 0.925 0.569
white_hdr "$D/white.hdr" 64 32
# sigma_a of the colour (docs/formats.md: Chiang Eq. 9 with bn = the radial roughness 0.3)
sa=$("$PY" - <<'EOF'
import math
bn = 0.3
d = 5.969 - 0.215 * bn + 2.532 * bn**2 - 10.73 * bn**3 + 5.574 * bn**4 + 0.245 * bn**5
print(", ".join("%.9g" % (math.log(c) / d) ** 2 for c in (1.0, 0.925, 0.569)))
EOF
)
scene() { # scene NAME MATERIAL_KEYS
    cat > "$D/$1.json" <<JSON
{
  "hair": {"file": "blond.hair"},
  "material": {"model": "chiang", $2, "roughness": 0.3, "radial_roughness": 0.3},
  "environment": {"file": "white.hdr"},
  "camera": {"fov_deg": 40},
  "image": {"width": 64, "height": 48},
  "quality": {"lobes": 8, "multiple_scattering": "on"}
}
JSON
}
scene colors '"melanin": 0.8, "strand_sigma_a": "colors"'
scene same "\"sigma_a\": [$sa]"
out=$("$SL" render "$D/colors.json" --exr "$D/colors.exr" --device c --method fast --explain 2>&1); rc=$?
if [ $rc -eq 0 ] && printf '%s\n' "$out" | grep -q "^ms table .*1 per-strand sigma_a nodes\|^ms table .*3 per-strand sigma_a nodes" &&
   printf '%s\n' "$out" | grep -q "^dual .*strands' mean sigma_a"; then pass strand_ms_plan
else fail strand_ms_plan "rc=$rc $(printf '%s\n' "$out" | grep -E '^(dual|ms table)' | tr '\n' ' ')"; fi
"$SL" render "$D/same.json" --exr "$D/same.exr" --device c --method fast 2>/dev/null
# rel RMSE per pixel: the strands' sigma_a are floats, the material's doubles (and single
# scattering goes through the per-row path): 1e-3 is far above that rounding and far below
# the error of the frame before session 8, whose MS kept the material's sigma_a (measured:
# 0.73 / 0.77 / 0.76 in R / G / B, the frame 4x too dark)
cmp_out=$("$SL" compare "$D/colors.exr" "$D/same.exr" --csv 2>&1)
rm_px=$(printf '%s\n' "$cmp_out" | awk -F, '$1 == "rel_rmse_px_raw" {print $5}')
if [ -n "$rm_px" ] && awk -v x="$rm_px" 'BEGIN {exit !(x < 1e-3)}'; then pass strand_ms_colors_equal_material
else fail strand_ms_colors_equal_material "rel RMSE $rm_px: $(printf '%s' "$cmp_out" | head -c 400)"; fi

# ground truth: the path tracer through the real fibers with the strands' colours. Its hue
# (HSV, degrees) and the frame's must agree within 3 deg (measured 58.7 and 58.5 at 16 spp; the
# file colour's own hue is 49.6 deg: a slab this thin scatters fewer times than Chiang's fit
# assumes). Before session 8 the path tracer ignored the strands: hue 11 deg, the frame's 15.
# Only the hue is checked: the frame is paler and darker than the path tracer here (mean 0.57x,
# blue / red 0.91 against 0.77: the MS energy deficit of issue 19, docs/results.md).
"$SL" reference "$D/colors.json" --path --spp 16 -o "$D/path.exr" > /dev/null 2>&1
hue_of() { # hue_of EXR: the HSV hue of the mean premultiplied colour over hair pixels
    "$SL" compare "$1" "$1" --csv 2>/dev/null | awk -F, '$1 == "mean_ours" {
        r = $2; g = $3; b = $4; mx = r; mn = r
        if (g > mx) mx = g; if (b > mx) mx = b; if (g < mn) mn = g; if (b < mn) mn = b
        if (mx - mn <= 0) { print "nan"; exit }
        if (mx == r) h = 60 * (g - b) / (mx - mn)
        else if (mx == g) h = 60 * (2 + (b - r) / (mx - mn))
        else h = 60 * (4 + (r - g) / (mx - mn))
        if (h < 0) h += 360
        printf "%.2f\n", h }'
}
h_frame=$(hue_of "$D/colors.exr"); h_path=$(hue_of "$D/path.exr")
if [ -n "$h_frame" ] && [ -n "$h_path" ] &&
   awk -v a="$h_frame" -v b="$h_path" 'BEGIN {d = a - b; if (d < 0) d = -d; exit !(d <= 3)}'; then
    pass strand_ms_hue_matches_path_tracer
else fail strand_ms_hue_matches_path_tracer "frame hue '$h_frame' path tracer '$h_path'"; fi

# The issue's own check (issue 22): straight.hair (../shared, blond in the file: 1.0, 0.925,
# 0.569, hue 49.6 deg) with "colors" under the white map. Measured at 96 x 72: frame 58.8 deg,
# path tracer (8 spp) 58.6 deg; before session 8 the frame was 21.8 deg (MS in the material's
# brown). The frame must match the path tracer within 3 deg and the file within 10 deg (the
# rest is physical: Chiang's inverse is fitted to hair deep enough to scatter many times, and
# 10K straight strands are not; both renders are paler than the file's colour).
if have_shared && [ -f "$SHARED/hair/straight.hair" ]; then
    cat > "$D/straight.json" <<JSON
{
  "hair": {"file": "$(cd "$SHARED" && pwd)/hair/straight.hair"},
  "material": {"model": "chiang", "melanin": 0.3, "roughness": 0.3, "radial_roughness": 0.3, "strand_sigma_a": "colors"},
  "environment": {"file": "white.hdr"},
  "camera": {"fov_deg": 30},
  "image": {"width": 96, "height": 72},
  "quality": {"lobes": 8, "multiple_scattering": "on"}
}
JSON
    "$SL" render "$D/straight.json" --exr "$D/straight.exr" --device c --method fast 2>/dev/null
    "$SL" reference "$D/straight.json" --path --spp 8 -o "$D/straight_path.exr" > /dev/null 2>&1
    h_frame=$(hue_of "$D/straight.exr"); h_path=$(hue_of "$D/straight_path.exr")
    if [ -n "$h_frame" ] && [ -n "$h_path" ] &&
       awk -v a="$h_frame" -v b="$h_path" 'BEGIN {d = a - b; if (d < 0) d = -d; e = a - 49.6; if (e < 0) e = -e; exit !(d <= 3 && e <= 10)}'; then
        pass strand_ms_straight_hue
    else fail strand_ms_straight_hue "frame hue '$h_frame', path tracer '$h_path', file 49.6"; fi
else
    skip strand_ms_straight_hue "../shared/data/hair/straight.hair absent"
fi
