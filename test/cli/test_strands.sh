# test_strands.sh: per-strand sigma_a in `strandlight render` (material.strand_sigma_a, docs/formats.md)
# and the planner-threshold keys (quality.*_threshold): a CSV of overrides renders and the plan
# says so (view and light unaffected), a painted frame differs from the plain one, bad CSV rows
# and "colors" on a hair without colours give one-line errors and no output, thresholds are
# validated and cited by --explain.
. test/cli/lib.sh
D="$TMP/strands"
rm -rf "$D"; mkdir -p "$D"
cat > "$D/lobes.json" <<'JSON'
{"lobes": [{"dir": [0, 1, 0], "lambda": 0.5, "rgb": [1, 0.9, 0.8]},
           {"dir": [0.6, 0, 0.8], "lambda": 0.8, "rgb": [0.4, 0.5, 0.6]}]}
JSON
scene() { # scene NAME MATERIAL_EXTRA QUALITY
    cat > "$D/$1.json" <<JSON
{
  "hair": {"procedural": {"style": "wavy", "strands": 120, "points": 8, "seed": 2}, "radius": 0.04},
  "material": {"eta": 1.55, "sigma_a": [0.18, 0.32, 0.62]$2},
  "environment": {"lobes": "lobes.json"},
  "image": {"width": 48, "height": 36},
  "quality": {"multiple_scattering": "off"$3},
  "output": {"exr": "out/$1.exr"}
}
JSON
}
printf 'strand,sigma_a_r,sigma_a_g,sigma_a_b\n' > "$D/paint.csv"
for s in $(seq 0 2 119); do printf '%d,9,9,9\n' "$s" >> "$D/paint.csv"; done
scene plain "" ""
scene painted ', "strand_sigma_a": "paint.csv"' ""
out=$("$SL" render "$D/painted.json" --device c --explain 2>/dev/null); rc=$?
if [ $rc -eq 0 ] && printf '%s\n' "$out" | grep -q '^shade .*per-strand sigma_a'; then pass strands_csv_renders
else fail strands_csv_renders "rc=$rc $(printf '%s' "$out" | grep '^shade')"; fi
expect_ok strands_plain_renders "$SL" render "$D/plain.json" --device c
if [ ! -f "$D/out/plain.exr" ] || [ ! -f "$D/out/painted.exr" ]; then
    fail strands_paint_changes_frame "no output: $(ls "$D/out" 2>&1)"
elif cmp -s "$D/out/plain.exr" "$D/out/painted.exr"; then
    fail strands_paint_changes_frame "the painted frame equals the plain one: per-strand sigma_a ignored"
else pass strands_paint_changes_frame; fi

# bad CSV rows: one line naming the file and the line, no output
printf 'strand,sigma_a_r,sigma_a_g,sigma_a_b\n1,1,1,1\n500,1,1,1\n' > "$D/range.csv"
scene range ', "strand_sigma_a": "range.csv"' ""
expect_error strands_csv_out_of_range "range.csv:3: strand 500: out of range (the hair has 120 strands)" "$SL" render "$D/range.json" --device c
printf 'strand,sigma_a_r,sigma_a_g,sigma_a_b\n1,1,oops,1\n' > "$D/nan.csv"
scene nan ', "strand_sigma_a": "nan.csv"' ""
expect_error strands_csv_not_a_number "nan.csv:2: sigma_a_g: 'oops' is not a number" "$SL" render "$D/nan.json" --device c
scene missing ', "strand_sigma_a": "nope.csv"' ""
expect_error strands_csv_missing "nope.csv" "$SL" render "$D/missing.json" --device c
scene colors ', "strand_sigma_a": "colors"' ""
expect_error strands_colors_without_colours "has no per-point colours" "$SL" render "$D/colors.json" --device c
bad=""
for n in range nan missing colors; do [ -e "$D/out/$n.exr" ] && bad="$bad $n"; done
if [ -z "$bad" ]; then pass strands_errors_no_output; else fail strands_errors_no_output "written:$bad"; fi
no_leftovers strands_no_temp "$D/out"

# thresholds: validated, and --explain cites the keys
scene thr "" ', "lobe_threshold": 0.5'
out=$("$SL" render "$D/thr.json" --device c --explain 2>/dev/null)
if printf '%s\n' "$out" | grep -q '^lobes  *skipped.*1 of 2 lobes below 0.5 .*quality.lobe_threshold'; then pass strands_lobe_threshold_key
else fail strands_lobe_threshold_key "$(printf '%s' "$out" | grep '^lobes')"; fi
scene badthr "" ', "ms_auto_threshold": 2'
expect_error strands_bad_threshold "quality.ms_auto_threshold: must be in [0, 1]" "$SL" render "$D/badthr.json" --device c
