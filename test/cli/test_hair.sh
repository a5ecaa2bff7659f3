# test_hair.sh: `strandlight info` on every hair model of ../shared/data (counts checked against
# an independent python3 header parse, never against our own output) and on bad input files
# generated here: each must exit 1 with one stderr line naming the file and the problem.
. test/cli/lib.sh
D="$TMP/hair"
rm -rf "$D"; mkdir -p "$D"
PY=python3; [ -x /usr/bin/python3 ] && PY=/usr/bin/python3   # a pyenv shim takes seconds to start

expect_output info_help "usage: strandlight info FILE" "$SL" info --help
out=$("$SL" info 2>&1); rc=$?
if [ $rc -eq 2 ]; then pass info_no_file_is_usage_error; else fail info_no_file_is_usage_error "rc=$rc $out"; fi
out=$("$SL" info --bogus x.hair 2>&1); rc=$?
if [ $rc -eq 2 ]; then pass info_unknown_option_is_usage_error; else fail info_unknown_option_is_usage_error "rc=$rc $out"; fi

# --- every real model: strands / points / segments from python3 parsing the headers --------
if have_shared; then
    $PY - "$SHARED/hair" > "$D/expected.txt" <<'EOF'
import os, struct, sys
root = sys.argv[1]
def hair(p):
    b = open(p, 'rb').read()
    S, P, flags, dseg = struct.unpack_from('<IIII', b, 4)
    size = 128 + 2*S*(flags & 1) + 12*P*(flags >> 1 & 1) + 4*P*(flags >> 2 & 1) + 4*P*(flags >> 3 & 1) + 12*P*(flags >> 4 & 1)
    assert size == len(b), p
    return S, P
def tfx(p):
    b = open(p, 'rb').read()
    v, S, V = struct.unpack_from('<fII', b, 0)
    if v < 3.5:
        assert struct.unpack_from('<I', b, 144)[0] == 296 and len(b) == 296 + 12*S*V, p
    else:
        off, uv = struct.unpack_from('<II', b, 12)
        assert off == 160 and len(b) == max(160 + 16*S*V, uv + 8*S if uv else 0), p
    return S, S*V
def data(p):
    b = open(p, 'rb').read()
    S, = struct.unpack_from('<i', b, 0); o = 4; P = 0
    for _ in range(S):
        n, = struct.unpack_from('<i', b, o); o += 4 + 12*n; P += n
    assert o == len(b), p
    return S, P
def proj(p):
    d = os.path.dirname(p); S = P = 0
    for line in open(p):
        t = line.split('#')[0].split()
        if t and t[0].endswith('.tfx'):
            s, q = tfx(os.path.join(d, t[0])); k = 1 + int(t[1]); S += k*s; P += k*q
    return S, P
for dp, dn, fn in sorted(os.walk(root)):
    for f in sorted(fn):
        p = os.path.join(dp, f); ext = f.rsplit('.', 1)[-1]
        fun = {'hair': hair, 'tfx': tfx, 'data': data, 'tfxproj': proj}.get(ext)
        if fun:
            S, P = fun(p)
            print(p, S, P, P - S)
EOF
    n=$(grep -c '' "$D/expected.txt")
    if [ "$n" -ge 14 ]; then pass info_found_all_models; else fail info_found_all_models "only $n hair files (want 11 models + 3 projects)"; fi
    while read -r f S P G; do
        name="info_counts_$(basename "$f")"
        out=$("$SL" info "$f" 2>&1); rc=$?
        if [ $rc -ne 0 ]; then fail "$name" "exit $rc: $out"; continue; fi
        got=$(printf '%s\n' "$out" | awk -F': ' '$1=="strands"{s=$2} $1=="points"{p=$2} $1=="segments"{g=$2} END{print s, p, g}')
        if [ "$got" = "$S $P $G" ]; then pass "$name"; else fail "$name" "got '$got', want '$S $P $G'"; fi
    done < "$D/expected.txt"
    out=$("$SL" info "$SHARED/hair/straight.hair")
    for want in "format: cyHair .hair" "thickness: default 0.1 (diameter" "per-point thickness: no" \
                "per-point transparency: no (default 0.355777)" "per-point color: yes" \
                "bounding box: (-32.49"; do
        if printf '%s' "$out" | grep -qF -- "$want"; then pass "info_straight_hair: $want"; else fail info_straight_hair "lacks '$want'"; fi
    done
    expect_output info_tfx4_format "format: TressFX 4 .tfx" "$SL" info "$SHARED/hair/tressfx4/Ratboy_mohawk.tfx"
    expect_output info_tfx3_format "format: TressFX 3 .tfx" "$SL" info "$SHARED/hair/tressfx3/bear/bear.tfx"
    expect_output info_usc_format "format: USC-HairSalon .data" "$SL" info "$SHARED/hair/harolongo.data"
    expect_output info_project_guides "guide strands: 4933 (+ 19732 follow strands)" "$SL" info "$SHARED/hair/tressfx3/ponytail/ponytail.tfxproj"
    # .hdr/.exr go to the environment-map describer (engineer "env"'s sl_envmap_info)
    expect_ok info_dispatches_envmap "$SL" info "$SHARED/envmaps/pmndrs/venice.hdr"
