# test_reference_path.sh: `strandlight reference --path` end to end on tiny scenes (procedural
# hair, the 16 x 8 sky map of reference_lib.sh): the EXR's channels and the JSON record (spp,
# seed, wall and CPU time, the noise from even vs odd samples), the cache, the same bytes for 1
# and 2 threads, the time budget, the progress line on a terminal, and bad input: --path with
# pixel-mode options or without a map, a map with NaN pixels (an error unless
# --clamp-nonfinite), and SIGINT (exit 130, nothing written). Numerics: unit_tests path_.
. test/cli/lib.sh
. test/cli/reference_lib.sh
ref_setup reference_path

"$PY" - "$D" <<'PYEOF'
import struct, sys
d = sys.argv[1]
hair = '"hair": {"procedural": {"style": "wavy", "strands": 20, "points": 8, "seed": 2}, "radius": 0.3}'
mat = '"material": {"model": "chiang", "melanin": 0.5}'
img = '"image": {"width": 16, "height": 12}'
open(d + "/scene.json", "w").write("{%s, %s, \"environment\": {\"file\": \"sky.hdr\"}, %s}\n" % (hair, mat, img))
open(d + "/nan.json", "w").write("{%s, %s, \"environment\": {\"file\": \"nan.exr\"}, %s}\n" % (hair, mat, img))
open(d + "/nomap.json", "w").write("{%s, \"environment\": {\"lobes\": \"x.json\"}}\n" % hair)
# an uncompressed float EXR (8 x 4, channels B G R) with one NaN pixel
w, h = 8, 4
def attr(name, typ, data): return name.encode() + b"\0" + typ.encode() + b"\0" + struct.pack("<i", len(data)) + data
ch = b"".join(c.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in "BGR") + b"\0"
box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
hdr = (struct.pack("<ii", 20000630, 2) + attr("channels", "chlist", ch) + attr("compression", "compression", b"\0")
       + attr("dataWindow", "box2i", box) + attr("displayWindow", "box2i", box) + attr("lineOrder", "lineOrder", b"\0")
       + attr("pixelAspectRatio", "float", struct.pack("<f", 1)) + attr("screenWindowCenter", "v2f", struct.pack("<ff", 0, 0))
       + attr("screenWindowWidth", "float", struct.pack("<f", 1)) + b"\0")
lines = []
for y in range(h):
    vals = [float("nan") if (y == 1 and x == 3) else 1.0 for x in range(w)]
    data = b"".join(struct.pack("<%df" % w, *vals) for _ in "BGR")
    lines.append(struct.pack("<ii", y, len(data)) + data)
off = len(hdr) + 8 * h
table = b""
for l in lines:
    table += struct.pack("<Q", off); off += len(l)
open(d + "/nan.exr", "wb").write(hdr + table + b"".join(lines))
PYEOF

run() { "$SL" reference "$@" 2>"$D/stderr"; }

if run "$D/scene.json" --path --spp 8 --threads 1 -o "$D/a/p.exr" && [ -s "$D/a/p.exr" ] && [ -s "$D/a/p.exr.json" ]; then
    pass path_writes_exr_json
else
    fail path_writes_exr_json "exit $?: $(cat "$D/stderr")"
fi
if grep -q "path tracer: 8 spp, seed 1" "$D/stderr"; then pass path_note; else fail path_note "$(cat "$D/stderr")"; fi
msg=$("$PY" - "$D/a/p.exr.json" <<'PYEOF'
import json, sys, math
r = json.load(open(sys.argv[1]))["reference"]
bad = []
if r.get("path") is not True: bad.append("path")
for k, v in (("spp", 8), ("spp_asked", 8), ("seed", 1), ("width", 16), ("height", 12)):
    if r.get(k) != v: bad.append("%s %r" % (k, r.get(k)))
for k in ("time_s", "cpu_s", "paths_per_s"):
    if not (isinstance(r.get(k), (int, float)) and r[k] >= 0): bad.append(k)
n = r.get("noise", {})
for k in ("rel_rmse", "rel_rmse_4x4", "rel_rmse_8x8"):
    if not (isinstance(n.get(k), (int, float)) and math.isfinite(n[k]) and n[k] > 0): bad.append("noise." + k)
if r.get("capped_paths") != 0: bad.append("capped_paths")
print("; ".join(bad))
PYEOF
)
if [ -z "$msg" ]; then pass path_json_fields; else fail path_json_fields "$msg"; fi
# channel names (the header's chlist is plain text; `info` shortens the list)
ok=1
for c in R A Z direct.R indirect.G MS.B R_mode.R TT.G TRT.B rest.R; do
    if ! LC_ALL=C grep -aq "$c" "$D/a/p.exr"; then ok=0; fail path_exr_channels "no channel $c"; fi
done
[ $ok = 1 ] && pass path_exr_channels

