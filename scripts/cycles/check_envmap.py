"""check_envmap.py: checks in Cycles itself that the world render_cycles.py builds is our map in
our frame (frames.py), rotation included (docs/validation.md, "Frame check").

  blender -b --factory-startup --python-exit-code 1 -P scripts/cycles/check_envmap.py -- \\
      MAP.hdr|MAP.exr [--rotation-deg R ...] [--expect-dir X,Y,Z] [--count N] [--keep DIR]

For each rotation R (default 0 and 73) and each test direction d of our world (the centre of
the map's brightest pixel, then N pseudo-random pixel centres, default 12), a pinhole camera with
a 0.002 deg field of view at 4 x 4 pixels (Blender's smallest image) looks along R_y(R) d in Blender (film not transparent,
no hair, 4 samples, Closest lookups): the background it sees must be the map's pixel at d
exactly as our loader decodes it (relative difference < 1e-5 per channel). --expect-dir is the
brightest pixel's direction printed by `strandlight info MAP` (host/io/envmap): the script's own
map_dir of that pixel must agree with it, which ties frames.py to the C code. Also prints how far
Blender's own .hdr decoding is from ours (rgbe.py). Exit 1 with one line on the first failure.
"""
import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import blender_scene as bs  # noqa: E402
import frames  # noqa: E402


def fail(msg):
    sys.stderr.write(f"check_envmap.py: {msg}\n")
    sys.exit(1)


def args():
    a = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    o = {"map": None, "rot": [], "expect": None, "count": 12, "keep": None}
    i = 0
    while i < len(a):
        if a[i] in ("--rotation-deg", "--expect-dir", "--count", "--keep") and i + 1 < len(a):
            v = a[i + 1]
            try:
                if a[i] == "--rotation-deg":
                    o["rot"].append(float(v))
                elif a[i] == "--expect-dir":
                    o["expect"] = np.array([float(t) for t in v.split(",")])
                elif a[i] == "--count":
                    o["count"] = int(v)
                else:
                    o["keep"] = v
            except ValueError:
                fail(f"{a[i]}: bad value '{v}'")
            i += 2
        elif a[i].startswith("-"):
            fail(f"unknown option or missing value '{a[i]}'")
        else:
            o["map"] = a[i]
            i += 1
    if not o["map"]:
        fail("usage: ... -P check_envmap.py -- MAP [--rotation-deg R] [--expect-dir X,Y,Z]")
    return o


def look(sc, d, tmpdir, k):
    """The background Cycles sees along our direction d (rgb)."""
    for ob in list(sc.objects):
        if ob.type == "CAMERA":
            bpy.data.objects.remove(ob)
    d = d / np.linalg.norm(d)
    helper = np.array([0.0, 1.0, 0.0]) if abs(d[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    right = np.cross(d, helper)
    right /= np.linalg.norm(right)
    up = np.cross(right, d)
    bs.camera(sc, [0, 0, 0], right, up, d, 0.002, 1e-3, 10.0)
    path = os.path.join(tmpdir, f"look{k}.exr")
    sc.render.filepath = path
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(path, check_existing=False)
    px = np.empty(4 * img.size[0] * img.size[1], np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    px = px.reshape(-1, 4)[:, :3].astype(np.float64)
    if np.ptp(px, axis=0).max() > 1e-6 * np.abs(px).max():
        fail(f"the {len(px)} pixels looking along {d} differ: {px}")
    return px[0]


def main():
    o = args()
    rots = o["rot"] or [0.0, 73.0]
    try:
        rgb = bs.env_image(o["map"])
    except (OSError, ValueError, bs.SceneError) as ex:
        fail(str(ex))
    h, w = rgb.shape[:2]
    lum = rgb @ np.array([0.2126, 0.7152, 0.0722])
    by, bx = np.unravel_index(np.argmax(lum), lum.shape)
    if o["expect"] is not None:
        got = frames.map_dir(w, h, bx, by)
        if np.max(np.abs(got - o["expect"])) > 1e-3:
            fail(f"brightest pixel ({bx}, {by}): frames.map_dir {got}, strandlight info "
                 f"{o['expect']}")
        print(f"brightest pixel ({bx}, {by}): direction {np.round(got, 4)} = strandlight info's")
    rng = np.random.default_rng(7)
    pix = [(int(bx), int(by))] + [(int(rng.integers(w)), int(rng.integers(h // 16, h - h // 16)))
                                  for _ in range(o["count"])]
    if o["map"].lower().endswith(".hdr"):  # Blender's own decoding, for the record
        img = bpy.data.images.load(o["map"], check_existing=False)
        px = np.empty(4 * w * h, np.float32)
        img.pixels.foreach_get(px)
        bl = px.reshape(h, w, 4)[::-1, :, :3]
        sa = (np.cos(np.arange(h) * math.pi / h) - np.cos(np.arange(1, h + 1) * math.pi / h))
        m_bl, m_us = (bl * sa[:, None, None]).sum((0, 1)), (rgb * sa[:, None, None]).sum((0, 1))
        print(f"Blender's own RGBE decoding / ours, solid-angle mean per channel: "
              f"{np.round(m_bl / m_us, 5)}; pixels that are 0 here and not in Blender's: "
              f"{int(np.sum((rgb == 0) & (bl > 0)))}")
        bpy.data.images.remove(img)

    tmpdir = o["keep"] or tempfile.mkdtemp(prefix="check_envmap")
    os.makedirs(tmpdir, exist_ok=True)
    worst = 0.0
    k = 0
    for r in rots:
        sc = bs.reset()
        bs.settings(sc, 4, 4, 4, 1, 1, transparent=False)  # Blender's smallest image
        bs.output_exr(sc, half=False)
        bs.world(sc, rgb, r, 1.0, "Closest")
        R = frames.rot_y(r)
        for (x, y) in pix:
            d = R @ frames.map_dir(w, h, x, y)
            got = look(sc, d, tmpdir, k)
            k += 1
            want = rgb[y, x].astype(np.float64)
            rel = np.max(np.abs(got - want) / np.maximum(np.abs(want), 1e-12))
            worst = max(worst, rel)
            print(f"rotation {r:7.2f}  pixel ({x:4d}, {y:3d})  look {np.round(d, 4)}  "
                  f"Cycles {np.round(got, 5)}  map {np.round(want, 5)}  rel {rel:.2e}")
            if rel > 1e-5:
                fail(f"rotation {r}: pixel ({x}, {y}): Cycles sees {got}, the map has {want}")
    print(f"check_envmap.py: {len(pix) * len(rots)} directions, worst relative difference "
          f"{worst:.2e}: the world is our map in our frame")


main()
