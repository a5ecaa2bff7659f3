#!/usr/bin/env bash
# same_output.sh [REV] [BUILD]: shows that the tree's outputs are byte-identical to those of
# git revision REV (default: HEAD) on the shipped scenes. It builds REV in a detached worktree
# (build-same/base), runs the same commands with REV's binary and with BUILD/strandlight (default
# build/, built by `make`), each with a cache directory of its own (SL_CACHE_DIR: nothing fitted,
# tabulated or compiled by one is read by the other), and compares every file they write with
# cmp. Used to check refactors that must change no pixel (docs/design.md); prints one line per
# case and "N identical, N differ" at the end; exit 0 only when every output is identical.
#
# Cases: every data/*.json scene on the C path with every AOV (report scenes need ../shared, and
# are rendered at 200x150 to keep this to a few minutes), the default scene with each SRBF method
# and on PoCL when it is present, an orbit, `eval` on the committed stiff sample, `fit`, and a
# small `reference`. OLD_BIN=PATH uses a binary of REV built elsewhere instead of building it.
set -u
cd "$(dirname "$0")/.."
REV=${1:-HEAD}
BUILD=${2:-build}
ROOT=$PWD
WORK=$ROOT/build-same
NEW=$ROOT/$BUILD/strandlight
[ -x "$NEW" ] || { echo "same_output.sh: $NEW missing (run make)" >&2; exit 2; }
mkdir -p "$WORK"
if [ -n "${OLD_BIN:-}" ]; then
    OLD=$OLD_BIN   # a binary of REV built elsewhere (with its own kernels/ tree)
else
if [ -d "$WORK/base" ]; then git worktree remove --force "$WORK/base" >/dev/null 2>&1 || rm -rf "$WORK/base"; fi
git worktree prune
git worktree add --detach "$WORK/base" "$REV" >/dev/null 2>&1 || { echo "same_output.sh: cannot check out $REV" >&2; exit 2; }
echo "same_output: building $REV in $WORK/base ..."
make -C "$WORK/base" -j2 build/strandlight >"$WORK/base-build.log" 2>&1 ||
    { echo "same_output.sh: build of $REV failed (see $WORK/base-build.log)" >&2; exit 2; }
OLD=$WORK/base/build/strandlight
fi
# Fresh caches on both sides: `--method auto` picks Ren's table when one is cached, so a cache
# left by an earlier run would change what a binary renders.
rm -rf "$WORK/out" "$WORK/cache"; mkdir -p "$WORK/out/old" "$WORK/out/new" "$WORK/cache/old" "$WORK/cache/new"

same=0; differ=0
# Run times differ between any two runs: keys of the JSON side files that hold a time (or a
# path of the run's own output folder) are dropped before the comparison. So is "integrity" (a
# reference record's digest of the EXR beside it, since issue #17): the EXR itself is compared.
normalise() {
    find "$1" -name '*.json' -print0 | xargs -0 -r python3 -c '
import json, re, sys
def clean(v):
    if isinstance(v, dict):
        return {k: clean(x) for k, x in v.items() if not re.search("time|seconds|elapsed|date|path|_s$", k) and k != "integrity"}
    if isinstance(v, list):
        return [clean(x) for x in v]
    return v
for f in sys.argv[1:]:
    try:
        d = json.load(open(f))
    except Exception:
        continue
    json.dump(clean(d), open(f, "w"), indent=1, sort_keys=True)
'
}
# run NAME ARGS...: runs `strandlight ARGS` with each binary; @OUT@ in ARGS is the binary's own
# output directory. Stdout is kept (eval writes CSV there); stderr (timings) is not compared.
run() {
    local name=$1; shift
    local side bin
    for side in old new; do
        if [ $side = old ]; then bin=$OLD; else bin=$NEW; fi
        local out=$WORK/out/$side/$name
        mkdir -p "$out"
        local args=()
        local a
        for a in "$@"; do args+=("${a//@OUT@/$out}"); done
        SL_CACHE_DIR=$WORK/cache/$side "$bin" "${args[@]}" >"$out/stdout" 2>"$out/stderr" </dev/null
        echo "$?" >"$out/status"
        # Messages name the run's own folder and its time: neither is an output.
        sed -i -E "s#$out#OUT#g; s/[0-9]+(\.[0-9]+)? s\b/T s/g" "$out/stdout"
        normalise "$out"
    done
    if diff -r "$WORK/out/old/$name" "$WORK/out/new/$name" -x stderr >/dev/null 2>&1; then
        echo "identical $name"; same=$((same + 1))
    else
        echo "DIFFER    $name"; differ=$((differ + 1))
        diff -rq "$WORK/out/old/$name" "$WORK/out/new/$name" -x stderr | head -5
    fi
}
# run_stdin NAME FILE ARGS...: as run, with FILE on stdin.
run_stdin() {
    local name=$1 input=$2; shift 2
    local side bin
    for side in old new; do
        if [ $side = old ]; then bin=$OLD; else bin=$NEW; fi
        local out=$WORK/out/$side/$name
        mkdir -p "$out"
        SL_CACHE_DIR=$WORK/cache/$side "$bin" "$@" <"$input" >"$out/stdout" 2>"$out/stderr"
        echo "$?" >"$out/status"
    done
    if diff -r "$WORK/out/old/$name" "$WORK/out/new/$name" -x stderr >/dev/null 2>&1; then
        echo "identical $name"; same=$((same + 1))
    else
        echo "DIFFER    $name"; differ=$((differ + 1))
    fi
}

for scene in data/*.json; do
    stem=$(basename "$scene" .json)
    size=()
    case $stem in report_*)
        [ -d ../shared/data ] || { echo "skipped   $stem (no ../shared/data)"; continue; }
        size=(--width 200 --height 150) ;;
    esac
    run "render_$stem" render "$scene" "${size[@]}" --device c --aov all \
        --exr @OUT@/frame.exr --png @OUT@/frame.png
done
for m in fast xu table; do
    run "render_default_$m" render data/default.json --device c --method $m --width 320 --height 240 \
        --exr @OUT@/frame.exr --png @OUT@/frame.png
done
run render_default_fragment render data/default.json --device c --shading-rate fragment \
    --width 320 --height 240 --exr @OUT@/frame.exr
run render_default_orbit render data/default.json --device c --orbit 3 --width 160 --height 120 \
    --exr @OUT@/orbit.exr
if "$NEW" devices 2>/dev/null | grep -qi pocl; then
    run render_default_pocl render data/default.json --device pocl --width 320 --height 240 \
        --aov all --exr @OUT@/frame.exr
fi
run_stdin eval_srbf_fast test/test_srbf_stiff.csv eval srbf --method fast --backend c
run_stdin eval_srbf_exact_head <(head -20 test/test_srbf_stiff.csv) eval srbf --method exact --backend reference
run fit_city fit data/env/city_256.hdr --lobes 8 -o @OUT@/lobes.json
run reference_blond reference data/blond.json -o @OUT@/ref.exr --lights 16 --width 64 --height 48
run reference_blond_frag reference data/blond.json -o @OUT@/ref.exr --lights 8 --width 64 --height 48 --fragments

echo "$same identical, $differ differ"
git worktree remove --force "$WORK/base" >/dev/null 2>&1
[ "$differ" -eq 0 ]
