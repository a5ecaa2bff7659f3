# test_fit.sh: `strandlight fit` and `strandlight sample` from the command line (small maps
# written here, so it runs without the shared data; one shared map when present).
. test/cli/lib.sh
D="$TMP/fit"
rm -rf "$D"; mkdir -p "$D"

# A 32 x 16 Radiance map with flat scanlines: sky of 1.0 (mantissa 128, exponent 129) and one
# pixel 2^12 brighter (a sun).
mkmap() { # mkmap FILE
    {
        printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16 +X 32\n'
        for y in $(seq 0 15); do
            for x in $(seq 0 31); do
                if [ "$x" = 20 ] && [ "$y" = 5 ]; then printf '\200\200\200\215'; else printf '\200\200\200\201'; fi
            done
        done
    } > "$1"
}
mkmap "$D/tiny.hdr"

expect_output fit_help "--lobes" "$SL" fit --help
expect_output sample_help "--lights" "$SL" sample --help

out=$("$SL" fit "$D/tiny.hdr" -o "$D/x.json" 2>&1); rc=$?
if [ $rc -eq 2 ]; then pass fit_missing_lobes_is_usage; else fail fit_missing_lobes_is_usage "rc=$rc $out"; fi
out=$("$SL" fit "$D/tiny.hdr" --lobes 0 -o "$D/x.json" 2>&1); rc=$?
if [ $rc -eq 2 ]; then pass fit_bad_lobes_is_usage; else fail fit_bad_lobes_is_usage "rc=$rc $out"; fi
out=$("$SL" fit "$D/tiny.hdr" --lobes 4 --bogus 2>&1); rc=$?
if [ $rc -eq 2 ]; then pass fit_unknown_option_is_usage; else fail fit_unknown_option_is_usage "rc=$rc $out"; fi

expect_error fit_missing_map "$D/none.hdr" "$SL" fit "$D/none.hdr" --lobes 4 -o "$D/x.json"
printf 'not a map' > "$D/bad.hdr"
expect_error fit_corrupt_map "bad.hdr" "$SL" fit "$D/bad.hdr" --lobes 4 -o "$D/x.json"
expect_error sample_missing_map "$D/none.hdr" "$SL" sample "$D/none.hdr" --lights 4 -o "$D/l.json"
mkdir -p "$D/adir"
expect_error fit_output_is_directory "adir" "$SL" fit "$D/tiny.hdr" --lobes 4 -o "$D/adir"

expect_ok fit_tiny "$SL" fit "$D/tiny.hdr" --lobes 6 -o "$D/out/lobes.json" --preview "$D/out/prev.png"
if [ -s "$D/out/lobes.json" ] && grep -q '"rel_l2"' "$D/out/lobes.json" && grep -q '"lobe_conv_rel_l2"' "$D/out/lobes.json" \
   && grep -q '"map_hash"' "$D/out/lobes.json" && [ "$(grep -c '"dir"' "$D/out/lobes.json")" = 6 ]; then
    pass fit_writes_lobes_json
else fail fit_writes_lobes_json "$(head -c 300 "$D/out/lobes.json" 2>&1)"; fi
if [ -s "$D/out/prev.png" ] && head -c 8 "$D/out/prev.png" | grep -q PNG; then pass fit_preview_png; else fail fit_preview_png "no PNG"; fi
# The sun pixel (x = 20, y = 5) becomes the strongest lobe: its direction is that pixel's
# (numerics.md sec. 4: th = pi (5.5)/16, ph = 2 pi 20.5/32 - pi).
if awk 'BEGIN{pi=atan2(0,-1); th=pi*5.5/16; ph=2*pi*20.5/32-pi; x=sin(th)*sin(ph); y=cos(th); z=-sin(th)*cos(ph)}
        /"dir"/ && !done { gsub(/[\[\],]/," "); for(i=1;i<=NF;i++) if ($i ~ /"dir"/) { d=$(i+1)*x+$(i+2)*y+$(i+3)*z; done=1 } }
        END { exit !(d > 0.999) }' "$D/out/lobes.json"; then pass fit_sun_is_first_lobe; else fail fit_sun_is_first_lobe "first lobe not at the sun pixel"; fi
expect_output fit_auto "lobes, rel_l2" "$SL" fit "$D/tiny.hdr" --lobes auto --target-error 0.5 --max-lobes 12 -o "$D/auto.json"
expect_ok sample_tiny "$SL" sample "$D/tiny.hdr" --lights 16 -o "$D/out/lights.json"
if [ "$(grep -c '"dir"' "$D/out/lights.json")" = 16 ] && grep -q '"lobe_conv_rel_l2"' "$D/out/lights.json"; then
    pass sample_writes_lights_json
else fail sample_writes_lights_json "$(head -c 300 "$D/out/lights.json")"; fi
# Same input, same output (deterministic, threads do not matter).
"$SL" fit "$D/tiny.hdr" --lobes 6 --threads 1 -o "$D/t1.json" -q
"$SL" fit "$D/tiny.hdr" --lobes 6 --threads 3 -o "$D/t3.json" -q
if diff <(grep '"dir"' "$D/t1.json") <(grep '"dir"' "$D/t3.json") >/dev/null; then pass fit_deterministic; else fail fit_deterministic "lobes differ with --threads"; fi
no_leftovers fit_no_temporaries "$D/out"

if have_shared; then
    expect_output fit_shared_map "40 lobes" "$SL" fit "$SHARED/envmaps/pmndrs/npm_exr/sky.exr" --lobes 40 -o "$D/sky.json"
else
    skip fit_shared_map "no shared data"
fi

# fit's lobe count has an upper bound with its reason (100000 used to be accepted and ran for
# hours without a word); nothing is written
err=$("$SL" fit data/env/city_256.hdr --lobes 100000 -o "$TMP/fit_big.json" 2>&1); rc=$?
if [ "$rc" -eq 2 ] && printf '%s' "$err" | grep -q 'at most 512 (the fit.s cost grows' && [ ! -e "$TMP/fit_big.json" ]; then
    pass fit_lobes_upper_bound
else fail fit_lobes_upper_bound "exit $rc: $err"; fi

# a lobes file fitted to another map than environment.file is refused naming the key; the
# matching pair renders
L="$TMP/fitpair"; rm -rf "$L"; mkdir -p "$L"
"$SL" fit data/env/city_256.hdr --lobes 2 -o "$L/city.lobes.json" -q 2>/dev/null
python3 - "$L" <<'PY'
import sys
# a 16x8 Radiance HDR of one constant colour, written by hand (RLE-free scanlines, 4 bytes/pixel)
d = sys.argv[1]
w, h = 16, 8
with open(d + "/flat.hdr", "wb") as f:
    f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
    f.write(bytes([128, 128, 128, 129]) * (w * h))
PY
for m in city flat; do
    map="$PWD/data/env/city_256.hdr"; [ $m = flat ] && map="flat.hdr"
    printf '{"hair": {"procedural": {"strands": 20, "points": 6}}, "environment": {"file": "%s", "lobes": "city.lobes.json"}, "image": {"width": 16, "height": 12}}\n' "$map" > "$L/$m.json"
done
expect_ok fit_lobes_match_map "$SL" render "$L/city.json" --device c -o "$L/a.exr"
expect_error fit_lobes_other_map "environment.lobes: " "$SL" render "$L/flat.json" --device c -o "$L/b.exr"
if [ ! -e "$L/b.exr" ]; then pass fit_lobes_other_map_no_output; else fail fit_lobes_other_map_no_output "wrote b.exr"; fi
