# test_render.sh: `strandlight render` (docs/frame.md) on a tiny scene (lobes from a file, 48x36):
# AOV channels present in the EXR, --explain's plan (an orbit frame reuses every light pass; dark
# hair skips multiple scattering), --orbit N --frames A:B halves byte-identical to one full run,
# and bad input: a one-line error and no output file.
. test/cli/lib.sh
D="$TMP/render"
rm -rf "$D"; mkdir -p "$D"
cat > "$D/lobes.json" <<'JSON'
{"lobes": [{"dir": [0, 1, 0], "lambda": 0.5, "rgb": [1, 0.9, 0.8]},
           {"dir": [0.6, 0, 0.8], "lambda": 0.8, "rgb": [0.4, 0.5, 0.6]}]}
JSON
scene() { # scene NAME SIGMA_A EXTRA_OUTPUT
    cat > "$D/$1.json" <<JSON
{
  "hair": {"procedural": {"style": "wavy", "strands": 120, "points": 8, "seed": 2}, "radius": 0.04},
  "material": {"eta": 1.55, "sigma_a": $2},
  "environment": {"lobes": "lobes.json"},
  "image": {"width": 48, "height": 36},
  "quality": {"multiple_scattering": "auto"},
  "output": {"exr": "out/$1.exr"$3}
}
JSON
}
scene tiny "[0.18, 0.32, 0.62]" ', "aovs": ["R", "TT", "TRT", "MS", "shadow", "lobes"]'
scene dark "8.0" ""
scene plain "[0.18, 0.32, 0.62]" ""

# AOVs from the scene: every channel name is in the EXR header (stored as plain strings)
expect_ok render_tiny "$SL" render "$D/tiny.json" --device c
miss=""
for c in R G B A Z R_mode.R R_mode.G R_mode.B TT.R TT.G TT.B TRT.R TRT.G TRT.B MS.R MS.G MS.B shadow.Y lobes.Y; do
    head -c 2000 "$D/out/tiny.exr" | tr '\0' '\n' | grep -qx -- "$c" || miss="$miss $c"
done
if [ -z "$miss" ]; then pass render_aovs_present; else fail render_aovs_present "missing:$miss"; fi
# without output.aovs: only beauty, alpha and depth
expect_ok render_plain "$SL" render "$D/plain.json" --device c
if head -c 2000 "$D/out/plain.exr" | tr '\0' '\n' | grep -qx 'TT.R'; then
    fail render_no_aovs_by_default "TT.R written without being asked"
else
    pass render_no_aovs_by_default
fi
# --aov on the command line
expect_ok render_aov_option "$SL" render "$D/plain.json" --device c --aov TT,shadow --exr "$D/out/opt.exr"
if head -c 2000 "$D/out/opt.exr" | tr '\0' '\n' | grep -qx 'shadow.Y'; then pass render_aov_option_channel; else fail render_aov_option_channel "no shadow.Y"; fi
no_leftovers render_no_temp "$D/out"

# --explain: the planner's decisions
out=$("$SL" render "$D/dark.json" --device c --explain 2>/dev/null)
if printf '%s\n' "$out" | grep -q '^ms  *skipped.*dark hair'; then pass render_explain_dark_skips_ms
else fail render_explain_dark_skips_ms "$(printf '%s' "$out" | grep '^ms')"; fi
out=$("$SL" render "$D/plain.json" --device c --explain --orbit 3 --exr "$D/orbit/o.exr" 2>/dev/null)
n_run=$(printf '%s\n' "$out" | grep -c '^light  *run')
n_cached=$(printf '%s\n' "$out" | grep -c '^light  *cached')
if [ "$n_run" -eq 1 ] && [ "$n_cached" -eq 2 ]; then pass render_orbit_reuses_light
else fail render_orbit_reuses_light "light run $n_run, cached $n_cached (want 1, 2)"; fi
if [ -f "$D/orbit/o_0000.exr" ] && [ -f "$D/orbit/o_0002.exr" ]; then pass render_orbit_files
else fail render_orbit_files "$(ls "$D/orbit" 2>&1)"; fi

# --frames: two halves of a 4-frame orbit, in two processes, equal one full run byte for byte
"$SL" render "$D/plain.json" --device c --orbit 4 --exr "$D/full/f.exr" 2>/dev/null
"$SL" render "$D/plain.json" --device c --orbit 4 --frames 0:2 --exr "$D/half/f.exr" 2>/dev/null &
"$SL" render "$D/plain.json" --device c --orbit 4 --frames 2:4 --exr "$D/half/f.exr" 2>/dev/null
wait
bad=""
for i in 0000 0001 0002 0003; do cmp -s "$D/full/f_$i.exr" "$D/half/f_$i.exr" || bad="$bad $i"; done
if [ -z "$bad" ]; then pass render_frames_halves_equal_full; else fail render_frames_halves_equal_full "differ:$bad"; fi

