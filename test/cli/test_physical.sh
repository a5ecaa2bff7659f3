# test_physical.sh: the frame's physical checks that need no reference (DEVELOPERS.md,
# issue 19): a white furnace (constant white map, non-absorbing d'Eon fibers: every fiber should
# vanish into the background, mean colour / coverage = 1) and lobe-cut invariance (the same light
# cut into other lobes must give the same image). Procedural wavy hair, 4000 strands, 96 x 72,
# C path, multiple scattering on. Figures: `strandlight compare A.exr B.exr --csv` (docs/results.md,
# "Physical checks of the frame").
. test/cli/lib.sh
D="$TMP/physical"
rm -rf "$D"; mkdir -p "$D"
white_hdr "$D/white.hdr" 64 32
scene() { # scene NAME ENVIRONMENT [STRANDS]
    cat > "$D/$1.json" <<JSON
{"hair": {"procedural": {"style": "wavy", "strands": ${3:-4000}, "points": 16, "seed": 1}, "radius": 0.04},
 "material": {"model": "deon", "sigma_a": [0, 0, 0]},
 "environment": $2,
 "image": {"width": 96, "height": 72},
 "quality": {"lobes": 24, "multiple_scattering": "on"}}
JSON
    "$SL" render "$D/$1.json" --exr "$D/$1.exr" --device c 2>/dev/null
}
# the near-uniform light of the white map: one lobe of lambda 10 (G falls to 0.98 opposite its
# axis; rgb so that its power is the map's 4 pi), or two coincident halves of it
echo '{"lobes": [{"dir": [0, 1, 0], "lambda": 10, "rgb": [1.0101, 1.0101, 1.0101]}]}' > "$D/one.json.lobes"
echo '{"lobes": [{"dir": [0, 1, 0], "lambda": 10, "rgb": [0.50505, 0.50505, 0.50505]}, {"dir": [0, 1, 0], "lambda": 10, "rgb": [0.50505, 0.50505, 0.50505]}]}' > "$D/two.json.lobes"
# a narrow coloured lobe and a broad one; then the narrow one cut into two coincident lobes of
# other colours that sum to it
echo '{"lobes": [{"dir": [0, 1, 0], "lambda": 0.2, "rgb": [3, 2, 1]}, {"dir": [0.6, 0, 0.8], "lambda": 0.5, "rgb": [1, 1, 1]}]}' > "$D/na.json.lobes"
echo '{"lobes": [{"dir": [0, 1, 0], "lambda": 0.2, "rgb": [1, 1, 0.5]}, {"dir": [0.6, 0, 0.8], "lambda": 0.5, "rgb": [1, 1, 1]}, {"dir": [0, 1, 0], "lambda": 0.2, "rgb": [2, 1, 0.5]}]}' > "$D/nb.json.lobes"
# the broad one cut into two coincident lobes of other colours that sum to it
echo '{"lobes": [{"dir": [0.6, 0, 0.8], "lambda": 0.5, "rgb": [0.25, 0.5, 0.75]}, {"dir": [0, 1, 0], "lambda": 0.2, "rgb": [3, 2, 1]}, {"dir": [0.6, 0, 0.8], "lambda": 0.5, "rgb": [0.75, 0.5, 0.25]}]}' > "$D/nc.json.lobes"
scene fit '{"file": "white.hdr"}'
scene fit_sparse '{"file": "white.hdr"}' 800
scene fit_dense '{"file": "white.hdr"}' 8000
for n in one two na nb nc; do scene "$n" "{\"lobes\": \"$n.json.lobes\"}"; done

csv() { "$SL" compare "$1" "$2" --csv 2>/dev/null; }
field() { awk -F, -v k="$1" -v c="$2" '$1 == k {print $c}'; } # field KEY COLUMN < csv
within() { awk -v x="$1" -v lo="$2" -v hi="$3" 'BEGIN {exit !(x >= lo && x <= hi)}'; }

# White furnace: mean premultiplied colour / mean coverage over hair pixels, at three densities
# (800, 4000, 8000 strands). Target 1 within 5 % (issue 19). Measured 1.002 / 0.987 / 0.979 with
# the stack around each fragment and the sub-lobes' width (session 10; before: 1.310 / 0.966 /
# 0.809, the sparse hair too bright with Zinke's semi-infinite medium behind every point, the
# dense too dark without the light reflected between layers: docs/volume.md, "The stack behind
# and in front of a fragment"). Checked within 0.05.
for v in fit_sparse fit fit_dense; do
    c=$(csv "$D/$v.exr" "$D/$v.exr")
    m=$(printf '%s\n' "$c" | field mean_ours 2); a=$(printf '%s\n' "$c" | field mean_alpha_ours 5)
    r=$(awk -v m="$m" -v a="$a" 'BEGIN {if (a > 0) printf "%.4f", m / a}')
    n=physical_white_furnace; [ "$v" = fit ] || n="physical_white_furnace_${v#fit_}"
    if [ -n "$r" ] && within "$r" 0.95 1.05; then pass "$n"
    else fail "$n" "mean / coverage '$r' (m '$m', a '$a'), want 1 within 0.05"; fi
done

# The same light cut into other lobes: a narrow lobe cut into two coincident lobes of other
# colours (every pass sees the same directions), a broad lobe cut likewise, and the near-uniform
# light as one broad lobe or as two coincident halves (the broad lobes are fitted together by one
# set of sub-lobes, host/lighting/lobe_subdivide.h, so every cut gives the same sub-lobes). The
# image is the same up to float rounding of the sums and the per-point lobe threshold: measured
# per-pixel rel. RMSE 0.013, 0.000 and 0.000; checked at 0.03. (Before the joint fit each broad
# lobe was subdivided on its own: one lobe got 12 sub-lobes, each half 6, and the halves' image
# was 0.17 per pixel from the whole lobe's.)
for p in "nb na narrow" "nc na broad" "two one broad_halves"; do
    set -- $p
    e=$(csv "$D/$1.exr" "$D/$2.exr" | field rel_rmse_px_raw 5)
    if [ -n "$e" ] && within "$e" 0 0.03; then pass "physical_lobe_cut_$3"
    else fail "physical_lobe_cut_$3" "$1 vs $2: per-pixel rel. RMSE '$e', want <= 0.03"; fi
done

# The near-uniform light as one broad lobe and as the 24 lobes fitted to the white map (another
# light, close to it: the fit's rel. L2 is a few %): mean colour within 3 % (issue 19's target;
# measured 0.987), 8 x 8 blocks within 0.04 (measured 0.014, per pixel 0.014; before session 10
# 0.080 and 0.110: the 24 fitted lobes, all broad, kept one map each, the lone lobe got
# sub-lobes).
c=$(csv "$D/one.exr" "$D/fit.exr")
q=$(printf '%s\n' "$c" | field ratio 2); b=$(printf '%s\n' "$c" | field rel_rmse_blocks_raw 5)
if [ -n "$q" ] && [ -n "$b" ] && within "$q" 0.97 1.03 && within "$b" 0 0.04; then
    pass physical_lobe_one_vs_fitted_map
else fail physical_lobe_one_vs_fitted_map "mean ratio '$q' (want 1 within 0.03), 8x8 blocks '$b' (want <= 0.04)"; fi
