# test_report.sh: `strandlight report SCENE.json --quick --tiny` end to end on a small scene
# (300 procedural strands, the repository's city map fitted with 8 lobes, 48 px wide, reference
# 8 lights aa 2 with the light split): the report directory holds results.csv, report.md and
# error_vs_time.svg (rel_rmse_4x4 column included), the CSV has the documented columns and the
# reference row, every error is finite, a second run reuses the cached reference (same
# reference time), nothing temporary is left, and a bad scene gives a one-line error and no
# report directory. The fragment reference (8 lights): its row reference_fragments (time, own
# N-vs-2N error), the rel_rmse_frag* and pareto_frag columns finite on every fast run, its
# image, its front and target sentences in report.md, its markers in the SVG, cached too.
# The error metric itself is checked by unit_tests reference_ (sl_image_error), the fragment
# reference's shading by unit_tests reffrag_.
. test/cli/lib.sh
D="$TMP/report"
rm -rf "$D"
mkdir -p "$D"
ENV="$PWD/data/env/city_256.hdr"
cat >"$D/small.json" <<EOF
{"hair": {"procedural": {"style": "wavy", "strands": 300, "points": 8, "seed": 3}, "radius": 0.06},
 "material": {"eta": 1.55, "sigma_a": [0.18, 0.32, 0.62]},
 "environment": {"file": "$ENV"},
 "camera": {"fov_deg": 30},
 "image": {"width": 640, "height": 480},
 "quality": {"lobes": 8, "multiple_scattering": "on"}}
EOF
printf '{"hair": {"procedural": {"style": "wavy"}}, "bogus": 1}\n' >"$D/badkey.json"

run() { "$SL" report "$@" 2>"$D/stderr"; }

