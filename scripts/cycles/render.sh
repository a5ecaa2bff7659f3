#!/usr/bin/env bash
# render.sh SCENE.json OUT.exr --spp N --seed S [--width W --height H] [--threads T]
#           [--keep-hair FILE.hair] [render_cycles.py options: --offset-sign, --env-interp, --half]
#
# A Strandlight scene rendered by Blender Cycles (docs/validation.md, "Against Blender Cycles"):
#   1. strandlight export SCENE.json -o HAIR [--width W --height H]   (strands + camera sidecar)
#   2. blender -b --factory-startup -P scripts/cycles/render_cycles.py -- SCENE.json OUT.exr ...
# HAIR is a temporary file unless --keep-hair names one. Blender's own log goes to OUT.exr.log.
# Blender is never a build or test dependency: BLENDER (default `blender` on PATH) must be
# installed by hand (Debian: apt-get install blender, 3.4). SL is the strandlight binary (default
# build/strandlight of this checkout). Errors: one line on stderr, exit 1.
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
SL=${SL:-$root/build/strandlight}
BLENDER=${BLENDER:-blender}
die() { echo "render.sh: $*" >&2; exit 1; }

[ $# -ge 2 ] || die "usage: render.sh SCENE.json OUT.exr --spp N --seed S [--width W --height H] [--threads T] [--keep-hair FILE.hair]"
scene=$1 out=$2; shift 2
case "$out" in *.exr) ;; *) die "$out: the output must be a .exr file" ;; esac
[ -f "$scene" ] || die "$scene: no such scene file"
command -v "$BLENDER" >/dev/null 2>&1 || die "no Blender ('$BLENDER' not found; apt-get install blender, or set BLENDER)"
[ -x "$SL" ] || die "$SL: no strandlight binary (run make, or set SL)"

size=() pass=() keep=""
while [ $# -gt 0 ]; do
    case "$1" in
        --width|--height) [ $# -ge 2 ] || die "$1 needs a value"; size+=("$1" "$2"); pass+=("$1" "$2"); shift 2 ;;
        --keep-hair) [ $# -ge 2 ] || die "$1 needs a value"; keep=$2; shift 2 ;;
        *) pass+=("$1"); shift ;;
    esac
done

tmp=$(mktemp -d "${TMPDIR:-/tmp}/cycles_render.XXXXXX") || die "cannot make a temporary directory"
trap 'rm -rf "$tmp"' EXIT
hair=${keep:-$tmp/strands.hair}
if ! msg=$("$SL" export "$scene" -o "$hair" "${size[@]}" 2>&1 >/dev/null); then
    die "$(printf '%s' "$msg" | tail -1)"
fi

mkdir -p "$(dirname "$out")" || die "$out: cannot make its directory"
log=$out.log
"$BLENDER" -b --factory-startup --python-exit-code 1 -P "$here/render_cycles.py" -- \
    "$scene" "$out" --hair "$hair" "${pass[@]}" >"$log" 2>&1
rc=$?
line=$(grep -a '^render_cycles.py: ' "$log" | tail -1)
if [ $rc -ne 0 ] || [ ! -f "$out" ]; then
    if [ -n "$line" ]; then rm -f "$log"; else
        line="Blender failed (exit $rc): $(grep -a -i 'error' "$log" | tail -1) (log: $log)"; fi
    echo "${line#render_cycles.py: }" | sed 's/^/render.sh: /' >&2
    exit 1
fi
echo "$line"
