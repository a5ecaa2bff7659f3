# test_export.sh: `strandlight export` (the scene's strands as a .hair file and its camera) and
# `strandlight compare` (an image against references) from the command line: round trips
# through `strandlight info`, the up-axis and radius as the renderer sees them (checked by an
# independent python3 parse of the written bytes), the camera sidecar, and bad outputs / inputs
# that must exit 1 with one stderr line and write nothing.
. test/cli/lib.sh
D="$TMP/export"
rm -rf "$D"; mkdir -p "$D"
PY=python3; [ -x /usr/bin/python3 ] && PY=/usr/bin/python3

expect_output export_help "FILE.hair.camera.json" "$SL" export --help
expect_output compare_help "--ours-noise" "$SL" compare --help
out=$("$SL" export "$D/none.json" 2>&1); rc=$?
if [ $rc -eq 2 ]; then pass export_missing_output_is_usage; else fail export_missing_output_is_usage "rc=$rc $out"; fi
out=$("$SL" export --bogus 2>&1); rc=$?
if [ $rc -eq 2 ]; then pass export_unknown_option_is_usage; else fail export_unknown_option_is_usage "rc=$rc $out"; fi

# --- procedural hair: counts and radius survive the round trip ---------------------------------
cat > "$D/proc.json" <<'EOF'
{"hair": {"procedural": {"style": "wavy", "strands": 30, "points": 8, "seed": 2}, "radius": 0.05},
 "material": {"model": "chiang", "melanin": 0.3, "offset_deg": 3},
 "environment": {"file": "map.hdr", "rotation_deg": 30, "intensity": 2},
 "camera": {"fov_deg": 25}, "image": {"width": 64, "height": 48}}
EOF
expect_ok export_procedural "$SL" export "$D/proc.json" -o "$D/out/proc.hair"
info=$("$SL" info "$D/out/proc.hair" 2>&1)
if printf '%s\n' "$info" | grep -q '^strands: 30$' && printf '%s\n' "$info" | grep -q '^points: 240$' \
   && printf '%s\n' "$info" | grep -q '^radius: per point, min 0.05, max 0.05$'; then
    pass export_round_trip_counts
else fail export_round_trip_counts "$info"; fi
if $PY - "$D/out/proc.hair.camera.json" <<'EOF'
import json, sys
c = json.load(open(sys.argv[1]))
cam, m, env = c["camera"], c["material"], c["environment"]
assert c["strands"] == 30 and c["points"] == 240, c
assert c["image"] == {"width": 64, "height": 48}, c["image"]
assert cam["framed"] is True and cam["fov_deg"] == 25, cam
assert abs(cam["forward"][2] + 1) < 1e-12 and cam["eye"][2] > cam["target"][2], cam  # framed along -Z
assert m["model"] == "chiang" and m["melanin"] == 0.3 and abs(m["offset_deg"] - 3) < 1e-12, m
assert m["melanin_redness"] == 1.0 and m["roughness"] == 0.3 and m["eta"] == 1.55, m   # defaults
assert env["rotation_deg"] == 30 and env["intensity"] == 2 and env["file"].endswith("map.hdr"), env
EOF
then pass export_sidecar; else fail export_sidecar "$(cat "$D/out/proc.hair.camera.json")"; fi
# the framing depends on the image size: --width/--height resolve the camera for that size
"$SL" export "$D/proc.json" -o "$D/out/wide.hair" --width 40 --height 200 >/dev/null 2>&1
if $PY -c "import json,sys; a=json.load(open(sys.argv[1])); b=json.load(open(sys.argv[2]));
assert b['image']=={'width':40,'height':200} and a['camera']['eye']!=b['camera']['eye']" \
   "$D/out/proc.hair.camera.json" "$D/out/wide.hair.camera.json"; then pass export_size_override
else fail export_size_override "camera not resolved at --width/--height"; fi

# --- a file with up: z and a radius override: points as the renderer sees them -----------------
$PY - "$D/z.hair" <<'EOF'
import struct, sys
pts = [(0, 0, 0), (1, 2, 3), (4, 5, 6), (-1, -2, 7), (0.5, 0.25, -3)]
hdr = b"HAIR" + struct.pack("<IIII", 2, 5, 0x7, 0) + struct.pack("<ff", 0.2, 0) + struct.pack("<3f", 1, 1, 1)
with open(sys.argv[1], "wb") as f:
    f.write(hdr + b"\0" * (128 - len(hdr)))
    f.write(struct.pack("<2H", 2, 1))
    for p in pts: f.write(struct.pack("<3f", *p))
    f.write(struct.pack("<5f", 0.2, 0.3, 0.4, 0.5, 0.6))
