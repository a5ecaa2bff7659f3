# test_usability.sh: the traps of issue 22 ("What a new user trips over") that no other script
# covers; docs/usability.md lists every trap with the test that covers it. Here: "colors"
# reproduces the file's colour (straight.hair's blond, the ponytail .tfxproj's hairColor), errors
# in referenced files name the scene and the key, tfx_follow on a .tfxproj with per_guide 0,
# outputs checked before the work (a read-only directory, a new directory at /, --exr without a
# PNG), duplicate keys in a lobes file, progress on a terminal (render: frame, pass, ETA; fit;
# sample; the table build) and none off a terminal or under --quiet, and --explain rows wrapped
# at the terminal's width.
# A terminal is simulated with script(1) (bsdutils).
. test/cli/lib.sh
D="$TMP/usability"
rm -rf "$D"; mkdir -p "$D"
export SL_CACHE_DIR="$D/cache" # fitted lobes and tables built here, never found from another run
PY=/usr/bin/python3; [ -x "$PY" ] || PY=python3

# a 16x8 Radiance HDR of one constant white (RGBE 128,128,128,129 = 1.0): the neutral map
white_hdr "$D/white.hdr" 16 8

# hue_check NAME "FILE R G B" "RENDERED R G B": the rendered mean's HSV hue and saturation
hue_check() {
    "$PY" - "$2" "$3" <<'PYEOF'
import colorsys, sys
want = [float(x) for x in sys.argv[1].split()]
got = [float(x) for x in sys.argv[2].split()]
hw, sw, _ = colorsys.rgb_to_hsv(*want)
hg, sg, _ = colorsys.rgb_to_hsv(*got)
dh = abs(hw - hg) * 360; dh = min(dh, 360 - dh)
# hue within 12 deg of the file's: measured (48 x 36, MS auto, which is on for these colours)
# straight.hair 58.7 deg (file 49.6), the ponytail 32.2 deg (file 23.4). The path tracer puts
# straight.hair at 58.6 deg (test_strand_ms.sh checks the frame against it within 3 deg): the
# offset is physical (Chiang's inverse is fitted to hair deeper than these). Saturation is
# low (0.16x and 0.51x the file's; the path tracer's 0.38x for straight.hair: issue 19's MS
# deficit) and only required to be there. Before session 8 (MS in the material's colour)
# straight.hair came out at 21.8 deg.
ok = dh <= 12 and sg > 0.05 * sw
print("hue %.1f deg (file %.1f), saturation %.3f (file %.3f)" % (hg * 360, hw * 360, sg, sw))
sys.exit(0 if ok else 1)
PYEOF
}
mean_rgb() { "$SL" compare "$1" "$1" 2>/dev/null | awk '/^mean ours/ {print $4, $5, $6}'; }

