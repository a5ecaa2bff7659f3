# test_reference.sh: `strandlight reference` end to end on a tiny scene (32x24, 20 procedural
# strands, a 16x8 sky map cut into 4 lights): it writes a float EXR with the documented
# channels and a JSON record with the convergence (4 vs 8 lights), a second run reuses the
# cached result (no render), the image does not depend on the thread count, and bad input gives
# a one-line error and no output file. --fragments (fragment mode): writes the EXR and a JSON
# with "fragments": true and its convergence on the same fragments, is cached under its own key
# (not the pixel mode's), the same for 1 and 3 threads, and fails with one line without a map.
# The numerics are checked by unit_tests reference_ and reffrag_.
. test/cli/lib.sh
. test/cli/reference_lib.sh
ref_setup reference

"$PY" - "$D" <<'PYEOF'
import sys
d = sys.argv[1]
base = '"hair": {"procedural": {"style": "wavy", "strands": 20, "points": 8, "seed": 2}, "radius": 0.3}, "environment": {"file": "sky.hdr"}, "image": {"width": 32, "height": 24}, "quality": {"multiple_scattering": "%s"}'
open(d + "/scene.json", "w").write("{" + base % "off" + "}\n")
open(d + "/scene_ms.json", "w").write("{" + base % "on" + "}\n")
open(d + "/nomap.json", "w").write('{"hair": {"procedural": {"style": "wavy", "strands": 20, "points": 8}}, "environment": {"lobes": "x.json"}}\n')
open(d + "/badkey.json", "w").write('{"hair": {"procedural": {"style": "wavy"}}, "bogus": 1}\n')
PYEOF

run() { "$SL" reference "$@" 2>"$D/stderr"; }

if run "$D/scene.json" -o "$D/a/ref.exr" --lights 4 --aa 2 --threads 1; then
    if [ -s "$D/a/ref.exr" ] && [ -s "$D/a/ref.exr.json" ]; then pass reference_writes_exr_json; else fail reference_writes_exr_json "missing outputs"; fi
    if grep -q "convergence: 4 vs 8 lights: rel RMSE" "$D/stderr"; then pass reference_convergence_stderr; else fail reference_convergence_stderr "$(cat "$D/stderr")"; fi
else
    fail reference_writes_exr_json "exit $?: $(cat "$D/stderr")"
fi
# The JSON: convergence present and finite, lights = 4; the EXR: float channels R G B A Z ms.*.
msg=$("$PY" - "$D/a/ref.exr.json" <<'PYEOF'
import json, sys, math
r = json.load(open(sys.argv[1]))["reference"]
c = r.get("convergence", {})
bad = []
if r.get("lights") != 4: bad.append("lights %r" % r.get("lights"))
if not (isinstance(c.get("rel_rmse"), (int, float)) and math.isfinite(c["rel_rmse"]) and c["rel_rmse"] > 0): bad.append("rel_rmse %r" % c.get("rel_rmse"))
if c.get("lights_2n") != 8: bad.append("lights_2n")
print("; ".join(bad))
PYEOF
)
if [ -z "$msg" ]; then pass reference_json_fields; else fail reference_json_fields "$msg"; fi
if "$SL" info "$D/a/ref.exr" 2>/dev/null | grep -q "TRT.B"; then pass reference_exr_channels
else fail reference_exr_channels "info does not list the EXR channel TRT.B: $("$SL" info "$D/a/ref.exr" 2>&1 | tr '\n' ' ' | cut -c1-200)"; fi

# Cached: the same inputs give "cached" without rendering, and the EXR is untouched.
before=$(stat -c %Y.%s "$D/a/ref.exr")
sleep 1
if run "$D/scene.json" -o "$D/a/ref.exr" --lights 4 --aa 2 --threads 2 && grep -q "cached" "$D/stderr" && [ "$(stat -c %Y.%s "$D/a/ref.exr")" = "$before" ]; then
    pass reference_cached
else
    fail reference_cached "$(cat "$D/stderr")"
fi
# A different setting is not the cached one.
if run "$D/scene.json" -o "$D/a/ref.exr" --lights 4 --aa 1 --no-convergence && ! grep -q "cached" "$D/stderr"; then
    pass reference_cache_key_settings
