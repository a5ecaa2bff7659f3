#!/usr/bin/env bash
# make_doc_images.sh [BUILD]: regenerates the issue-8 images in docs/img/ (docs/volume.md,
# "Renders"): the default scene's hair (4000 wavy strands, city map, 24 lobes) at 320x240 with
#   blond.png       data/blond.json (eumelanin 0.3 + pheomelanin 0.1), multiple scattering on
#   blond_noms.png  the same with quality.multiple_scattering off (single scattering only)
#   dark.png        data/dark.json (eumelanin 1.4), multiple scattering auto (the planner
#                   runs it: estimated share 0.035, threshold 0.02; small in the image)
# Each render prints its plan (--explain); at the end the mean luminance of each frame. About 4-6 s per image on 2 shared cores.
set -eu
BUILD=${1:-build}
SL="$BUILD/strandlight"
OUT=docs/img
D=$(mktemp -d)
trap 'rm -rf "$D"' EXIT
mkdir -p "$OUT"
# MS-off variant of blond.json: same scene, absolute map path (the copy lives in $D).
sed -e 's/"multiple_scattering": "on"/"multiple_scattering": "off"/' \
    -e "s#\"env/city_256.hdr\"#\"$PWD/data/env/city_256.hdr\"#" data/blond.json > "$D/blond_noms.json"
grep -q '"multiple_scattering": "off"' "$D/blond_noms.json"
"$SL" render data/blond.json --exr "$D/blond.exr" --png "$OUT/blond.png" --explain
"$SL" render "$D/blond_noms.json" --exr "$D/blond_noms.exr" --png "$OUT/blond_noms.png" --explain
"$SL" render data/dark.json --exr "$D/dark.exr" --png "$OUT/dark.png" --explain
# Mean luminance per pixel of each frame (background 0 included; same coverage in all three).
for f in blond blond_noms dark; do
    printf '%-11s %s\n' "$f" "$("$SL" info "$D/$f.exr" | grep 'luminance mean (per pixel)')"
done
ls -l "$OUT"/blond.png "$OUT"/blond_noms.png "$OUT"/dark.png