# bad input: one line, exit 1 (or 2 for usage), no output file
printf '{"hair": {"procedural": {"strands": 10}}, "camera": {"fov_deg": "wide"}, "environment": {"lobes": "lobes.json"}, "output": {"exr": "out/bad.exr"}}\n' > "$D/bad.json"
expect_error render_bad_scene "camera.fov_deg" "$SL" render "$D/bad.json" --device c
if [ -e "$D/out/bad.exr" ]; then fail render_bad_scene_no_output "out/bad.exr exists"; else pass render_bad_scene_no_output; fi
printf '{"hair": {"procedural": {"strands": 10}}, "environment": {"lobes": "missing.json"}, "output": {"exr": "out/bad2.exr"}}\n' > "$D/bad2.json"
expect_error render_missing_lobes "missing.json" "$SL" render "$D/bad2.json" --device c
if [ -e "$D/out/bad2.exr" ]; then fail render_missing_lobes_no_output "exists"; else pass render_missing_lobes_no_output; fi
"$SL" render "$D/plain.json" --frames 0:1 >/dev/null 2>&1
if [ $? -eq 2 ]; then pass render_frames_needs_orbit; else fail render_frames_needs_orbit "exit not 2"; fi
"$SL" render "$D/plain.json" --orbit 2 --frames 1:3 >/dev/null 2>&1
if [ $? -eq 2 ]; then pass render_frames_range; else fail render_frames_range "exit not 2"; fi
"$SL" render "$D/plain.json" --shading-rate vertex:0 >/dev/null 2>&1
if [ $? -eq 2 ]; then pass render_bad_rate; else fail render_bad_rate "exit not 2"; fi

# SRBF method (docs/frame.md, "SRBF method"), own table cache: auto keeps fast for one frame
# (a build would not pay off), --method table builds and caches the table, the next auto run
# loads it; an unknown method is a usage error
M="$D/method"
mkdir -p "$M"
out=$(SL_CACHE_DIR="$M/cache" "$SL" render "$D/plain.json" --device c --explain --exr "$M/a.exr" 2>/dev/null)
if printf '%s\n' "$out" | grep -q '^srbf  *skipped.*would not pay off'; then pass render_method_auto_fast
else fail render_method_auto_fast "$(printf '%s' "$out" | grep '^srbf')"; fi
out=$(SL_CACHE_DIR="$M/cache" "$SL" render "$D/plain.json" --device c --explain --method table --exr "$M/t.exr" 2>/dev/null)
if printf '%s\n' "$out" | grep -q '^srbf  *run.*built' && printf '%s\n' "$out" | grep -q 'SRBF table on C'; then
    pass render_method_table_builds
else fail render_method_table_builds "$(printf '%s' "$out" | grep -E '^(srbf|shade)')"; fi
out=$(SL_CACHE_DIR="$M/cache" "$SL" render "$D/plain.json" --device c --explain --exr "$M/a2.exr" 2>/dev/null)
if printf '%s\n' "$out" | grep -q '^srbf  *run.*disk cache'; then pass render_method_auto_loads_cached
else fail render_method_auto_loads_cached "$(printf '%s' "$out" | grep '^srbf')"; fi
err=$("$SL" render "$D/plain.json" --device c --method exact 2>&1 >/dev/null); rc=$?
if [ "$rc" -eq 2 ] && printf '%s' "$err" | grep -q 'expected auto, fast, xu or table'; then
    pass render_method_unknown
else fail render_method_unknown "exit $rc: $err"; fi

# model deon renders with the d'Eon fast SRBF path (single scattering; no dual-scattering terms
# for deon, docs/dual.md) on C and OpenCL; xu and the table are Marschner-only usage errors.
cat > "$D/deon.json" <<JSON
{"hair": {"procedural": {"style": "wavy", "strands": 200, "points": 10, "seed": 3}},
 "material": {"model": "deon", "sigma_a": [0.2, 0.35, 0.7]},
 "environment": {"lobes": "lobes.json"}, "image": {"width": 48, "height": 36}}
JSON
expect_output render_deon_plan "model deon" sh -c "'$SL' render '$D/deon.json' --device c --exr '$D/deon_c.exr' --explain 2>&1"
expect_error render_deon_xu "--method xu exists for the Marschner model only" \
    "$SL" render "$D/deon.json" --device c --method xu --exr "$D/deon_xu.exr"
if have_cl; then
    # on the test device, and the plan names it: the shading did run there
    out=$("$SL" render "$D/deon.json" --device "$SL_CL_DEVICE" --exr "$D/deon_cl.exr" --explain 2>&1); rc=$?
    if [ "$rc" -ne 0 ]; then fail render_deon_opencl "exit $rc: $(printf '%s' "$out" | tail -3)"
    elif ! printf '%s\n' "$out" | grep -q '^shade .* on OpenCL'; then
        fail render_deon_opencl "the plan does not say OpenCL: $(printf '%s\n' "$out" | grep '^shade')"
    else pass render_deon_opencl; fi
