#!/usr/bin/env bash
# bench_scaling.sh [BUILD_DIR]: the frame's cost model (issue 20). Renders a procedural wavy
# hair (the default scene's) on the C path at 4 sizes of each of segments (strands x 15
# segments), lobes and pixels, one variable at a time around a base (1000 strands, 20 lobes,
# 320x240), parses the per-pass seconds `render --explain` prints, and prints a table per
# variable (wall and CPU seconds of the whole process beside the passes) and the log-log
# least-squares slope of every pass against every variable. A slope above 1.15 is flagged
# SUPERLINEAR; passes whose largest time is under MIN_S (default 0.05 s) get no slope (timer
# noise dominates them). Benchmarks are never part of `make test`; nothing here asserts a time.
#
# Fixed so that only the variable moves: --method fast, --shading-rate vertex (auto would switch
# to fragment shading at the largest resolution), multiple scattering on, quality.broad_lobes
# split (subdivide would turn 80 lobes into ~156, so the lobe axis would not be the one asked
# for; the x of the lobe rows is the count the light pass reports). Lobe sets are fitted once and
# then come from the disk cache (the first run pays ~15 s of fitting).
# Environment: STRANDS, LOBES, SIZES (WxH) override the lists; THREADS (C threads, default every
# CPU); REPS (default 3: best of REPS per pass and for wall and CPU; the machine is shared); MIN_S.
set -eu
BUILD=${1:-build}
SL="$BUILD/strandlight"
TMP="$BUILD/bench-scaling"
mkdir -p "$TMP"
if [ -x /usr/bin/python3 ]; then PY=/usr/bin/python3; else PY=python3; fi
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) CPUs"
exec "$PY" - "$SL" "$TMP" <<'PY'
import json, math, os, re, resource, subprocess, sys, time

sl, tmp = sys.argv[1], sys.argv[2]
env = os.environ
strands_list = [int(v) for v in env.get("STRANDS", "500 1000 2000 4000").split()]
lobes_list = [int(v) for v in env.get("LOBES", "10 20 40 80").split()]
sizes_list = [tuple(int(x) for x in v.split("x")) for v in
              env.get("SIZES", "160x120 320x240 640x480 1280x960").split()]
threads = env.get("THREADS", "")
reps = int(env.get("REPS", "3"))
min_s = float(env.get("MIN_S", "0.05"))
BASE = dict(strands=1000, lobes=20, size=(320, 240))
POINTS = 16
ROW = re.compile(r"^(\S+(?: table)?)\s+(run|cached|skipped)\s+([0-9.]+)s")
LIGHT_LOBES = re.compile(r"deep opacity maps \S+ for (\d+) lobes")


def scene(strands, lobes, size):
    return {"hair": {"procedural": {"style": "wavy", "strands": strands, "points": POINTS,
                                    "seed": 1}, "radius": 0.04},
            "material": {"model": "chiang", "melanin": 0.3, "roughness": 0.3,
                         "radial_roughness": 0.3},
            "environment": {"file": "data/env/city_256.hdr"},
            "camera": {"fov_deg": 30},
            "image": {"width": size[0], "height": size[1]},
            "quality": {"lobes": lobes, "multiple_scattering": "on", "broad_lobes": "split"}}


def render_once(sc):
    cmd = [sl, "render", "-", "-o", os.path.join(tmp, "frame.exr"), "--device", "c",
           "--method", "fast", "--shading-rate", "vertex", "--explain", "--quiet"]
    if threads:
        cmd += ["--threads", threads]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    p = subprocess.run(cmd, input=json.dumps(sc), capture_output=True, text=True)
    wall = time.monotonic() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit("bench_scaling: render failed (exit %d): %s" % (p.returncode, p.stderr.strip()))
    passes, lobes_used = {}, None
    for line in p.stdout.splitlines():
        m = ROW.match(line)
        if m:
            passes[m.group(1)] = float(m.group(3))
            if m.group(1) == "light":
                lm = LIGHT_LOBES.search(line)
                if lm:
                    lobes_used = int(lm.group(1))
        elif line.startswith("total"):
            passes["total"] = float(line.split()[1].rstrip("s"))
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return passes, wall, cpu, lobes_used


