#!/usr/bin/env python3
"""sun_map.py OUT.hdr ELEVATION_DEG [POWER] [RADIUS_DEG]: a lat-long map (512 x 256, flat RGBE)
that is black but for one sun: a disc of RADIUS_DEG (default 1.5) whose pixels sum to POWER
(default 4.5, radiance x solid angle), at ELEVATION_DEG above the horizon toward azimuth
(0.5630, -0.8265) in x, z (behind the default camera's hair). The project's lat-long convention
(docs/formats.md): pixel centre (theta from +y, phi) looks along (-sin th sin ph, cos th,
sin th cos ph). Used by scripts/ms_vs_light_angle.sh and test/cli/test_ms_direction.sh."""
import math
import sys

W, H = 512, 256
out, el = sys.argv[1], math.radians(float(sys.argv[2]))
power = float(sys.argv[3]) if len(sys.argv) > 3 else 4.5
radius = float(sys.argv[4]) if len(sys.argv) > 4 else 1.5
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
