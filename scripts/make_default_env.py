#!/usr/bin/env python3
"""make_default_env.py: makes the shipped default environment map data/env/<name>_256.hdr.

Usage: python3 scripts/make_default_env.py [SRC.hdr] [OUT.hdr]
Defaults: SRC = ../shared/data/envmaps/blender_rgbe/city.hdr, OUT = data/env/city_256.hdr.
Pure Python 3 (no numpy); takes a few seconds.

1. Decode the 1024x512 Radiance RGBE source (new-style RLE, layout in ../shared/data/README.md).
   The blender_rgbe copies were encoded by truncating the mantissa, so they decode here the
   Radiance way, (m + 0.5) * 2^(E-136), which removes that 0.3 % low bias.
2. Downsample by 4 in each direction (256x128) with an energy-preserving box filter in linear
   float: each output pixel is the solid-angle-weighted mean of its 4x4 source block, with row
   weights cos(th_top) - cos(th_bottom) of the source rows. The output rows are exactly the unions
   of the source rows, so the integral of radiance over every output pixel (and over the sphere)
   is kept.
3. Encode RGBE with the mantissa ROUNDED to nearest for the decoder convention m * 2^(E-136) used
   by stb_image (the product's loader), so decoding is unbiased; write new-style RLE scanlines.
"""
import math
import os
import sys

FACTOR = 4


def read_rgbe(path):
    data = open(path, "rb").read()
    pos = 0

    def line():
        nonlocal pos
        end = data.index(b"\n", pos)
        text = data[pos:end].decode("latin-1")
        pos = end + 1
        return text

    if line() not in ("#?RADIANCE", "#?RGBE"):
        raise SystemExit(f"{path}: not a Radiance file")
    while line() != "":
        pass
    parts = line().split()
    if parts[0] != "-Y" or parts[2] != "+X":
        raise SystemExit(f"{path}: unsupported orientation {parts}")
    h, w = int(parts[1]), int(parts[3])
    img = []  # rows of [r, g, b] floats
    for _ in range(h):
        if data[pos] != 2 or data[pos + 1] != 2 or (data[pos + 2] << 8 | data[pos + 3]) != w:
            raise SystemExit(f"{path}: only new-style RLE scanlines are handled here")
        pos += 4
        comps = []
        for _k in range(4):
            out = bytearray()
            while len(out) < w:
                c = data[pos]
                pos += 1
                if c > 128:
                    out += bytes([data[pos]]) * (c - 128)
                    pos += 1
                else:
                    out += data[pos:pos + c]
                    pos += c
            comps.append(out)
        row = []
        for x in range(w):
            e = comps[3][x]
            s = math.ldexp(1.0, e - 136) if e else 0.0
            row.append([(comps[c][x] + 0.5) * s if e else 0.0 for c in range(3)])
        img.append(row)
    return w, h, img


def downsample(w, h, img):
    ow, oh = w // FACTOR, h // FACTOR
    wt = [math.cos(math.pi * y / h) - math.cos(math.pi * (y + 1) / h) for y in range(h)]
    out = []
    for oy in range(oh):
        rows = range(oy * FACTOR, (oy + 1) * FACTOR)
        wsum = sum(wt[y] for y in rows) * FACTOR
        orow = []
        for ox in range(ow):
            acc = [0.0, 0.0, 0.0]
            for y in rows:
                for x in range(ox * FACTOR, (ox + 1) * FACTOR):
                    p = img[y][x]
                    for c in range(3):
                        acc[c] += wt[y] * p[c]
            orow.append([a / wsum for a in acc])
        out.append(orow)
    return ow, oh, out


def rgbe(p):
    v = max(p)
    if v < 1e-32:
        return bytes(4)
    e = math.frexp(v)[1]  # v < 2^e
    q = [int(math.floor(c * math.ldexp(1.0, 8 - e) + 0.5)) for c in p]
    if max(q) > 255:  # rounding reached 256: one exponent up
        e += 1
        q = [int(math.floor(c * math.ldexp(1.0, 8 - e) + 0.5)) for c in p]
    return bytes(q + [e + 128])


def rle(comp):
    """New-style RLE of one component: runs of >= 3 equal bytes, literal dumps otherwise."""
    out = bytearray()
    i, n = 0, len(comp)
    while i < n:
        j = i
        while j < n and j - i < 127 and comp[j] == comp[i]:
            j += 1
        if j - i >= 3:
            out += bytes([128 + j - i, comp[i]])
            i = j
            continue
        k = i  # literal run until the next run of >= 3 or 128 bytes
        while k < n and k - i < 128:
            if k + 2 < n and comp[k] == comp[k + 1] == comp[k + 2]:
                break
            k += 1
        out += bytes([k - i]) + comp[i:k]
        i = k
    return out


def write_rgbe(path, w, h, img):
    body = bytearray(b"#?RADIANCE\n# strandlight default map, see data/README.md\n"
                     b"FORMAT=32-bit_rle_rgbe\n\n")
    body += f"-Y {h} +X {w}\n".encode()
    for row in img:
        px = [rgbe(p) for p in row]
        body += bytes([2, 2, w >> 8, w & 255])
        for k in range(4):
            body += rle(bytes(p[k] for p in px))
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(body)
    os.replace(tmp, path)


def mean_lum(w, h, img):
    """Solid-angle-weighted mean Rec.709 luminance."""
    tot = 0.0
    for y in range(h):
        om = math.cos(math.pi * y / h) - math.cos(math.pi * (y + 1) / h)
        tot += om * sum(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2] for p in img[y])
    return tot * (2 * math.pi / w) / (4 * math.pi)


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else "../shared/data/envmaps/blender_rgbe/city.hdr"
    name = os.path.splitext(os.path.basename(src))[0]
    dst = sys.argv[2] if len(sys.argv) > 2 else f"data/env/{name}_256.hdr"
    w, h, img = read_rgbe(src)
    ow, oh, small = downsample(w, h, img)
    os.makedirs(os.path.dirname(dst) or ".", exist_ok=True)
    write_rgbe(dst, ow, oh, small)
    print(f"{src}: {w}x{h}, Y mean (solid angle) {mean_lum(w, h, img):.5f}")
    print(f"{dst}: {ow}x{oh}, Y mean (solid angle) {mean_lum(ow, oh, small):.5f}, "
          f"{os.path.getsize(dst)} bytes")


if __name__ == "__main__":
    main()