before=$(stat -c %Y.%s "$D/a/p.exr")
sleep 1
if run "$D/scene.json" --path --spp 8 --threads 2 -o "$D/a/p.exr" && grep -q "cached" "$D/stderr" && [ "$(stat -c %Y.%s "$D/a/p.exr")" = "$before" ]; then
    pass path_cached
else
    fail path_cached "$(cat "$D/stderr")"
fi

run "$D/scene.json" --path --spp 4 --threads 1 -o "$D/t1.exr"
run "$D/scene.json" --path --spp 4 --threads 2 -o "$D/t2.exr"
if [ -s "$D/t1.exr" ] && cmp -s "$D/t1.exr" "$D/t2.exr"; then pass path_threads_identical; else fail path_threads_identical "t1.exr and t2.exr differ"; fi

# --time: whole passes within the budget, the spp reached recorded
if run "$D/scene.json" --path --time 1 --threads 2 -o "$D/tb.exr" && "$PY" -c "
import json, sys
r = json.load(open('$D/tb.exr.json'))['reference']
sys.exit(0 if r['spp'] >= 1 and r['spp_asked'] == 0 and r['time_budget_s'] == 1 and r['time_s'] < 1.5 else 1)"; then
    pass path_time_budget
else
    fail path_time_budget "$(cat "$D/stderr"; cat "$D/tb.exr.json" 2>/dev/null | tr '\n' ' ' | cut -c1-300)"
fi

# the progress line on a terminal (script(1) gives the command a pseudo-terminal)
if command -v script >/dev/null 2>&1; then
    script -qec "$SL reference $D/scene.json --path --spp 6 --force -o $D/pg.exr" /dev/null > "$D/tty.txt" 2>&1
    if grep -q "spp" "$D/tty.txt" && grep -q "eta" "$D/tty.txt" && grep -q "noise" "$D/tty.txt"; then pass path_progress_tty
    else fail path_progress_tty "$(tr '\r' '\n' < "$D/tty.txt" | tail -3)"; fi
else
    skip path_progress_tty "no script(1)"
fi

# bad input: one-line errors, nothing written
"$SL" reference "$D/scene.json" --path --fragments -o "$D/x1.exr" >/dev/null 2>"$D/stderr"; rc=$?
if [ "$rc" = 2 ] && grep -q "fragments" "$D/stderr" && [ ! -e "$D/x1.exr" ]; then pass path_with_fragments_is_error; else fail path_with_fragments_is_error "exit $rc: $(cat "$D/stderr")"; fi
"$SL" reference "$D/scene.json" --path --lights 8 -o "$D/x2.exr" >/dev/null 2>&1; rc=$?
if [ "$rc" = 2 ] && [ ! -e "$D/x2.exr" ]; then pass path_with_lights_is_error; else fail path_with_lights_is_error "exit $rc"; fi
"$SL" reference "$D/scene.json" --spp 8 -o "$D/x3.exr" >/dev/null 2>&1; rc=$?
if [ "$rc" = 2 ] && [ ! -e "$D/x3.exr" ]; then pass path_spp_needs_path; else fail path_spp_needs_path "exit $rc"; fi
"$SL" reference "$D/scene.json" --path --time 0 -o "$D/x4.exr" >/dev/null 2>&1; rc=$?
if [ "$rc" = 2 ]; then pass path_bad_time; else fail path_bad_time "exit $rc"; fi
expect_error path_needs_map "environment.file: the path tracer needs an environment map" "$SL" reference "$D/nomap.json" --path -o "$D/x5.exr"
expect_error path_nan_map "non-finite" "$SL" reference "$D/nan.json" --path --spp 2 -o "$D/x6.exr"
[ -e "$D/x6.exr" ] && fail path_nan_map_no_output "x6.exr written" || pass path_nan_map_no_output
if run "$D/nan.json" --path --spp 2 --clamp-nonfinite -o "$D/x7.exr" && [ -s "$D/x7.exr" ]; then pass path_nan_map_clamped; else fail path_nan_map_clamped "$(cat "$D/stderr")"; fi

# SIGINT while rendering: exit 130, one line, no EXR, no JSON, no temporary
mkdir -p "$D/int"
"$SL" reference "$D/scene.json" --path --spp 1000000 --threads 2 -o "$D/int/p.exr" 2>"$D/int.err" &
pid=$!
sleep 1.5
kill -INT "$pid" 2>/dev/null
wait "$pid"; rc=$?
left=$(ls -A "$D/int")
if [ "$rc" = 130 ] && [ -z "$left" ] && grep -q "interrupted" "$D/int.err"; then pass path_sigint_writes_nothing
else fail path_sigint_writes_nothing "exit $rc, left: '$left', stderr: $(cat "$D/int.err")"; fi

expect_output path_help "--path" "$SL" reference --help
no_leftovers path_no_temporaries "$D"
no_leftovers path_no_temporaries_a "$D/a"
