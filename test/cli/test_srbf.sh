# test_srbf.sh: `strandlight eval srbf` (numerics.md sec. 4-5, docs/srbf.md): output columns per
# model and method, method/backend/segments errors, and two value checks computed here, not by
# the code under test: at the pole the answer does not depend on phi_j, and the narrow-lobe limit
# I/int(G) -> f(omega_j, omega_o) against `eval scatter --backend reference`.
. test/cli/lib.sh
D="$TMP/srbf"
mkdir -p "$D"
if [ -z "${PY:-}" ]; then
    if [ -x /usr/bin/python3 ]; then PY=/usr/bin/python3; else PY=python3; fi
fi
printf 'theta_o,phi_o,theta_j,phi_j,lambda\n0.3,0.5,0.2,0.4,0.5\n-1.2,0.5,1.5707963267948966,0.3,0.3\n-1.2,0.5,1.5707963267948966,-2.0,0.3\n' > "$D/in.csv"

expect_output srbf_ref_header "theta_o,phi_o,theta_j,phi_j,lambda,I_R,I_TT,I_TRT,I" \
    sh -c "'$SL' eval srbf --backend reference < '$D/in.csv'"
expect_output srbf_xu_header "theta_o,phi_o,theta_j,phi_j,lambda,I_R,I_TT,I_TRT,I" \
    sh -c "'$SL' eval srbf --backend c --method xu --segments 2 < '$D/in.csv'"
expect_output srbf_fast_default "I_R,I_TT,I_TRT,I" sh -c "'$SL' eval srbf < '$D/in.csv'"
printf '{"model": "deon", "orders": 2}\n' > "$D/deon.json"
printf 'theta_o,phi_o,theta_j,phi_j,lambda\n0.3,0.5,0.2,0.4,0.5\n' > "$D/one.csv"
expect_output srbf_deon_header "lambda,I_0,I_1,I_2,I_rest,I" \
    sh -c "'$SL' eval srbf --backend reference --material '$D/deon.json' < '$D/one.csv'"

expect_usage_srbf() {
    local name=$1 want=$2; shift 2
    local out rc
    out=$("$SL" eval srbf "$@" < "$D/one.csv" 2>&1 >/dev/null); rc=$?
    if [ "$rc" -ne 2 ]; then fail "$name" "exit $rc (want 2): $out"; return; fi
    if ! printf '%s' "$out" | grep -qF -- "$want"; then fail "$name" "stderr '$out' lacks '$want'"; return; fi
    pass "$name"
}
expect_usage_srbf srbf_xu_on_reference "method exact only" --backend reference --method xu
expect_usage_srbf srbf_exact_on_c "needs --backend reference" --backend c --method exact
expect_usage_srbf srbf_segments_range "--segments" --method xu --segments 9
# model deon has a fast path (docs/srbf.md; accuracy in test/cli/test_srbf_deon.sh)
expect_ok srbf_deon_fast sh -c "'$SL' eval srbf --material '$D/deon.json' < '$D/one.csv'"
printf 'theta_o,phi_o,theta_j,phi_j,lambda\n0.3,0.5,0.2,0.4,0\n' > "$D/bad.csv"
expect_error srbf_lambda_positive "lambda: must be > 0" \
    sh -c "'$SL' eval srbf --backend reference < '$D/bad.csv'"

# The pole: rows 2 and 3 differ only in phi_j, which names no direction at theta_j = pi/2.
out=$("$SL" eval srbf --backend reference < "$D/in.csv")
if printf '%s\n' "$out" | "$PY" -c '
import sys
rows = [l.split(",") for l in sys.stdin.read().split("\n")[1:] if l]
a, b = [float(x) for x in rows[1][5:]], [float(x) for x in rows[2][5:]]
sys.exit(0 if all(abs(x - y) <= 1e-6 * a[3] for x, y in zip(a, b)) and a[3] > 0 else 1)'; then
    pass srbf_pole_phi_independent
else fail srbf_pole_phi_independent "$out"; fi