EOF
printf '{"hair": {"file": "z.hair", "up": "z", "radius": 0.07}, "environment": {"lobes": "lobes.json"}, "camera": {"eye": [0, 1, 30], "target": [0, 1, 0], "fov_deg": 40}}\n' > "$D/z.json"
expect_ok export_up_z "$SL" export "$D/z.json" -o "$D/out/z.hair"
if $PY - "$D/out/z.hair" <<'EOF'
import struct, sys
b = open(sys.argv[1], "rb").read()
S, P, flags = struct.unpack_from("<III", b, 4)
assert (S, P) == (2, 5) and flags & 0x7 == 0x7, (S, P, flags)
seg = struct.unpack_from("<2H", b, 128)
assert seg == (2, 1), seg
pts = struct.unpack_from("<15f", b, 132)
thick = struct.unpack_from("<5f", b, 132 + 60)
src = [(0, 0, 0), (1, 2, 3), (4, 5, 6), (-1, -2, 7), (0.5, 0.25, -3)]
want = [c for (x, y, z) in src for c in (x, z, -y)]          # z up -> y up: (x, z, -y)
assert all(abs(a - w) < 1e-6 for a, w in zip(pts, want)), pts
assert all(abs(t - 0.14) < 1e-7 for t in thick), thick      # 2 x the radius override
EOF
then pass export_up_and_radius; else fail export_up_and_radius "points or thickness differ"; fi
if grep -q '"framed":[[:space:]]*false' "$D/out/z.hair.camera.json"; then pass export_given_eye; else fail export_given_eye "framed flag"; fi

# --- scripts/cycles (Blender's side) without Blender: its .hair reader and its frame -------------
# (numpy is what Blender's Python brings; without it these two checks SKIP)
if $PY -c "import numpy" 2>/dev/null; then
    if $PY - "$D/out/z.hair" "$D/out/proc.hair" <<'EOF'
import sys
sys.path.insert(0, "scripts/cycles")
import hairfile
h = hairfile.read(sys.argv[1])
assert h.num_strands == 2 and list(h.strand_first) == [0, 3, 5], h.strand_first
assert abs(h.points[1] - [1, 3, -2]).max() < 1e-6 and abs(h.radius - 0.07).max() < 1e-7
p = hairfile.read(sys.argv[2])
assert p.num_strands == 30 and len(p.points) == 240 and abs(p.radius - 0.05).max() < 1e-7
EOF
    then pass cycles_hairfile_reads_export; else fail cycles_hairfile_reads_export "hairfile.py disagrees"; fi
    # frames.map_dir against the C code: the brightest pixel's direction `strandlight info` prints
    $PY - "$D/map.hdr" <<'EOF'
import sys
w, h = 32, 16
with open(sys.argv[1], "wb") as f:
    f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
    for y in range(h):
        for x in range(w):
            f.write(b"\x80\x80\x80\x8d" if (x, y) == (27, 4) else b"\x80\x80\x80\x81")
EOF
    dir=$("$SL" info "$D/map.hdr" 2>/dev/null | sed -n 's/^luminance max: .*dir (\(.*\))$/\1/p')
    if $PY - "$dir" <<'EOF'
import sys
sys.path.insert(0, "scripts/cycles")
import numpy as np, frames
want = np.array([float(t) for t in sys.argv[1].split(",")])
got = frames.map_dir(32, 16, 27, 4)
assert np.abs(got - want).max() < 1e-3, (got, want)
assert frames.dir_to_pixel(32, 16, got) == (27, 4)
b = frames.to_blender(got)  # Blender's equirectangular u of that direction: our pixel column
u = -np.arctan2(b[1], b[0]) / (2 * np.pi) + 0.5
assert int(u * 32) == 27 and abs(np.linalg.det(frames.OURS_TO_BLENDER) - 1) < 1e-12, u
EOF
    then pass cycles_frames_match_c; else fail cycles_frames_match_c "frames.py vs strandlight info: '$dir'"; fi
else
    skip cycles_hairfile_reads_export "no numpy for $PY"
    skip cycles_frames_match_c "no numpy for $PY"
fi

# --- bad outputs and inputs: one line, exit 1, nothing written ---------------------------------
printf 'x' > "$D/afile"
expect_error export_bad_output_path "afile" "$SL" export "$D/proc.json" -o "$D/afile/x.hair"
if [ "$(cat "$D/afile")" = x ] && ! ls -a "$D" | grep -q -e tmp -e 'x\.hair'; then
    pass export_bad_output_writes_nothing
else fail export_bad_output_writes_nothing "$(ls "$D")"; fi
mkdir -p "$D/adir"
expect_error export_output_is_directory "adir" "$SL" export "$D/proc.json" -o "$D/adir"
expect_error export_missing_scene "none.json" "$SL" export "$D/none.json" -o "$D/out/n.hair"
printf '{"hair": {"procedural": {"style": "wavy"}}, "bogus": 1}\n' > "$D/badkey.json"
expect_error export_bad_scene "bogus" "$SL" export "$D/badkey.json" -o "$D/out/b.hair"
if [ ! -e "$D/out/n.hair" ] && [ ! -e "$D/out/b.hair" ] && [ ! -e "$D/out/b.hair.camera.json" ]; then
    pass export_failures_write_nothing
