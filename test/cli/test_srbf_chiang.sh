# test_srbf_chiang.sh: model chiang on the renderer's SRBF fast path (docs/srbf.md, "Chiang fast
# path"): `eval srbf` output columns on c and opencl, --method xu and the table refused for it,
# pole invariance in phi_j, C against OpenCL; `render` of a chiang scene on C and on the OpenCL
# device (the plan names the path), xu / table refused; and multiple scattering running for
# chiang and deon when the scene asks for it. The values against an independent double computation are the unit tests'
# (test/passes/shade/test_srbf_chiang.c).
. test/cli/lib.sh
D="$TMP/srbf_chiang"
rm -rf "$D"
mkdir -p "$D"
if [ -z "${PY:-}" ]; then
    if [ -x /usr/bin/python3 ]; then PY=/usr/bin/python3; else PY=python3; fi
fi
printf '{"model": "chiang", "sigma_a": 0.4, "roughness": 0.25, "radial_roughness": 0.4}\n' > "$D/ch.json"
printf '{"model": "chiang"}\n' > "$D/ch_rgb.json"
# rows: a TT-dominated forward lobe, an R lobe on the cone, a wide lobe, and the same view with
# the lobe at the pole for two phi_j (rows 4 and 5)
printf 'theta_o,phi_o,theta_j,phi_j,lambda\n0.3,0.5,-0.2,2.8,0.2\n0.3,0.5,-0.3,0.6,0.1\n0,1,0.1,-2,1\n-0.5,0.3,1.5707963267948966,0.2,0.4\n-0.5,0.3,1.5707963267948966,-2.5,0.4\n' > "$D/in.csv"

expect_output srbf_chiang_fast_header "lambda,I_0,I_1,I_2,I_rest,I" \
    sh -c "'$SL' eval srbf --backend c --material '$D/ch.json' < '$D/in.csv'"
expect_output srbf_chiang_fast_rgb_header "I_0_r,I_1_r,I_2_r,I_rest_r,I_r,I_0_g" \
    sh -c "'$SL' eval srbf --backend c --method fast --material '$D/ch_rgb.json' < '$D/in.csv'"
expect_error srbf_chiang_xu_refused "model chiang has --method fast" \
    sh -c "'$SL' eval srbf --backend c --method xu --material '$D/ch.json' < '$D/in.csv'"
expect_error srbf_chiang_table_refused "eval: srbf --method table prints the Marschner columns only; model chiang" \
    sh -c "'$SL' eval srbf --backend c --method table --material '$D/ch.json' < '$D/in.csv'"

fast=$("$SL" eval srbf --backend c --material "$D/ch.json" < "$D/in.csv" 2>/dev/null)
# every row finite, > 0, I the sum of its parts; rows 4 and 5 (the pole) equal
if printf '%s\n' "$fast" | "$PY" -c '
import math, sys
rows = [l.split(",") for l in sys.stdin.read().split("\n")[1:] if l]
ok = len(rows) == 5
for r in rows:
    v = [float(x) for x in r[5:10]]
    ok = ok and all(math.isfinite(x) and x >= 0 for x in v) and v[4] > 0
    ok = ok and abs(sum(v[:4]) - v[4]) <= 1e-6 * v[4]
a, b = float(rows[3][9]), float(rows[4][9])
sys.exit(0 if ok and abs(a - b) <= 1e-5 * a else 1)'; then pass srbf_chiang_rows_and_pole
else fail srbf_chiang_rows_and_pole "$fast"; fi

# C twin against the OpenCL kernel (same header; float rounding only: 1e-4 relative of I)
if ! oc=$("$SL" eval srbf --backend opencl --device "$SL_CL_DEVICE" --material "$D/ch.json" < "$D/in.csv" 2>"$D/oc.err"); then
    cl_skip srbf_chiang_c_vs_opencl "$(tail -1 "$D/oc.err")"
elif "$PY" -c '
import sys
a = [l.split(",") for l in sys.argv[1].split("\n")[1:] if l]
b = [l.split(",") for l in sys.argv[2].split("\n")[1:] if l]
ok = len(a) == len(b) == 5
for x, y in zip(a, b):
    tot = float(x[9])
    ok = ok and all(abs(float(p) - float(q)) <= 1e-4 * tot for p, q in zip(x[5:10], y[5:10]))
sys.exit(0 if ok else 1)' "$fast" "$oc"; then pass srbf_chiang_c_vs_opencl
else fail srbf_chiang_c_vs_opencl "c: $fast opencl: $oc"; fi

# render: a chiang scene on C and on the OpenCL device, the plan names the path (the images'
# agreement is test/plan/test_frame_chiang.c's)
cat > "$D/lobes.json" <<'JSON'
{"lobes": [{"dir": [0, 1, 0], "lambda": 0.5, "rgb": [1, 0.9, 0.8]},
           {"dir": [0.6, 0, 0.8], "lambda": 0.2, "rgb": [0.4, 0.5, 0.6]}]}