if run "$D/small.json" --quick --tiny -o "$D/out/small" --threads 2 --device none; then
    ok=1
    for f in results.csv report.md error_vs_time.svg; do
        [ -s "$D/out/small/$f" ] || { fail report_writes_files "missing $f"; ok=0; }
    done
    [ "$ok" = 1 ] && pass report_writes_files
    csv="$D/out/small/results.csv"
    # header: the columns the issue asks for, by name
    hdr=$(head -1 "$csv")
    ok=1
    for c in backend lobes layers m kappa voxels ms time_s rel_rmse p99_rel_err rel_rmse_4x4 rel_rmse_R rel_rmse_TT rel_rmse_TRT rel_rmse_MS; do
        printf '%s\n' "$hdr" | tr ',' '\n' | grep -qx "$c" || { fail report_csv_columns "no column $c in: $hdr"; ok=0; }
    done
    [ "$ok" = 1 ] && pass report_csv_columns
    ok=1
    for c in rel_rmse_frag p99_frag rel_rmse_frag_R rel_rmse_frag_TT rel_rmse_frag_TRT rel_rmse_frag_MS pareto_frag rel_rmse_frag_4x4 shading_rate broad_lobes; do
        printf '%s\n' "$hdr" | tr ',' '\n' | grep -qx "$c" || { fail report_csv_frag_columns "no column $c in: $hdr"; ok=0; }
    done
    [ "$ok" = 1 ] && pass report_csv_frag_columns
    # one reference_fragments row with a finite time and own error (in rel_rmse and
    # rel_rmse_frag); every fast run (c/opencl) has a finite rel_rmse_frag, p99_frag and
    # per-mode frag errors; at least one run is on the fragment front
    awk -F, 'function num(v) { return v ~ /^[0-9.]+(e[-+]?[0-9]+)?$/ }
        NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        $col["backend"] == "reference_fragments" { fr++
            if (!num($col["time_s"]) || !num($col["rel_rmse_frag"]) || !num($col["rel_rmse"]) || $col["lights"] != 8) bad = bad " fragrow" }
        $col["backend"] == "c" || $col["backend"] == "opencl" { runs++
            for (k = 0; k < 6; k++) { n = (k == 0 ? "rel_rmse_frag" : k == 1 ? "p99_frag" : k == 2 ? "rel_rmse_frag_R" : k == 3 ? "rel_rmse_frag_TT" : k == 4 ? "rel_rmse_frag_TRT" : "rel_rmse_frag_4x4")
                if (!num($col[n])) bad = bad " " NR ":" n "=" $col[n] }
            if ($col["pareto_frag"] == 1) front++ }
        END { if (fr != 1) { print "reference_fragments rows: " fr; exit 1 }
              if (front < 1) { print "no run on the fragment front"; exit 1 }
              if (bad != "") { print "bad:" bad; exit 1 } }' "$csv" >"$D/awk2.out" \
        && pass report_csv_fragment_row || fail report_csv_fragment_row "$(cat "$D/awk2.out")"
    if grep -q "Pareto front on the fragment metric" "$D/out/small/report.md" \
        && grep -q "Against the fragment reference" "$D/out/small/report.md" \
        && grep -q "Against the pixel reference" "$D/out/small/report.md" \
        && [ -s "$D/out/small/reference_fragments.png" ] \
        && grep -q "#9467bd" "$D/out/small/error_vs_time.svg"; then pass report_fragment_outputs
    else fail report_fragment_outputs "report.md sections, reference_fragments.png or svg markers missing"; fi
    # the reference row (backend reference) and at least 4 fast runs; every time and error
    # finite and >= 0 (awk: a number matches the regex; nan/inf/empty do not)
    awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        { rows++; if ($col["backend"] == "reference") ref++
          for (k = 0; k < 4; k++) { n = (k == 0 ? "time_s" : k == 1 ? "rel_rmse" : k == 2 ? "p99_rel_err" : "rel_rmse_4x4")
              v = $col[n]; if (v !~ /^[0-9.]+(e[-+]?[0-9]+)?$/) bad = bad " " NR ":" n "=" v } }
        END { if (ref != 1) { print "reference rows: " ref; exit 1 }
              if (rows < 5) { print "rows: " rows; exit 1 }
              if (bad != "") { print "not finite:" bad; exit 1 } }' "$csv" >"$D/awk.out" \
        && pass report_csv_reference_row_finite || fail report_csv_reference_row_finite "$(cat "$D/awk.out")"
    # MS on in the scene and in the reference: the base run has a finite MS error
    if awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        $col["backend"] == "c" && $col["ms"] == "on" && $col["rel_rmse_MS"] ~ /^[0-9.]+/ { n++ }
        END { exit n > 0 ? 0 : 1 }' "$csv"; then pass report_csv_ms_aov; else fail report_csv_ms_aov "no MS error"; fi
    grep -q "Pareto front" "$D/out/small/report.md" && grep -q "reference" "$D/out/small/report.md" \
        && pass report_md_sections || fail report_md_sections "report.md lacks sections"
    grep -q "<svg" "$D/out/small/error_vs_time.svg" && grep -q "#d62728" "$D/out/small/error_vs_time.svg" \
        && pass report_svg_front || fail report_svg_front "svg lacks the front"
    # one heat map per Pareto-front row (pareto column 1), plus the reference image
    nfront=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next } $col["pareto"] == 1 { n++ } END { print n + 0 }' "$csv")
    nheat=$(ls "$D/out/small" | grep -c '^heat_.*\.png$')
    if [ "$nfront" -ge 1 ] && [ "$nheat" = "$nfront" ] && [ -s "$D/out/small/reference.png" ]; then pass report_heat_maps
    else fail report_heat_maps "front $nfront, heat maps $nheat"; fi
    no_leftovers report_no_temp_files "$D/out"
    # progress (issue 22): each run's line ends with the sweep's time so far and the time left
    if grep -q '^strandlight: report: run 1/[0-9]*: .*(sweep [0-9]* s, about [0-9]* s left)$' "$D/stderr"; then
        pass report_progress_eta
    else fail report_progress_eta "$(grep 'report: run' "$D/stderr" | head -1)"; fi
    ls "$D/out" | grep -q '\.tmp\.' && fail report_no_temp_dir "$(ls "$D/out")" || pass report_no_temp_dir
    # second run: the reference comes from the cache, so its row (time from the JSON) is equal
    reft1=$(grep '^reference' "$csv")
    if run "$D/small.json" --tiny --quick -o "$D/out/small" --threads 2 --device none; then
        reft2=$(grep '^reference' "$csv")
        [ "$reft1" = "$reft2" ] && pass report_reference_cached || fail report_reference_cached "$reft1 != $reft2"
    else
        fail report_reference_cached "second run: $(tail -2 "$D/stderr")"
    fi
else
    fail report_runs "$(tail -3 "$D/stderr")"
fi

expect_error report_missing_scene "nope.json" "$SL" report "$D/nope.json" --tiny -o "$D/bad1"
[ -e "$D/bad1" ] && fail report_missing_no_dir "$D/bad1 exists" || pass report_missing_no_dir
expect_error report_bad_key "bogus" "$SL" report "$D/badkey.json" --tiny -o "$D/bad2"
[ -e "$D/bad2" ] && fail report_bad_key_no_dir "$D/bad2 exists" || pass report_bad_key_no_dir
