# reference_lib.sh: the setup test_reference.sh and test_reference_split.sh share (sourced after
# lib.sh; not a test itself, so no test_ prefix: test/run.sh runs only test/cli/test_*.sh).
# ref_setup NAME: D=$TMP/NAME, emptied; PY = python3 (without one: skip NAME and exit 0); writes
# $D/sky.hdr, a 16 x 8 flat RGBE map: a bright warm band near the top, a dim blue ground.
ref_setup() {
    D="$TMP/$1"
    rm -rf "$D"
    mkdir -p "$D"
    if [ -z "${PY:-}" ]; then
        if [ -x /usr/bin/python3 ]; then PY=/usr/bin/python3; else PY=python3; fi
    fi
    if ! command -v "$PY" >/dev/null 2>&1; then skip "$1" "no python3"; exit 0; fi
    "$PY" - "$D" <<'PYEOF'
import sys, math
d = sys.argv[1]
w, h = 16, 8
def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32: return bytes([0, 0, 0, 0])
    e = math.frexp(m)[1]
    s = 256.0 / (2.0 ** e)
    return bytes([int(r * s), int(g * s), int(b * s), e + 128])
px = b"".join(rgbe(*((4.0, 3.0, 2.0) if y < 2 else (0.2, 0.3, 0.6))) for y in range(h) for x in range(w))
open(d + "/sky.hdr", "wb").write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w) + px)
PYEOF
}
