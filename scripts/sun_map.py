#!/usr/bin/env python3
"""sun_map.py OUT.hdr ELEVATION_DEG [--scene SCENE.json --size WxH] [--power P] [--radius DEG]:
a lat-long map (512 x 256, flat RGBE) that is black but for one sun: a disc of DEG (default 1.5)
whose pixels sum to P (default 4.5, radiance x solid angle), at ELEVATION_DEG above the horizon
toward azimuth (0.5630, -0.8265) in x, z (behind the default camera's hair). The project's
lat-long convention (docs/formats.md): pixel centre (theta from +y, phi) looks along
(-sin th sin ph, cos th, sin th cos ph). With --scene, also the scene of the MS-direction checks
beside it: the default scene's hair (procedural wavy, 4000 strands, radius 0.04), white chiang
(sigma_a 0), this map, 4 lobes, multiple scattering on. Used by scripts/ms_vs_light_angle.sh and
test/cli/test_ms_direction.sh."""
import argparse
import json
import math
import os

ap = argparse.ArgumentParser()
ap.add_argument("out")
ap.add_argument("elevation", type=float)
ap.add_argument("--scene")
ap.add_argument("--size", default="160x120")
ap.add_argument("--power", type=float, default=4.5)
ap.add_argument("--radius", type=float, default=1.5)
a = ap.parse_args()
W, H = 512, 256
out, el, power, radius = a.out, math.radians(a.elevation), a.power, a.radius
ax, az = 0.5630, -0.8265
d = (math.cos(el) * ax, math.sin(el), math.cos(el) * az)
c0 = math.cos(math.radians(radius))
pix = []
for y in range(H):
    th = (y + 0.5) / H * math.pi
    for x in range(W):
        ph = (x + 0.5) / W * 2 * math.pi
        v = (-math.sin(th) * math.sin(ph), math.cos(th), math.sin(th) * math.cos(ph))
        if v[0] * d[0] + v[1] * d[1] + v[2] * d[2] > c0:
            pix.append((x, y, math.sin(th) * (math.pi / H) * (2 * math.pi / W)))
L = power / sum(p[2] for p in pix)
m, e = math.frexp(L)
texel = bytes([int(m * 256)] * 3 + [e + 128])
img = bytearray(4 * W * H)
for x, y, _ in pix:
    img[4 * (y * W + x):4 * (y * W + x) + 4] = texel
with open(out, 'wb') as f:
    f.write(b'#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n' % (H, W) + bytes(img))
if a.scene:
    w, h = (int(x) for x in a.size.split("x"))
    scene = {"hair": {"procedural": {"style": "wavy", "strands": 4000, "points": 16, "seed": 1},
                      "radius": 0.04},
             "material": {"model": "chiang", "sigma_a": [0, 0, 0], "roughness": 0.3,
                          "radial_roughness": 0.3},
             "environment": {"file": os.path.relpath(out, os.path.dirname(os.path.abspath(a.scene)))},
             "camera": {"fov_deg": 30}, "image": {"width": w, "height": h},
             "quality": {"lobes": 4, "multiple_scattering": "on"}}
    with open(a.scene, "w") as f:
        json.dump(scene, f)