cache = {}


def render(strands, lobes, size):
    key = (strands, lobes, size)
    if key not in cache:
        best = None
        for _ in range(reps):
            passes, wall, cpu, lu = render_once(scene(strands, lobes, size))
            if best is None:
                best = [passes, wall, cpu, lu]
            else:
                for k, v in passes.items():
                    best[0][k] = min(best[0].get(k, v), v)
                best[1], best[2] = min(best[1], wall), min(best[2], cpu)
        cache[key] = best
    return cache[key]


axes = [
    ("segments", [(s, BASE["lobes"], BASE["size"]) for s in strands_list],
     lambda k, r: k[0] * (POINTS - 1)),
    ("lobes", [(BASE["strands"], l, BASE["size"]) for l in lobes_list],
     lambda k, r: r[3] if r[3] else k[1]),
    ("pixels", [(BASE["strands"], BASE["lobes"], s) for s in sizes_list],
     lambda k, r: k[2][0] * k[2][1]),
]

t_all = time.monotonic()
# Warm-up: one tiny render per lobe count fits (or loads) its lobes and fills the disk caches,
# so that no timed row pays a fit or a first-use table build in its wall and CPU seconds.
for l in sorted(set(lobes_list + [BASE["lobes"]])):
    render_once(scene(20, l, (32, 24)))
results = {}
order = []
for name, keys, xof in axes:
    rows = []
    for k in keys:
        r = render(*k)
        rows.append((xof(k, r), k, r))
        for p in r[0]:
            if p not in order and p != "total":
                order.append(p)
    results[name] = rows

cols = order + ["total"]


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(max(y, 1e-4)) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


flags = []
slopes = {}
for name, rows in results.items():
    print("\n%s (others at base: %d strands, %d lobes asked, %dx%d; C path, %s threads)" %
          (name, BASE["strands"], BASE["lobes"], BASE["size"][0], BASE["size"][1],
           threads or "all"))
    print("| %s | scene | %s | wall s | CPU s |" % (name, " | ".join(cols)))
    print("|---|---|%s---|---|" % ("---|" * len(cols)))
    for x, k, r in rows:
        print("| %d | %d str, %d lobes, %dx%d | %s | %.2f | %.2f |" %
              (x, k[0], k[1], k[2][0], k[2][1],
               " | ".join("%.3f" % r[0].get(c, 0.0) for c in cols), r[1], r[2]))
    xs = [x for x, _, _ in rows]
    for c in cols + ["wall", "cpu"]:
        if c == "wall":
            ys = [r[1] for _, _, r in rows]
        elif c == "cpu":
            ys = [r[2] for _, _, r in rows]
        else:
            ys = [r[0].get(c, 0.0) for _, _, r in rows]
        if len(set(xs)) < 2 or max(ys) < min_s:
            slopes[(c, name)] = None
            continue
        s = slope(xs, ys)
        slopes[(c, name)] = s
        if s > 1.15:
            flags.append("%s vs %s: slope %.2f" % (c, name, s))

print("\nlog-log least-squares slope of seconds against each variable (%d sizes each; '-': "
      "the pass stays under %.2f s, too small to fit; > 1.15 flagged *)" %
      (len(strands_list), min_s))
print("| pass | %s |" % " | ".join(n for n, _, _ in axes))
print("|---|%s" % ("---|" * len(axes)))
for c in cols + ["wall", "cpu"]:
    cells = []
    for n, _, _ in axes:
        s = slopes.get((c, n))
        cells.append("-" if s is None else "%.2f%s" % (s, " *" if s > 1.15 else ""))
    print("| %s | %s |" % ("CPU s" if c == "cpu" else "wall s" if c == "wall" else c,
                           " | ".join(cells)))
print()
if flags:
    print("SUPERLINEAR: " + "; ".join(flags))
else:
    print("no pass superlinear (every slope <= 1.15)")
print("bench_scaling: %d renders in %.0f s" % (len(cache) * reps, time.monotonic() - t_all))
PY