else
    skip info_counts "no shared data at $SHARED"
fi
expect_error info_missing_envmap "$D/none.exr: No such file or directory" "$SL" info "$D/none.exr"

# --- bad inputs -------------------------------------------------------------------------------
$PY - "$D" <<'EOF'
import os, struct, sys
d = sys.argv[1]
def w(name, b): open(os.path.join(d, name), 'wb').write(b)
def hair(S=2, P=6, flags=0x02, dseg=2, segs=None, pts=None, extra=b''):
    h = b'HAIR' + struct.pack('<IIII', S, P, flags, dseg) + struct.pack('<5f', 0.1, 0, 1, 1, 1) + bytes(88)
    if flags & 1: h += struct.pack('<%dH' % S, *segs)
    pts = pts if pts is not None else [float(i) for i in range(3*P)]
    return h + struct.pack('<%df' % len(pts), *pts) + extra
def tfx3(S=2, V=4, pts=None, version=3.0):
    h = struct.pack('<fIIII', version, S, V, 0, 0) + bytes(124) + struct.pack('<I', 296) + bytes(148)
    pts = pts if pts is not None else [float(i) for i in range(3*S*V)]
    return h + struct.pack('<%df' % len(pts), *pts)
def tfx4(S=2, V=4):
    h = struct.pack('<fIIIIIII', 4.0, S, V, 160, 0, 0, 0, 0) + bytes(128)
    return h + struct.pack('<%df' % (4*S*V), *[float(i) for i in range(4*S*V)])
def data(strands):
    b = struct.pack('<i', len(strands))
    for n in strands: b += struct.pack('<i', n) + struct.pack('<%df' % (3*n), *[0.5*i for i in range(3*n)])
    return b
good = hair()
w('ok.hair', good)
w('trunc_header.hair', good[:60])
w('trunc_points.hair', good[:-5])
w('trailing.hair', good + b'\0\0\0')
w('count_mismatch.hair', hair(S=2, P=7, flags=0x03, segs=[2, 2]))   # size right for P=7, sum 6
w('absurd.hair', hair(P=0xffffffff, pts=[float(i) for i in range(18)]))
w('magic.hair', b'HAIX' + good[4:])
nan = [float(i) for i in range(18)]; nan[4] = float('nan'); w('nan.hair', hair(pts=nan))
inf = [float(i) for i in range(18)]; inf[14] = float('-inf'); w('inf.hair', hair(pts=inf))
w('one_point.hair', hair(S=2, P=4, flags=0x03, segs=[0, 2], pts=[float(i) for i in range(12)]))
zero = [1.0]*9 + [float(i) for i in range(9)]; w('zero_length.hair', hair(pts=zero))
w('empty.hair', b'')
w('empty.tfx', b'')
w('empty.data', b'')
t = tfx3()
w('ok.tfx', t)
w('trunc_header.tfx', t[:100])
w('trunc.tfx', t[:-1])
w('trailing.tfx', t + b'\0' * 4)
w('absurd.tfx', t[:4] + struct.pack('<I', 0x7fffffff) + t[8:])
w('version.tfx', tfx3(version=7.0))
w('one_vertex.tfx', tfx3(V=1))
p = [float(i) for i in range(24)]; p[13] = float('nan'); w('nan.tfx', tfx3(pts=p))
p = [float(i) for i in range(24)]; p[12:24] = [2.0] * 12; w('zero_length.tfx', tfx3(pts=p))
w('ok4.tfx', tfx4())
w('trunc4.tfx', tfx4()[:-16])
u = data([3, 4])
w('ok.data', u)
w('trunc.data', u[:-4])
w('trailing.data', u + b'\0')
w('absurd.data', struct.pack('<i', 0x7fffffff) + u[4:])
w('absurd_points.data', struct.pack('<ii', 1, 0x40000000) + bytes(24))
w('zero_strands.data', struct.pack('<i', 0))
w('unknown.bin', b'\x01\x02\x03\x04')
open(os.path.join(d, 'bad.tfxproj'), 'w').write('version 3.0\nok.tfx four 0.4 5.0 x.tfxsim g\n')
open(os.path.join(d, 'missing.tfxproj'), 'w').write('nothere.tfx 4 0.4 5.0 x.tfxsim g\n')
open(os.path.join(d, 'ok.tfxproj'), 'w').write('# two groups\nok.tfx 2 0.5 1.0 a.tfxsim one\nok4.tfx 0 0 0 b.tfxsim two\nhairColor 0.5 0.4 0.3\n')
EOF

