#!/usr/bin/env bash
# bench_fiber.sh [BUILD_DIR]: evaluations per second of `strandlight eval scatter` (Marschner,
# default material) on each backend, for docs/numerics.md. Random directions (fixed seed);
# wall time of the whole command, so CSV parsing/printing is included (measured separately
# with a header-only run and the --backend c run of the same rows is dominated by it for small
# N). Prints one line per backend: rows, seconds, evals/s, ratio to the reference.
set -eu
BUILD=${1:-build}
SL="$BUILD/strandlight"
TMP="$BUILD/bench-fiber"
mkdir -p "$TMP"
gen() { # gen N FILE: N random rows (theta in [-pi/2, pi/2], phi in (-pi, pi])
    python3 - "$1" "$2" <<'PY'
import math, random, sys
n, path = int(sys.argv[1]), sys.argv[2]
r = random.Random(12345)
with open(path, "w") as f:
    f.write("theta_i,phi_i,theta_o,phi_o\n")
    for _ in range(n):
        f.write("%.9g,%.9g,%.9g,%.9g\n" % (r.uniform(-1.5, 1.5), r.uniform(-3.14, 3.14),
                                           r.uniform(-1.5, 1.5), r.uniform(-3.14, 3.14)))
PY
}
NREF=${NREF:-2000}
NFAST=${NFAST:-100000}
gen "$NREF" "$TMP/ref.csv"
gen "$NFAST" "$TMP/fast.csv"
run() { # run BACKEND FILE -> seconds
    local s e
    s=$(date +%s.%N)
    "$SL" eval scatter --backend "$1" < "$2" > "$TMP/out.csv"
    e=$(date +%s.%N)
    echo "$e - $s" | bc -l
}
# Warm the OpenCL program cache first so the build is not timed.
"$SL" eval scatter --backend opencl < "$TMP/ref.csv" > /dev/null 2>&1 || true
tref=$(run reference "$TMP/ref.csv")
rref=$(echo "$NREF / $tref" | bc -l)
printf "%-10s %8d rows %8.3f s %12.0f evals/s  x%.0f\n" reference "$NREF" "$tref" "$rref" 1
for b in c opencl; do
    if ! t=$(run "$b" "$TMP/fast.csv" 2>/dev/null); then echo "$b: not available"; continue; fi
    r=$(echo "$NFAST / $t" | bc -l)
    printf "%-10s %8d rows %8.3f s %12.0f evals/s  x%.0f\n" "$b" "$NFAST" "$t" "$r" "$(echo "$r / $rref" | bc -l)"
done