else
    fail reference_cache_key_settings "$(cat "$D/stderr")"
fi

# Thread count: byte-identical EXR (same writer, same pixels).
run "$D/scene.json" -o "$D/t1.exr" --lights 4 --threads 1 --no-convergence
run "$D/scene.json" -o "$D/t3.exr" --lights 4 --threads 3 --no-convergence
if [ -s "$D/t1.exr" ] && cmp -s "$D/t1.exr" "$D/t3.exr"; then pass reference_threads_identical; else fail reference_threads_identical "t1.exr and t3.exr differ"; fi

# Multiple scattering on: renders, and the ms channels are recorded.
if run "$D/scene_ms.json" -o "$D/ms.exr" --lights 2 --no-convergence && grep -Eq '"multiple_scattering":[[:space:]]*true' "$D/ms.exr.json"; then
    pass reference_ms_runs
else
    fail reference_ms_runs "$(cat "$D/stderr")"
fi

# Fragment mode.
if run "$D/scene.json" -o "$D/f/ref.exr" --fragments --lights 4 --threads 1 \
    && grep -q "convergence: 4 vs 8 lights" "$D/stderr" && grep -q "fragments:" "$D/stderr" \
    && grep -Eq '"fragments":[[:space:]]*true' "$D/f/ref.exr.json" && grep -q '"oit_k"' "$D/f/ref.exr.json"; then
    pass reference_fragments_runs
else
    fail reference_fragments_runs "$(cat "$D/stderr")"
fi
if run "$D/scene.json" -o "$D/f/ref.exr" --fragments --lights 4 --threads 2 && grep -q "cached" "$D/stderr"; then
    pass reference_fragments_cached
else
    fail reference_fragments_cached "$(cat "$D/stderr")"
fi
# the pixel-mode record at the same path is not a fragment-mode cache hit (and vice versa)
if run "$D/scene.json" -o "$D/f/ref.exr" --lights 4 --no-convergence && ! grep -q "cached" "$D/stderr"; then
    pass reference_fragments_own_key
else
    fail reference_fragments_own_key "$(cat "$D/stderr")"
fi
run "$D/scene.json" -o "$D/f1.exr" --fragments --lights 4 --threads 1 --no-convergence
run "$D/scene.json" -o "$D/f3.exr" --fragments --lights 4 --threads 3 --no-convergence
if [ -s "$D/f1.exr" ] && cmp -s "$D/f1.exr" "$D/f3.exr"; then pass reference_fragments_threads_identical; else fail reference_fragments_threads_identical "f1.exr and f3.exr differ"; fi
expect_error reference_fragments_needs_map "environment.file: the reference needs an environment map" "$SL" reference "$D/nomap.json" --fragments -o "$D/xf.exr"
[ -e "$D/xf.exr" ] && fail reference_fragments_no_output_on_error "xf.exr written" || pass reference_fragments_no_output_on_error
expect_output reference_help_fragments "--fragments" "$SL" reference --help

expect_error reference_needs_map "environment.file: the reference needs an environment map" "$SL" reference "$D/nomap.json" -o "$D/x.exr"
[ -e "$D/x.exr" ] && fail reference_no_output_on_error "x.exr written" || pass reference_no_output_on_error
expect_error reference_bad_scene "bogus" "$SL" reference "$D/badkey.json" -o "$D/y.exr"
[ -e "$D/y.exr" ] && fail reference_no_output_bad_scene "y.exr written" || pass reference_no_output_bad_scene
expect_error reference_missing_scene "nope.json" "$SL" reference "$D/nope.json" -o "$D/z.exr"
"$SL" reference --lights 0 "$D/scene.json" >/dev/null 2>&1; rc=$?
if [ "$rc" = 2 ]; then pass reference_usage_lights; else fail reference_usage_lights "exit $rc (want 2)"; fi
expect_output reference_help "--lights N" "$SL" reference --help
no_leftovers reference_no_temporaries "$D"
no_leftovers reference_no_temporaries_a "$D/a"
no_leftovers reference_no_temporaries_f "$D/f"
