# test_cache_concurrency.sh: several processes filling the same SL_CACHE_DIR at once must not
# corrupt it (docs/robustness.md). Cache writers use sl_cache_write (host/base/disk_cache.h): a
# temporary name unique per process (pid + counter, O_EXCL) renamed over the entry, so a reader
# sees the old entry, no entry, or a whole new one; damaged entries fail their hash. Checked: every concurrent run succeeds with the same output; a
# later run reads every entry from the cache (none rejected as corrupt, nothing rebuilt); no
# temporary file is left. Caches covered: the fitted lobes and SRBF tables (`render` with an
# environment file) and the OpenCL program binaries (`kernels`, when there is a device).
. test/cli/lib.sh
D="$TMP/cache_conc"
rm -rf "$D"; mkdir -p "$D"
cp data/env/city_256.hdr "$D/"
for i in 1 2 3; do
    cat > "$D/scene$i.json" <<JSON
{
  "hair": {"procedural": {"style": "wavy", "strands": 20, "points": 8, "seed": 1}, "radius": 0.04},
  "material": {"eta": 1.55, "sigma_a": [0.18, 0.32, 0.62]},
  "environment": {"file": "city_256.hdr"},
  "camera": {"fov_deg": 30},
  "image": {"width": 16, "height": 12},
  "quality": {"lobes": 4},
  "output": {"exr": "out$i/f.exr"}
}
JSON
done
export SL_CACHE_DIR="$D/cache"

# Two renders start together on an empty cache: both fit, both write the same entries.
pids=""
for i in 1 2; do
    "$SL" render "$D/scene$i.json" --device c >"$D/r$i.log" 2>&1 &
    pids="$pids $!"
done
ok=1
for p in $pids; do wait "$p" || ok=0; done
if [ "$ok" -ne 1 ]; then fail cache_conc_render_all_ok "$(cat "$D"/r*.log | tail -n 2)"
elif ! cmp -s "$D/out1/f.exr" "$D/out2/f.exr"; then
    fail cache_conc_render_all_ok "the concurrent runs gave different images"
else pass cache_conc_render_all_ok; fi
out=$("$SL" render "$D/scene3.json" --device c 2>&1); rc=$?
if [ $rc -eq 0 ] && printf '%s' "$out" | grep -q "lobes from the cache" &&
    ! printf '%s' "$out" | grep -qi "bad cache entry\|ignoring\|fitted" && cmp -s "$D/out1/f.exr" "$D/out3/f.exr"; then
    pass cache_conc_render_entries_valid
else fail cache_conc_render_entries_valid "rc=$rc $(printf '%s' "$out" | head -3)"; fi
no_leftovers cache_conc_render_no_temp "$SL_CACHE_DIR"

# Damaged entries are rebuilt, never trusted (host/base/disk_cache.h: a header with the key and
# a hash of the payload): one byte changed in the lobes entry, the SRBF tables cut short. The
# run warns, fits again, gives the same image and rewrites both; the next run reads them.
lobes_entry=$(ls "$SL_CACHE_DIR"/lobes-*.bin 2>/dev/null | head -1)
tables_entry=$(ls "$SL_CACHE_DIR"/srbf-tables-*.bin 2>/dev/null | head -1)
if [ -z "$lobes_entry" ] || [ -z "$tables_entry" ]; then
    fail cache_conc_damaged_rebuilt "missing entries: $(ls "$SL_CACHE_DIR")"
