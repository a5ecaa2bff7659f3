# test_shipped_scenes.sh: every scene shipped in data/ loads and renders (a user's first
# commands: README "Scenes"). Each is rendered at 32 x 24 (a copy with its relative paths made
# absolute and its outputs dropped, so nothing in data/ or out/ is written) on the C path; a scene
# whose files live in ../shared/data skips when that is absent. (data/blond.json and dark.json
# had an extra "}" from session 5 to 12, which the tests did not see: nothing rendered them.)
. test/cli/lib.sh
D="$TMP/shipped_scenes"
rm -rf "$D"; mkdir -p "$D"
PY=python3; [ -x /usr/bin/python3 ] && PY=/usr/bin/python3
for f in data/*.json; do
    n="shipped_scene_$(basename "$f" .json)"
    if grep -q '"\.\./\.\./shared/' "$f" && ! have_shared; then skip "$n" "needs ../shared/data"; continue; fi
    if ! "$PY" - "$f" "$D/$(basename "$f")" "$SHARED" <<'PY' 2>"$D/py.err"; then
import json, os, sys
src, dst, shared = sys.argv[1:4]
s = json.load(open(src))
base = os.path.dirname(os.path.abspath(src))
for sect in ("hair", "environment"):
    v = s.get(sect, {}).get("file")
    if isinstance(v, str) and not os.path.isabs(v):
        s[sect]["file"] = os.path.normpath(os.path.join(base, v))
lobes = s.get("environment", {}).get("lobes")
if isinstance(lobes, str) and not os.path.isabs(lobes):
    s["environment"]["lobes"] = os.path.normpath(os.path.join(base, lobes))
s.pop("output", None)
s["image"] = {"width": 32, "height": 24}
json.dump(s, open(dst, "w"))
PY
        fail "$n" "not valid JSON: $(tail -1 "$D/py.err")"; continue
    fi
    if "$SL" --quiet render "$D/$(basename "$f")" --device c -o "$D/out.exr" 2>"$D/err" &&
        [ -s "$D/out.exr" ]; then
        pass "$n"
    else
        fail "$n" "render failed: $(head -1 "$D/err")"
    fi
    rm -f "$D/out.exr"
done