expect_ok info_ok_hair "$SL" info "$D/ok.hair"
expect_ok info_ok_tfx "$SL" info "$D/ok.tfx"
expect_ok info_ok_tfx4 "$SL" info "$D/ok4.tfx"
expect_ok info_ok_data "$SL" info "$D/ok.data"
expect_output info_ok_project "strands: 8" "$SL" info "$D/ok.tfxproj"   # 2 x (1 + 2) + 2 x (1 + 0)

e() { expect_error "$1" "$D/$2: $3" "$SL" info "$D/$2"; }
e bad_hair_truncated_header   trunc_header.hair  "truncated header (60 bytes, a .hair header has 128)"
e bad_hair_truncated_points   trunc_points.hair  "truncated: the header declares 2 strands and 6 points (200 bytes), the file has 195 bytes"
e bad_hair_trailing_bytes     trailing.hair      "3 trailing bytes after the 200 bytes the header declares"
e bad_hair_count_mismatch     count_mismatch.hair "the strands' segment counts add up to 6 points, the header says 7"
e bad_hair_absurd_count       absurd.hair        "truncated: the header declares 2 strands and 4294967295 points"
e bad_hair_wrong_magic        magic.hair         "wrong magic number (expected \"HAIR\" for a .hair file)"
e bad_hair_nan                nan.hair           "strand 0 point 1: coordinate y is not finite (nan)"
e bad_hair_inf                inf.hair           "strand 1 point 1: coordinate z is not finite (-inf)"
e bad_hair_one_point_strand   one_point.hair     "strand 0 has 0 segments (1 point), need at least 1"
e bad_hair_zero_length        zero_length.hair   "strand 0 has zero length (all 3 points coincide)"
e bad_hair_empty              empty.hair         "empty file"
e bad_tfx_empty               empty.tfx          "empty file"
e bad_data_empty              empty.data         "empty file"
e bad_tfx_truncated_header    trunc_header.tfx   "truncated header (100 bytes, a TressFX 3 header has 296)"
e bad_tfx_truncated           trunc.tfx          "truncated: vertex positions for 2 strands x 4 vertices end at byte 392, the file has 391 bytes"
e bad_tfx_trailing_bytes      trailing.tfx       "4 trailing bytes after the last array (which ends at byte 392)"
e bad_tfx_absurd_count        absurd.tfx         "truncated: the header declares 2147483647 strands x 4 vertices, more than the 392-byte file can hold"
e bad_tfx_version             version.tfx        "not a TressFX file (version float 7 at offset 0, expected 3.x or 4.x)"
e bad_tfx_one_vertex          one_vertex.tfx     "1 vertices per strand, need at least 2"
e bad_tfx_nan                 nan.tfx            "strand 1 point 0: coordinate y is not finite (nan)"
e bad_tfx_zero_length         zero_length.tfx    "strand 1 has zero length (all 4 points coincide)"
e bad_tfx4_truncated          trunc4.tfx         "truncated: vertex positions for 2 strands x 4 vertices end at byte 288, the file has 272 bytes"
e bad_data_truncated          trunc.data         "truncated: strand 1 declares 4 points (ends at byte 96), the file has 92 bytes"
e bad_data_trailing_bytes     trailing.data      "1 trailing bytes after the last strand (which ends at byte 96)"
e bad_data_absurd_count       absurd.data        "truncated: the file declares 2147483647 strands but ends after 2"
e bad_data_absurd_points      absurd_points.data "truncated: strand 0 declares 1073741824 points"
e bad_data_zero_strands       zero_strands.data  "strand count 0 (must be positive)"
e bad_unknown_format          unknown.bin        "unknown hair format (expected .hair, .tfx, .tfxproj or .data)"
expect_error bad_tfxproj_line "$D/bad.tfxproj:2: expected \`<file>.tfx <followPerGuide" "$SL" info "$D/bad.tfxproj"
expect_error bad_tfxproj_missing_group "$D/nothere.tfx: No such file or directory" "$SL" info "$D/missing.tfxproj"
expect_error bad_missing_file "$D/nope.hair: No such file or directory" "$SL" info "$D/nope.hair"
mkdir -p "$D/adir.hair"
expect_error bad_directory "$D/adir.hair: is a directory, expected a file" "$SL" info "$D/adir.hair"
cp "$D/ok.hair" "$D/unreadable.hair"; chmod 000 "$D/unreadable.hair"
if [ "$(id -u)" -ne 0 ]; then
    expect_error bad_unreadable "$D/unreadable.hair: Permission denied" "$SL" info "$D/unreadable.hair"