else fail export_failures_write_nothing "$(ls "$D/out")"; fi
no_leftovers export_no_temporaries "$D/out"

# --- compare on images rendered here ------------------------------------------------------------
cat > "$D/tiny.json" <<'EOF'
{"hair": {"procedural": {"style": "straight", "strands": 60, "points": 8, "seed": 1}, "radius": 0.3},
 "environment": {"lobes": "lobes.json"}, "camera": {"fov_deg": 30}, "image": {"width": 48, "height": 32},
 "quality": {"multiple_scattering": "off"}}
EOF
printf '{"lobes": [{"dir": [0, 1, 0], "lambda": 0.5, "rgb": [1, 0.8, 0.6]}]}\n' > "$D/lobes.json"
if "$SL" render "$D/tiny.json" --device c --aov TT --exr "$D/a.exr" >/dev/null 2>&1 &&
   "$SL" render "$D/tiny.json" --device c --exr "$D/small.exr" --width 24 --height 16 >/dev/null 2>&1; then
    csv=$("$SL" compare "$D/a.exr" "$D/a.exr" "$D/a.exr" --csv 2>&1)
    if printf '%s\n' "$csv" | grep -q '^ratio,1,1,1,$' && printf '%s\n' "$csv" | grep -q '^rel_rmse_blocks_corrected,0,0,0,0$' \
       && printf '%s\n' "$csv" | head -1 | grep -q '^quantity,r,g,b,avg$'; then
        pass compare_identical_csv
    else fail compare_identical_csv "$csv"; fi
    # the same scene under 1.1 x the light: every pixel 1.1 x (the renderer is linear in it;
    # half-float EXRs round to 5e-4): ratio 1.1, rel. RMSE 0.1 per pixel and per block
    sed 's/"lobes": "lobes.json"}/"lobes": "lobes.json", "intensity": 1.1}/' "$D/tiny.json" > "$D/tiny11.json"
    "$SL" render "$D/tiny11.json" --device c --aov TT --exr "$D/a11.exr" >/dev/null 2>&1
    csv=$("$SL" compare "$D/a11.exr" "$D/a.exr" --csv 2>&1)
    if printf '%s\n' "$csv" | awk -F, '$1 == "ratio" { for (i = 2; i <= 4; i++) if ($i < 1.098 || $i > 1.102) bad = 1; n++ }
        $1 ~ /^rel_rmse_(px|blocks)_raw$/ { if ($5 < 0.098 || $5 > 0.102) bad = 1; n++ }
        END { exit bad || n != 3 }'; then pass compare_known_ratio
    else fail compare_known_ratio "$csv"; fi
    # --layer: the TT AOV of both (also 1.1 x); --ref-layer: beauty against the reference's TT,
    # which is a part of it (ratio > 1); a missing layer names its channels
    csv=$("$SL" compare "$D/a11.exr" "$D/a.exr" --layer TT --csv 2>&1)
    if printf '%s\n' "$csv" | awk -F, '$1 == "ratio" { for (i = 2; i <= 4; i++) if ($i < 1.098 || $i > 1.102) bad = 1; n++ }
        END { exit bad || n != 1 }'; then pass compare_layer_ratio
    else fail compare_layer_ratio "$csv"; fi
    csv=$("$SL" compare "$D/a.exr" "$D/a.exr" --ref-layer TT --csv 2>&1)
    if printf '%s\n' "$csv" | awk -F, '$1 == "ratio" { for (i = 2; i <= 4; i++) if (!($i > 1.05)) bad = 1; n++ }
        END { exit bad || n != 1 }'; then pass compare_ref_layer
    else fail compare_ref_layer "$csv"; fi
    expect_error compare_layer_missing "need channels XX.R, XX.G, XX.B and A" "$SL" compare "$D/a.exr" "$D/a.exr" --layer XX
    expect_output compare_table "rel RMSE blocks, corrected" "$SL" compare "$D/a.exr" "$D/a.exr" "$D/a.exr" --ours-noise "$D/a.exr"
    expect_error compare_size_mismatch "small.exr is 24 x 16" "$SL" compare "$D/a.exr" "$D/small.exr"
    expect_error compare_missing_file "none.exr" "$SL" compare "$D/a.exr" "$D/none.exr"
    expect_error compare_not_exr "tiny.json" "$SL" compare "$D/a.exr" "$D/tiny.json"
    out=$("$SL" compare "$D/a.exr" "$D/a.exr" --block 0 2>&1); rc=$?
    if [ $rc -eq 2 ]; then pass compare_bad_block_is_usage; else fail compare_bad_block_is_usage "rc=$rc $out"; fi
else
    fail compare_renders "strandlight render --device c failed"
fi