# ---- "colors" reproduces the file's colours (with multiple scattering, as Chiang's inverse means)
if have_shared && [ -f "$SHARED/hair/straight.hair" ] && [ -f "$SHARED/hair/tressfx3/ponytail/ponytail.tfxproj" ]; then
    H="$SHARED/hair"; case $H in /*) ;; *) H="$PWD/$H" ;; esac
    for pair in "straight:$H/straight.hair:1.0 0.925490 0.568627" \
                "ponytail:$H/tressfx3/ponytail/ponytail.tfxproj:0.647 0.420 0.275"; do
        n=${pair%%:*}; rest=${pair#*:}; file=${rest%%:*}; rgb=${rest#*:}
        printf '{"hair": {"file": "%s"}, "material": {"model": "chiang", "strand_sigma_a": "colors"}, "environment": {"file": "white.hdr"}, "image": {"width": 48, "height": 36}, "quality": {"multiple_scattering": "auto"}}\n' \
            "$file" > "$D/col_$n.json"
        if ! err=$("$SL" render "$D/col_$n.json" --device c --quiet -o "$D/col_$n.exr" 2>&1); then
            fail "colors_hue_$n" "render failed: $err"; continue
        fi
        if out=$(hue_check "$n" "$rgb" "$(mean_rgb "$D/col_$n.exr")"); then pass "colors_hue_$n"
        else fail "colors_hue_$n" "$out"; fi
    done
else
    skip colors_hue "no ../shared hair"
fi

# ---- errors in referenced files name the scene and the key
printf '{"hair": {"procedural": {"strands": 20, "points": 6}}, "environment": {"file": "nomap.hdr"}, "image": {"width": 16, "height": 12}}\n' > "$D/nomap.json"
expect_error ref_missing_map "nomap.json: environment.file: $D/nomap.hdr: No such file or directory" \
    "$SL" render "$D/nomap.json" --device c -o "$D/x1.exr"
printf 'nothere.tfx 4 0.4 5.0 x.tfxsim g\n' > "$D/miss.tfxproj"
printf '{"hair": {"file": "miss.tfxproj"}, "environment": {"file": "white.hdr"}, "image": {"width": 16, "height": 12}}\n' > "$D/misstfx.json"
expect_error ref_missing_tfx_in_tfxproj "misstfx.json: hair.file: $D/nothere.tfx: No such file or directory" \
    "$SL" render "$D/misstfx.json" --device c -o "$D/x2.exr"

# ---- duplicate keys in a file the scene names (a lobes file) are an error naming the key path
printf '{"lobes": [{"dir": [0, 1, 0], "lambda": 0.5, "lambda": 0.7, "rgb": [1, 1, 1]}]}\n' > "$D/dup.lobes.json"
printf '{"hair": {"procedural": {"strands": 20, "points": 6}}, "environment": {"lobes": "dup.lobes.json"}, "image": {"width": 16, "height": 12}}\n' > "$D/dup.json"
expect_error dup_key_in_lobes_file "dup.json: environment.lobes: $D/dup.lobes.json: lobes[0].lambda: duplicate key" \
    "$SL" render "$D/dup.json" --device c -o "$D/x4.exr"

# ---- tfx_follow with per_guide 0 on a .tfxproj: refused naming the key (was accepted silently)
if have_shared && [ -f "$SHARED/hair/tressfx3/ponytail/ponytail.tfxproj" ]; then
    printf '{"hair": {"file": "%s", "tfx_follow": {"per_guide": 0}}, "environment": {"file": "white.hdr"}, "image": {"width": 16, "height": 12}}\n' \
        "$H/tressfx3/ponytail/ponytail.tfxproj" > "$D/pg0.json"
    expect_error tfx_follow_per_guide0_on_tfxproj "pg0.json: hair.tfx_follow: " \
        "$SL" render "$D/pg0.json" --device c -o "$D/x3.exr"
else
    skip tfx_follow_per_guide0_on_tfxproj "no ../shared hair"
fi

# ---- outputs checked before the work
printf '{"hair": {"procedural": {"strands": 30, "points": 6}}, "environment": {"file": "white.hdr"}, "image": {"width": 16, "height": 12}, "output": {"png": "scene.png"}}\n' > "$D/s.json"
mkdir -p "$D/ro"; chmod 555 "$D/ro"
if [ "$(id -u)" -ne 0 ]; then
    expect_error out_readonly_dir "ro/x.exr: directory $D/ro is not writable" "$SL" render "$D/s.json" --device c -o "$D/ro/x.exr"
elif command -v setpriv >/dev/null 2>&1 && setpriv --reuid=65534 --regid=65534 --clear-groups true 2>/dev/null; then
    # root writes anywhere: run as "nobody", whom only the mode stops
    chmod 777 "$D"; chmod 666 "$D/s.json" "$D/white.hdr"
    expect_error out_readonly_dir "ro/x.exr: directory $D/ro is not writable" \
        setpriv --reuid=65534 --regid=65534 --clear-groups env SL_CACHE_DIR="$D/nobody_cache" \
        "$SL" render "$D/s.json" --device c -o "$D/ro/x.exr"
else
    skip out_readonly_dir "running as root without a usable setpriv"
fi
chmod 755 "$D/ro"
d="/strandlight_usability_$$"
expect_error out_no_dir_at_root "directory $d does not exist (none is created at /)" \
    "$SL" render "$D/s.json" --device c -o "$d/x.exr"
if [ ! -e "$d" ]; then pass out_no_dir_at_root_nothing_created; else fail out_no_dir_at_root_nothing_created "made $d"; rmdir "$d"; fi
rm -f "$D/scene.png"
"$SL" render "$D/s.json" --device c --quiet --exr "$D/only.exr" 2>/dev/null
if [ -s "$D/only.exr" ] && [ ! -e "$D/scene.png" ]; then pass out_exr_alone_no_png
else fail out_exr_alone_no_png "only.exr missing or the scene's PNG written"; fi

# ---- progress on a terminal, none off it or under --quiet
if command -v script >/dev/null 2>&1; then
    on_tty() { script -qec "$1" /dev/null 2>&1 | tr '\r' '\n'; }
    out=$(on_tty "$SL render $D/s.json --device c --orbit 3 -o $D/orbit/o.exr")
    if printf '%s\n' "$out" | grep -q 'render: frame 1 of 3: light pass (4 of 13)' &&
       printf '%s\n' "$out" | grep -q 'render: frame 3 of 3, eta [0-9]*m[0-9][0-9]s: .* pass'; then
        pass progress_render_tty
    else fail progress_render_tty "$(printf '%s\n' "$out" | grep -a 'pass' | tail -2)"; fi
    out=$(on_tty "$SL render $D/s.json --device c --orbit 2 --quiet -o $D/orbit/q.exr")
    if ! printf '%s\n' "$out" | grep -q 'pass\|strandlight:'; then pass progress_render_quiet
    else fail progress_render_quiet "$(printf '%s\n' "$out" | head -2)"; fi
    out=$(on_tty "$SL fit data/env/city_256.hdr --lobes 12 -o $D/f.json")
    if printf '%s\n' "$out" | grep -q '^fit \[[#.]*\] *[0-9.]*% [0-9.]*s eta [0-9.]*s'; then pass progress_fit_tty
    else fail progress_fit_tty "$(printf '%s\n' "$out" | tail -2)"; fi
    out=$(on_tty "$SL sample data/env/city_256.hdr --lights 16 -o $D/l.json")
    if printf '%s\n' "$out" | grep -q '^sample: 16 lights and their errors'; then pass progress_sample_tty
    else fail progress_sample_tty "$(printf '%s\n' "$out" | tail -2)"; fi
    printf '{"hair": {"procedural": {"strands": 60, "points": 6}}, "material": {"eta": 1.61}, "environment": {"file": "white.hdr"}, "image": {"width": 16, "height": 12}, "quality": {"multiple_scattering": "off"}}\n' > "$D/t.json"
    out=$(on_tty "$SL render $D/t.json --device c --method table -o $D/t.exr")
    if printf '%s\n' "$out" | grep -q '^srbf table \[[#.]*\] *[0-9.]*% [0-9.]*s eta [0-9.]*s'; then pass progress_table_tty
    else fail progress_table_tty "$(printf '%s\n' "$out" | tail -2)"; fi
    # explain rows wrap at the terminal's width (80 here); to a pipe they stay whole
    out=$(on_tty "stty cols 80; $SL render $D/s.json --device c --explain -o $D/w.exr 2>/dev/null")
    long=$(printf '%s\n' "$out" | awk 'length($0) > 80' | wc -l)
    whole=$("$SL" render "$D/s.json" --device c --explain -o "$D/w2.exr" 2>/dev/null | awk 'length($0) > 80' | wc -l)
    if [ "$long" -eq 0 ] && [ "$whole" -gt 0 ]; then pass explain_wraps_on_tty
    else fail explain_wraps_on_tty "$long lines over 80 on the terminal, $whole over 80 to a pipe (want 0, > 0)"; fi
else
    skip progress_tty "no script(1)"
fi
# off a terminal: no progress bar and no status line (stderr here is a pipe)
err=$("$SL" fit data/env/city_256.hdr --lobes 12 -o "$D/f2.json" 2>&1 >/dev/null)
if ! printf '%s' "$err" | grep -q 'eta\|\['; then pass progress_off_tty_fit; else fail progress_off_tty_fit "$err"; fi
err=$("$SL" render "$D/s.json" --device c -o "$D/p.exr" 2>&1 >/dev/null)
if ! printf '%s' "$err" | grep -q ' pass (\|eta'; then pass progress_off_tty_render; else fail progress_off_tty_render "$err"; fi