# lambda -> 0: I / (pi l^2 (1 - e^(-4/l^2))) vs f at omega_i = omega_j (tolerance 3e-3: the
# O(lambda^2) bias at lambda = 0.005 is below 1e-3 for the default lobes).
printf 'theta_o,phi_o,theta_j,phi_j,lambda\n0.3,0.5,-0.2,0.15,0.005\n' > "$D/nar.csv"
printf 'theta_i,phi_i,theta_o,phi_o\n-0.2,0.15,0.3,0.5\n' > "$D/sc.csv"
i=$("$SL" eval srbf --backend reference < "$D/nar.csv" | tail -1)
f=$("$SL" eval scatter --backend reference < "$D/sc.csv" | tail -1)
if "$PY" -c '
import math, sys
i = [float(x) for x in sys.argv[1].split(",")]; f = [float(x) for x in sys.argv[2].split(",")]
l = i[4]; g = math.pi * l * l * (1 - math.exp(-4 / l / l))
sys.exit(0 if abs(i[8] / g - f[7]) <= 3e-3 * f[7] else 1)' "$i" "$f"; then
    pass srbf_narrow_limit
else fail srbf_narrow_limit "srbf $i scatter $f"; fi

# C twin against the OpenCL kernel (same header; float rounding only: 1e-4 relative of I).
for meth in xu fast; do
    if ! oc=$("$SL" eval srbf --backend opencl --device "$SL_CL_DEVICE" --method $meth < "$D/in.csv" 2>"$D/oc.err"); then
        cl_skip "srbf_c_vs_opencl_$meth" "$(tail -1 "$D/oc.err")"; continue
    fi
    cc=$("$SL" eval srbf --backend c --method $meth < "$D/in.csv")
    if "$PY" -c '
import sys
a = [l.split(",") for l in sys.argv[1].split("\n")[1:] if l]
b = [l.split(",") for l in sys.argv[2].split("\n")[1:] if l]
ok = len(a) == len(b) == 3
for x, y in zip(a, b):
    t = float(x[8])
    ok = ok and all(abs(float(p) - float(q)) <= 1e-4 * t + 1e-30 for p, q in zip(x[5:], y[5:]))
sys.exit(0 if ok else 1)' "$cc" "$oc"; then pass "srbf_c_vs_opencl_$meth"
    else fail "srbf_c_vs_opencl_$meth" "c: $cc opencl: $oc"; fi
done

# `report --kernel srbf` (host/verify/report/report_srbf.c): on the committed exact values of the stiff sample
# (test/test_srbf_stiff.csv), C only, a 25-row prefix: table, CSV and SVG written atomically;
# rows: fast, xu m = 1..8, Ren's precomputed table (header + 10).
R="$D/report"
mkdir -p "$R"
expect_output srbf_report_table "| fast | - | c |" \
    "$SL" report --kernel srbf --n 25 --exact test/test_srbf_stiff.csv --device none \
    --min-time 0.02 --csv "$R/r.csv" --svg "$R/r.svg"
if [ -s "$R/r.csv" ] && head -1 "$R/r.csv" | grep -q '^method,segments,backend,n,median,p95,max,' &&
    [ "$(wc -l < "$R/r.csv")" -eq 11 ] && grep -q '^table,0,c,' "$R/r.csv" && grep -q '</svg>' "$R/r.svg"; then
    pass srbf_report_files
else fail srbf_report_files "$(head -3 "$R/r.csv" 2>&1)"; fi
no_leftovers srbf_report_no_tmp "$R"
# a stale exact file (another sample) is refused, naming the file and line
sed '2s/^0,0\.9/0,0.8/' test/test_srbf_stiff.csv > "$R/stale.csv"
expect_error srbf_report_stale "stale.csv:2: theta_o" \
    "$SL" report --kernel srbf --n 5 --exact "$R/stale.csv" --device none
expect_usage_report() {
    local name=$1 want=$2; shift 2
    local out rc
    out=$("$SL" report "$@" 2>&1 >/dev/null); rc=$?
    if [ "$rc" -ne 2 ]; then fail "$name" "exit $rc (want 2): $out"; return; fi
    if ! printf '%s' "$out" | grep -qF -- "$want"; then fail "$name" "stderr '$out' lacks '$want'"; return; fi
    pass "$name"
}
expect_error srbf_report_scene_missing "scene.json: No such file" "$SL" report scene.json
expect_usage_report srbf_report_kernel_unknown "unknown kernel 'foo'" --kernel foo
expect_usage_report srbf_report_no_form "expected --kernel srbf"
expect_usage_report srbf_report_bad_n "--n" --kernel srbf --n 0
