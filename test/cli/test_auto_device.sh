# test_auto_device.sh: `render --device auto` on a CPU OpenCL device (host/plan/auto_device.h,
# docs/opencl.md "auto on a CPU device"): the first run times a proxy frame on the device and on
# C and says which it picked and why (an --explain row "device run", a notice on stderr), caches
# the choice (an auto-device entry), and the next run reuses it ("device cached", the same
# choice, no trial); the frame then runs where the choice says (the light row's "(C)" or
# "(OpenCL)"). A damaged entry is measured again. A GPU is used without a trial; an explicit
# --device and the C path never get a device row. Which path wins is a measurement: the test
# checks only that the render follows the choice it reports.
. test/cli/lib.sh
D="$TMP/auto_device"
rm -rf "$D"; mkdir -p "$D"
export SL_CACHE_DIR="$D/cache"
cat > "$D/lobes.json" <<'JSON'
{"lobes": [{"dir": [0, 1, 0], "lambda": 0.5, "rgb": [1, 0.9, 0.8]},
           {"dir": [0.6, 0, 0.8], "lambda": 2.0, "rgb": [0.1, 0.2, 0.3]}]}
JSON
cat > "$D/scene.json" <<'JSON'
{
  "hair": {"procedural": {"style": "wavy", "strands": 60, "points": 8, "seed": 1}, "radius": 0.04},
  "material": {"eta": 1.55, "sigma_a": [0.18, 0.32, 0.62]},
  "environment": {"lobes": "lobes.json"},
  "camera": {"fov_deg": 30},
  "image": {"width": 48, "height": 32}
}
JSON
r() { "$SL" render "$D/scene.json" --explain "$@"; }

# the C path and an explicit device: no choice, no device row
out=$(r --device c -o "$D/c.exr" 2>/dev/null)
if ! printf '%s\n' "$out" | grep -q '^device '; then pass auto_device_c_no_row
else fail auto_device_c_no_row "$(printf '%s\n' "$out" | grep '^device ')"; fi
out=$(OCL_ICD_VENDORS=/nonexistent "$SL" render "$D/scene.json" --explain -o "$D/n.exr" 2>/dev/null); rc=$?
if [ $rc -eq 0 ] && ! printf '%s\n' "$out" | grep -q '^device '; then pass auto_device_no_opencl_no_row
else fail auto_device_no_opencl_no_row "rc=$rc $(printf '%s\n' "$out" | grep '^device ')"; fi
if ! have_cl; then
    skip auto_device_trial "no OpenCL device"
    exit 0
fi
out=$(r --device "$SL_CL_DEVICE" -o "$D/x.exr" 2>/dev/null)
if ! printf '%s\n' "$out" | grep -q '^device '; then pass auto_device_explicit_no_row
else fail auto_device_explicit_no_row "$(printf '%s\n' "$out" | grep '^device ')"; fi
if "$SL" devices 2>/dev/null | grep -q '^ *type GPU'; then
    out=$(r --device auto -o "$D/g.exr" 2>/dev/null)
    if printf '%s\n' "$out" | grep -q '^device  *skipped .*a GPU device: used without a trial'; then pass auto_device_gpu_no_trial
    else fail auto_device_gpu_no_trial "$(printf '%s\n' "$out" | head -3)"; fi
    exit 0
fi

# light row of the plan: where the frame ran ("(C)" or "(OpenCL)")
light_on() { printf '%s\n' "$1" | sed -n 's/^light .* kappa [0-9.]* (\(C\|OpenCL\)) .*/\1/p'; }
# the choice a device row reports: C or OpenCL
chosen() {
    if printf '%s\n' "$1" | grep -q '^device .*auto on a CPU OpenCL device: C path, faster here'; then echo C
    elif printf '%s\n' "$1" | grep -q '^device .*auto on a CPU OpenCL device: kept the device, faster here'; then echo OpenCL
    fi
}
out1=$(r --device auto -o "$D/a1.exr" 2>"$D/err1"); rc=$?
c1=$(chosen "$out1")
if [ $rc -eq 0 ] && printf '%s\n' "$out1" | grep -q '^device  *run  *[0-9.]*s  auto on a CPU OpenCL device: .* [0-9.]* s, C path [0-9.]* s per frame of a proxy: .*measured now, cached)$' &&
   [ -n "$c1" ]; then pass auto_device_trial_row
else fail auto_device_trial_row "rc=$rc $(printf '%s\n' "$out1" | head -2) $(tail -1 "$D/err1")"; fi
if [ "$(grep -c '^strandlight: device: auto on a CPU OpenCL device: ' "$D/err1")" -eq 1 ]; then pass auto_device_trial_notice
else fail auto_device_trial_notice "$(cat "$D/err1")"; fi
if [ "$(light_on "$out1")" = "$c1" ]; then pass auto_device_frame_follows_choice
else fail auto_device_frame_follows_choice "chose '$c1', light pass on '$(light_on "$out1")'"; fi
n=$(ls "$SL_CACHE_DIR" | grep -c '^auto-device-.*\.bin$')
if [ "$n" -eq 1 ]; then pass auto_device_cached_entry; else fail auto_device_cached_entry "$n entries: $(ls "$SL_CACHE_DIR")"; fi
no_leftovers auto_device_no_temp "$SL_CACHE_DIR"

out2=$(r --device auto -o "$D/a2.exr" 2>"$D/err2"); rc=$?
if [ $rc -eq 0 ] && printf '%s\n' "$out2" | grep -q '^device  *cached .*measured before, from the disk cache)$' &&
   [ "$(chosen "$out2")" = "$c1" ] && [ "$(light_on "$out2")" = "$c1" ]; then pass auto_device_reuses_choice
else fail auto_device_reuses_choice "rc=$rc first '$c1' $(printf '%s\n' "$out2" | head -2)"; fi
# the same choice renders the same image
if cmp -s "$D/a1.exr" "$D/a2.exr"; then pass auto_device_reused_same_image
else fail auto_device_reused_same_image "a1.exr and a2.exr differ"; fi
# a different scene shape is a different entry (measured afresh)
out3=$(r --device auto -o "$D/a3.exr" --width 40 2>/dev/null)
if printf '%s\n' "$out3" | grep -q '^device  *run ' &&
   [ "$(ls "$SL_CACHE_DIR" | grep -c '^auto-device-.*\.bin$')" -eq 2 ]; then pass auto_device_shape_keyed
else fail auto_device_shape_keyed "$(printf '%s\n' "$out3" | head -1); $(ls "$SL_CACHE_DIR")"; fi
# a damaged entry is a miss: measured again and rewritten
for f in "$SL_CACHE_DIR"/auto-device-*.bin; do printf 'garbage' >"$f"; done
out4=$(r --device auto -o "$D/a4.exr" 2>/dev/null); rc=$?
if [ $rc -eq 0 ] && printf '%s\n' "$out4" | grep -q '^device  *run .*measured now, cached)$'; then pass auto_device_damaged_entry_remeasured
else fail auto_device_damaged_entry_remeasured "rc=$rc $(printf '%s\n' "$out4" | head -1)"; fi
# no disk cache: measured every run, said so
out5=$(SL_CACHE_DIR=off r --device auto -o "$D/a5.exr" 2>/dev/null); rc=$?
if [ $rc -eq 0 ] && printf '%s\n' "$out5" | grep -q '^device  *run .*measured now, no disk cache)$'; then pass auto_device_no_cache
else fail auto_device_no_cache "rc=$rc $(printf '%s\n' "$out5" | head -1)"; fi