elif command -v setpriv >/dev/null 2>&1 &&
     setpriv --reuid=65534 --regid=65534 --clear-groups "$SL" info "$D/ok.hair" >/dev/null 2>&1; then
    # root reads anything: run as "nobody" (who can read ok.hair, so only the mode stops it)
    expect_error bad_unreadable "$D/unreadable.hair: Permission denied" \
        setpriv --reuid=65534 --regid=65534 --clear-groups "$SL" info "$D/unreadable.hair"
else
    skip bad_unreadable "running as root without a usable setpriv: chmod 000 does not prevent reading"
fi
chmod 600 "$D/unreadable.hair"

# hair.tfx_follow where it cannot apply is an error naming the key (it used to be dropped silently)
if have_shared && [ -f "$SHARED/hair/straight.hair" ] && [ -f "$SHARED/hair/tressfx3/ponytail/ponytail.tfxproj" ]; then
    F="$TMP/follow"; mkdir -p "$F"
    for pair in "straight:$PWD/$SHARED/hair/straight.hair" "proj:$PWD/$SHARED/hair/tressfx3/ponytail/ponytail.tfxproj"; do
        n=${pair%%:*}; file=${pair#*:}
        case $SHARED in /*) file=${file#"$PWD/"} ;; esac
        printf '{"hair": {"file": "%s", "tfx_follow": {"per_guide": 4}}, "environment": {"file": "%s/data/env/city_256.hdr"}, "image": {"width": 16, "height": 12}}\n' \
            "$file" "$PWD" > "$F/$n.json"
    done
    expect_error tfx_follow_not_tfx "hair.tfx_follow: applies to TressFX guides only" \
        "$SL" render "$F/straight.json" --device c -o "$F/a.exr"
    expect_error tfx_follow_on_tfxproj "hair.tfx_follow: " "$SL" render "$F/proj.json" --device c -o "$F/b.exr"
else
    skip tfx_follow_errors "no ../shared hair"
fi

# geometry the float pipeline cannot render (issue 21: these rendered black with exit 0): valid
# files, refused by render with one line naming the scene's hair.file and the problem
$PY - "$D" <<'PYEOF'
import struct, sys
d = sys.argv[1]
def hair(name, pts, thick):
    n = len(pts) // 2
    hdr = b"HAIR" + struct.pack("<IIII", n, 2 * n, 2, 1) + struct.pack("<ff", thick, 0.0)
    hdr += struct.pack("<fff", 0.5, 0.5, 0.5)
    with open(f"{d}/{name}.hair", "wb") as f:
        f.write(hdr + b"\0" * (128 - len(hdr)))
        for p in pts:
            f.write(struct.pack("<3f", *p))
hair("huge", [(-3e38, 0, 0), (3e38, 1, 0), (-3e38, 2, 0), (3e38, 3, 1)], 0.1)
hair("tiny", [(0, 0, 0), (1e-38, 1e-38, 0), (2e-38, 0, 0), (0, 2e-38, 1e-38)], 1e-39)
hair("fat", [(0, 0, 0), (1, 1, 0), (2, 0, 0), (0, 2, 1)], 3e38)
hair("ok", [(0, 0, 0), (1, 1, 0), (2, 0, 0), (0, 2, 1)], 0.05)
PYEOF
printf '{"lobes": [{"dir": [0, 1, 0], "lambda": 0.5, "rgb": [1, 1, 1]}]}\n' > "$D/l.json"
for h in huge tiny fat ok; do
    printf '{"hair": {"file": "%s.hair"}, "environment": {"lobes": "l.json"}, "image": {"width": 16, "height": 12}}\n' "$h" > "$D/g_$h.json"
done
expect_error hair_coords_too_large "g_huge.json: hair.file: coordinates up to 3e+38: too large" \
    "$SL" render "$D/g_huge.json" --device c --exr "$D/g.exr"
expect_error hair_extent_too_small "g_tiny.json: hair.file: extent" \
    "$SL" render "$D/g_tiny.json" --device c --exr "$D/g.exr"
expect_error hair_radius_too_large "g_fat.json: hair.file: fiber radius up to 1.5e+38" \
    "$SL" render "$D/g_fat.json" --device c --exr "$D/g.exr"
if [ ! -e "$D/g.exr" ] && "$SL" render "$D/g_ok.json" --device c --quiet --exr "$D/g.exr" && [ -s "$D/g.exr" ]; then
    pass hair_representable_renders
else fail hair_representable_renders "the refused scenes wrote an image, or the ordinary one failed"; fi
