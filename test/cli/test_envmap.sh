# test_envmap.sh: `strandlight info` on environment maps: the shipped default map, the shared
# maps (when ../shared/data is present), and one-line errors for bad files.
. test/cli/lib.sh
D="$TMP/envmap"
mkdir -p "$D"

expect_output envmap_info_default_size "size: 256 x 128" "$SL" info data/env/city_256.hdr
expect_output envmap_info_default_format "format: Radiance RGBE" "$SL" info data/env/city_256.hdr
expect_output envmap_info_default_sun "at pixel (153, 30)" "$SL" info data/env/city_256.hdr

if have_shared; then
    expect_output envmap_info_dwab "format: OpenEXR float RGB (DWAB)" "$SL" info "$SHARED/envmaps/blender_exr/city.exr"
    expect_output envmap_info_dwab_negatives "negative values: 506" "$SL" info "$SHARED/envmaps/blender_exr/city.exr"
    expect_output envmap_info_half_negatives "negative values: 33" "$SL" info "$SHARED/envmaps/pmndrs/npm_exr/sky.exr"
    expect_output envmap_info_nonfinite_zero "non-finite values: 0" "$SL" info "$SHARED/envmaps/pmndrs/sky.hdr"
    head -c 3000 "$SHARED/envmaps/pmndrs/npm_exr/venice.exr" > "$D/trunc.exr"
    expect_error envmap_truncated_exr "trunc.exr: OpenEXR" "$SL" info "$D/trunc.exr"
else
    skip envmap_info_shared "../shared/data not present"
fi

: > "$D/empty.hdr"
expect_error envmap_empty "empty.hdr: empty file" "$SL" info "$D/empty.hdr"
printf 'GIF89a not a map' > "$D/magic.exr"
expect_error envmap_wrong_magic "magic.exr: not an OpenEXR or Radiance .hdr file" "$SL" info "$D/magic.exr"
mkdir -p "$D/dir.hdr"
expect_error envmap_directory "dir.hdr: is a directory" "$SL" info "$D/dir.hdr"
expect_error envmap_missing "nosuch.exr" "$SL" info "$D/nosuch.exr"
head -c 20000 data/env/city_256.hdr > "$D/trunc.hdr"
expect_error envmap_truncated_hdr "trunc.hdr: Radiance .hdr: truncated" "$SL" info "$D/trunc.hdr"
printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 200000\n' > "$D/huge.hdr"
expect_error envmap_absurd_size "huge.hdr: Radiance .hdr: implausible size" "$SL" info "$D/huge.hdr"
printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 0 +X 0\n' > "$D/zero.hdr"
expect_error envmap_zero_size "zero.hdr: Radiance .hdr" "$SL" info "$D/zero.hdr"
printf '#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 2 +X 2\n' > "$D/xyze.hdr"
expect_error envmap_xyze "unsupported FORMAT=32-bit_rle_xyze" "$SL" info "$D/xyze.hdr"
# An EXR header that declares a gigantic data window (4096 x 4096) in a tiny file.
printf '\x76\x2f\x31\x01\x02\x00\x00\x00channels\x00chlist\x00\x25\x00\x00\x00B\x00\x01\x00\x00\x00\x00\x00\x00\x00\x01\x00\x00\x00\x01\x00\x00\x00G\x00\x01\x00\x00\x00\x00\x00\x00\x00\x01\x00\x00\x00\x01\x00\x00\x00\x00compression\x00compression\x00\x01\x00\x00\x00\x03dataWindow\x00box2i\x00\x10\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\xff\x0f\x00\x00\xff\x0f\x00\x00displayWindow\x00box2i\x00\x10\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\xff\x0f\x00\x00\xff\x0f\x00\x00lineOrder\x00lineOrder\x00\x01\x00\x00\x00\x00pixelAspectRatio\x00float\x00\x04\x00\x00\x00\x00\x00\x80\x3fscreenWindowCenter\x00v2f\x00\x08\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00screenWindowWidth\x00float\x00\x04\x00\x00\x00\x00\x00\x80\x3f\x00' > "$D/huge.exr"
expect_error envmap_absurd_exr "huge.exr: OpenEXR" "$SL" info "$D/huge.exr"