else
    printf 'X' | dd of="$lobes_entry" bs=1 seek=100 conv=notrunc 2>/dev/null
    truncate -s -1 "$tables_entry"
    out=$("$SL" render "$D/scene3.json" --device c 2>&1); rc=$?
    if [ $rc -eq 0 ] && printf '%s' "$out" | grep -q "ignoring a bad cache entry" &&
        printf '%s' "$out" | grep -q "fitted" && cmp -s "$D/out1/f.exr" "$D/out3/f.exr"; then
        pass cache_conc_damaged_rebuilt
    else fail cache_conc_damaged_rebuilt "rc=$rc $(printf '%s' "$out" | head -3)"; fi
    out=$("$SL" render "$D/scene3.json" --device c 2>&1); rc=$?
    if [ $rc -eq 0 ] && printf '%s' "$out" | grep -q "lobes from the cache" &&
        ! printf '%s' "$out" | grep -qi "bad cache entry\|srbf tables built"; then
        pass cache_conc_damaged_rewritten
    else fail cache_conc_damaged_rewritten "rc=$rc $(printf '%s' "$out" | head -3)"; fi
fi

# OpenCL program binaries: two `kernels` runs on an empty program cache at once.
if ! have_cl; then
    skip cache_conc_kernels "no OpenCL device"
else
    export SL_CACHE_DIR="$D/clcache"
    pids=""
    for i in 1 2; do
        "$SL" kernels --device "$SL_CL_DEVICE" --only prefix_sum_serial --size 64 --reps 1 >"$D/k$i.log" 2>&1 &
        pids="$pids $!"
    done
    ok=1
    for p in $pids; do wait "$p" || ok=0; done
    if [ "$ok" -ne 1 ]; then fail cache_conc_kernels_all_ok "$(cat "$D"/k*.log | tail -n 2)"; else pass cache_conc_kernels_all_ok; fi
    out=$("$SL" kernels --device "$SL_CL_DEVICE" --only prefix_sum_serial --size 64 --reps 1 2>&1); rc=$?
    if [ $rc -eq 0 ] && printf '%s' "$out" | grep -q "0 built from source, 1 from the disk cache"; then
        pass cache_conc_kernels_entries_valid
    else fail cache_conc_kernels_entries_valid "rc=$rc $(printf '%s' "$out" | tail -1)"; fi
    no_leftovers cache_conc_kernels_no_temp "$SL_CACHE_DIR"
    # a forged entry (issue 21): prefix_sum's name, key and a valid hash, but another program's
    # binary (dual's). It must be rebuilt from source, not fail this run and every later one.
    "$SL" kernels --device "$SL_CL_DEVICE" --only dual --reps 1 >/dev/null 2>&1
    ps=$(ls "$SL_CACHE_DIR"/prefix_sum-*.bin 2>/dev/null | head -1)
    du=$(ls "$SL_CACHE_DIR"/dual-*.bin 2>/dev/null | head -1)
    if [ -n "$ps" ] && [ -n "$du" ] && "${PY:-python3}" - "$ps" "$du" <<'PYEOF'
import struct, sys
ps, du = sys.argv[1], sys.argv[2]
head = open(ps, "rb").read()[:48]
body = open(du, "rb").read()[48:]
h = 1469598103934665603
for b in body:
    h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
open(ps, "wb").write(head[:32] + struct.pack("<QQ", len(body), h) + body)
PYEOF
    then
        out=$("$SL" kernels --device "$SL_CL_DEVICE" --only prefix_sum_serial --size 64 --reps 1 2>&1); rc=$?
        if [ $rc -eq 0 ] && printf '%s' "$out" | grep -q "1 built from source, 0 from the disk cache"; then
            pass cache_forged_program_rebuilt
        else fail cache_forged_program_rebuilt "rc=$rc $(printf '%s' "$out" | tail -2)"; fi
        out=$("$SL" kernels --device "$SL_CL_DEVICE" --only prefix_sum_serial --size 64 --reps 1 2>&1); rc=$?
        if [ $rc -eq 0 ] && printf '%s' "$out" | grep -q "0 built from source, 1 from the disk cache"; then
            pass cache_forged_program_rewritten
        else fail cache_forged_program_rewritten "rc=$rc $(printf '%s' "$out" | tail -2)"; fi
    else
        fail cache_forged_program_rebuilt "no prefix_sum / dual entries to forge: $(ls "$SL_CACHE_DIR")"
    fi
fi