JSON
scene() { # scene NAME MATERIAL MS
    cat > "$D/$1.json" <<JSON
{"hair": {"procedural": {"style": "wavy", "strands": 200, "points": 10, "seed": 3}},
 "material": $2,
 "environment": {"lobes": "lobes.json"}, "image": {"width": 48, "height": 36},
 "quality": {"multiple_scattering": "$3"}}
JSON
}
scene chiang '{"model": "chiang", "melanin": 0.3, "radial_roughness": 0.35}' auto
scene chiang_ms '{"model": "chiang", "melanin": 0.3}' on
scene deon_ms '{"model": "deon", "sigma_a": [0.2, 0.35, 0.7]}' on
# a cache directory of the test's own: a table another run left in the user's cache would turn
# auto's choice for one frame from fast into the table
export SL_CACHE_DIR="$D/cache"
out=$("$SL" render "$D/chiang.json" --device c --exr "$D/chiang_c.exr" --explain 2>&1); rc=$?
if [ "$rc" -ne 0 ]; then fail render_chiang_c "exit $rc: $(printf '%s' "$out" | tail -3)"
elif ! printf '%s\n' "$out" | grep -q "^srbf .*no table: auto: fast: a build"; then
    fail render_chiang_c "the plan does not say why fast: $(printf '%s\n' "$out" | grep '^srbf')"
else pass render_chiang_c; fi
expect_error render_chiang_xu "material model chiang: --method xu exists for the Marschner model only" \
    "$SL" render "$D/chiang.json" --device c --method xu --exr "$D/chiang_xu.exr"
# Ren's table baked from chiang's own fast path (docs/srbf_ren.md, "Models deon and chiang"): the
# plan says so, and the frame is the fast frame's within the table's error (default table:
# image error ~0.005 against fast on the goal scene; bound 0.03 rel. RMSE of the pixels, which a
# table of the wrong model or a mode in the wrong block exceeds many times over)
out=$("$SL" render "$D/chiang.json" --device c --method table --exr "$D/chiang_table.exr" --explain 2>&1); rc=$?
if [ "$rc" -ne 0 ]; then fail render_chiang_table "exit $rc: $(printf '%s' "$out" | tail -3)"
elif ! printf '%s\n' "$out" | grep -q '^shade .*SRBF table on C'; then
    fail render_chiang_table "the plan does not say table: $(printf '%s\n' "$out" | grep -E '^(srbf|shade)')"
else
    cmp_out=$("$SL" compare "$D/chiang_table.exr" "$D/chiang_c.exr" 2>&1)
    err=$(printf '%s\n' "$cmp_out" | awk '/^rel RMSE pixels, raw/ {print $NF}')
    if [ -z "$err" ] || ! awk -v e="$err" 'BEGIN { exit !(e > 0 && e <= 0.03) }'; then
        fail render_chiang_table "table vs fast rel. RMSE '$err' (bound 0.03): $(printf '%s' "$cmp_out" | tail -3)"
    else pass render_chiang_table; fi
fi
if have_cl; then
    out=$("$SL" render "$D/chiang.json" --device "$SL_CL_DEVICE" --exr "$D/chiang_cl.exr" --explain 2>&1); rc=$?
    if [ "$rc" -ne 0 ]; then fail render_chiang_opencl "exit $rc: $(printf '%s' "$out" | tail -3)"
    elif ! printf '%s\n' "$out" | grep -q '^shade .* on OpenCL'; then
        fail render_chiang_opencl "the plan does not say OpenCL: $(printf '%s\n' "$out" | grep '^shade')"
    else pass render_chiang_opencl; fi
else
    skip render_chiang_opencl "no OpenCL device"
fi

# multiple_scattering: on: chiang and deon have their own dual-scattering terms now
# (kernels/dual_ec.h): the plan runs the ms and volume passes and prints no "not available"
# notice (this test wanted that notice while the terms were Marschner's only)
for m in chiang deon; do
    out=$("$SL" render "$D/${m}_ms.json" --device c --exr "$D/${m}_ms.exr" --explain 2>&1); rc=$?
    if [ "$rc" -ne 0 ]; then fail "render_${m}_ms_runs" "exit $rc: $out"
    elif printf '%s\n' "$out" | grep -q "not yet available"; then fail "render_${m}_ms_runs" "$out"
    elif ! printf '%s\n' "$out" | grep -q '^ms  *run'; then
        fail "render_${m}_ms_runs" "no ms pass run: $(printf '%s\n' "$out" | grep '^ms')"
    elif ! printf '%s\n' "$out" | grep -q '^volume  *run'; then
        fail "render_${m}_ms_runs" "no volume pass run: $(printf '%s\n' "$out" | grep '^volume')"
    elif [ ! -s "$D/${m}_ms.exr" ]; then fail "render_${m}_ms_runs" "no image"
    else pass "render_${m}_ms_runs"; fi
done
