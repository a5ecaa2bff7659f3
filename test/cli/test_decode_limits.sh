# test_decode_limits.sh: decode limits from the header (issue 21, docs/robustness.md sec. 5): a
# 49 KB EXR whose header declares 16384 x 8192 (the DWAB bomb of the issue, made by
# test/cli/exr_header_bomb.py) is refused by `info` and `render` from its header, one line naming
# the file, the limit and the variable that raises it, exit 1; raising the limit reaches the next
# limit (the decompression ratio), never the decoder.
. test/cli/lib.sh
D="$TMP/decode_limits"
rm -rf "$D"
mkdir -p "$D"
python3 test/cli/exr_header_bomb.py "$D/bomb.exr" 16384 8192 9 49152
expect_error limits_exr_info_memory "bomb.exr: OpenEXR: decoding 16384 x 8192 needs 3072 MiB, over the limit of 2048 MiB (SL_IMAGE_MAX_MB raises it)" \
    "$SL" info "$D/bomb.exr"
export SL_IMAGE_MAX_MB=100000
expect_error limits_exr_info_ratio "over 1100 bytes per file byte (SL_IMAGE_MAX_RATIO raises it)" \
    "$SL" info "$D/bomb.exr"
unset SL_IMAGE_MAX_MB
cat > "$D/s.json" <<JSON
{"hair": {"procedural": {"style": "wavy", "strands": 10, "points": 8, "seed": 1}, "radius": 0.05},
 "environment": {"file": "bomb.exr"}, "image": {"width": 16, "height": 12}}
JSON
expect_error limits_exr_render_env "bomb.exr: OpenEXR: decoding 16384 x 8192 needs 3072 MiB" \
    "$SL" render "$D/s.json" --device c --exr "$D/out.exr"
if [ ! -e "$D/out.exr" ]; then pass limits_exr_render_no_output; else fail limits_exr_render_no_output "out.exr written"; fi
# a legitimate map under the limits still loads
if "$SL" info data/env/city_256.hdr >/dev/null 2>&1; then pass limits_small_map_loads
else fail limits_small_map_loads "city_256.hdr refused"; fi