else
    skip render_deon_opencl "no OpenCL device"
fi

# quality.segments_m is Xu's m: under --method xu m = 1 and m = 4 must give different images (it
# used to be parsed and then ignored, every m rendering as 4)
for m in 1 4; do
    sed "s/\"multiple_scattering\": \"auto\"/\"multiple_scattering\": \"off\", \"segments_m\": $m/" \
        "$D/plain.json" > "$D/seg$m.json"
    "$SL" render "$D/seg$m.json" --device c --method xu --exr "$D/seg$m.exr" 2>/dev/null
done
if [ -s "$D/seg1.exr" ] && [ -s "$D/seg4.exr" ] && ! cmp -s "$D/seg1.exr" "$D/seg4.exr"; then
    pass render_segments_m_honoured
else fail render_segments_m_honoured "segments_m 1 and 4 rendered the same image (or none)"; fi

# -o names the EXR; an EXR named on the command line writes no PNG unless --png is given (the
# scene's output.png would have been overwritten by a render asked for elsewhere)
scene withpng "[0.18, 0.32, 0.62]" ', "png": "out/withpng.png"'
rm -rf "$D/out"
expect_ok render_o_exr "$SL" render "$D/withpng.json" --device c -o "$D/o.exr"
if [ -s "$D/o.exr" ] && [ ! -e "$D/out/withpng.png" ]; then pass render_o_no_scene_png
else fail render_o_no_scene_png "o.exr missing or the scene's PNG written"; fi
expect_ok render_o_png "$SL" render "$D/withpng.json" --device c -o "$D/o2.exr" --png "$D/o2.png"
if [ -s "$D/o2.png" ]; then pass render_o_with_png; else fail render_o_with_png "no PNG"; fi

# --exposure / output.exposure change the PNG preview only (the EXR stays linear radiance);
# a darker exposure gives a darker PNG
expect_ok render_exposure0 "$SL" render "$D/plain.json" --device c -o "$D/e0.exr" --png "$D/e0.png"
expect_ok render_exposure_m2 "$SL" render "$D/plain.json" --device c -o "$D/e2.exr" --png "$D/e2.png" --exposure -2
if cmp -s "$D/e0.exr" "$D/e2.exr" && ! cmp -s "$D/e0.png" "$D/e2.png"; then pass render_exposure_png_only
else fail render_exposure_png_only "EXR changed or PNG unchanged"; fi
sed 's/"output": {/"output": {"exposure": -2, /' "$D/plain.json" > "$D/expo.json"
expect_ok render_exposure_key "$SL" render "$D/expo.json" --device c -o "$D/e3.exr" --png "$D/e3.png"
if cmp -s "$D/e2.png" "$D/e3.png"; then pass render_exposure_key_same; else fail render_exposure_key_same "output.exposure -2 differs from --exposure -2"; fi
err=$("$SL" render "$D/plain.json" --device c --exposure x -o "$D/e4.exr" 2>&1); rc=$?
if [ "$rc" -eq 2 ] && printf '%s' "$err" | grep -q -- '--exposure: expected stops' && [ ! -e "$D/e4.exr" ]; then
    pass render_exposure_bad # a usage error: exit 2
else fail render_exposure_bad "exit $rc: $err"; fi
sed 's/"output": {/"output": {"exposure": "bright", /' "$D/plain.json" > "$D/expob.json"
expect_error render_exposure_key_bad "output.exposure: expected a number" "$SL" render "$D/expob.json" --device c -o "$D/e5.exr"

# outputs are validated before the work: an empty path, a directory, a tree of missing
# directories are one-line errors (exit 1) and nothing is rendered or created
expect_error render_out_empty "--exr: empty output path" "$SL" render "$D/plain.json" --device c --exr ""
expect_error render_out_dir "is a directory, expected a file" "$SL" render "$D/plain.json" --device c -o "$D"
expect_error render_out_deep "does not exist (only one missing level is created)" \
    "$SL" render "$D/plain.json" --device c -o "$D/no/such/dir/x.exr"
if [ ! -e "$D/no" ]; then pass render_out_deep_nothing_created; else fail render_out_deep_nothing_created "created $D/no"; fi

# render - : the scene on standard input, relative paths from the working directory
SLABS=$(cd "$(dirname "$SL")" && pwd)/$(basename "$SL")
(cd "$D" && "$SLABS" render - --device c -o stdin.exr < plain.json 2>/dev/null)
if [ -s "$D/stdin.exr" ]; then pass render_stdin; else fail render_stdin "no stdin.exr"; fi
err=$(printf '{"hair": {}}' | "$SL" render - --device c -o "$D/stdin2.exr" 2>&1); rc=$?
if [ "$rc" -eq 1 ] && printf '%s' "$err" | grep -q '^strandlight: <stdin>: hair: '; then pass render_stdin_error
else fail render_stdin_error "exit $rc: $err"; fi
