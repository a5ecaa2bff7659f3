"""rgbe.py: Radiance RGBE (.hdr) decoded exactly as Strandlight's loader decodes it.

Strandlight reads .hdr through stb_image: value = mantissa * 2^(E - 136), E = 0 -> black
(../shared/data/README.md). Blender's own reader (imbuf/radiance_hdr.cc, RGBE2FLOAT) uses
(mantissa + 0.5) * 2^(E - 136), which is 0.3 % brighter on average and much more in dim
channels (a mantissa of 4 gains 12 %) and turns RGBE's zeroed channels into small positive
values; so the map is decoded here and handed to Blender as float pixels.
Returns a float32 array (H, W, 3), row 0 at the top. Errors: ValueError naming the file.
"""
import numpy as np


def read(path):
    data = open(path, "rb").read()
    if not (data.startswith(b"#?RADIANCE") or data.startswith(b"#?RGBE")):
        raise ValueError(f"{path}: not a Radiance .hdr file")
    pos = 0
    fmt_ok = False
    while True:  # header lines up to the empty line
        end = data.find(b"\n", pos)
        if end < 0:
            raise ValueError(f"{path}: truncated header")
        line = data[pos:end]
        pos = end + 1
        if line.startswith(b"FORMAT=32-bit_rle_rgbe"):
            fmt_ok = True
        if line == b"":
            break
    if not fmt_ok:
        raise ValueError(f"{path}: not FORMAT=32-bit_rle_rgbe")
    end = data.find(b"\n", pos)
    res = data[pos:end].split()
    pos = end + 1
    if len(res) != 4 or res[0] != b"-Y" or res[2] != b"+X":
        raise ValueError(f"{path}: unsupported resolution line {data[pos:end]!r}")
    h, w = int(res[1]), int(res[3])
    rgbe = np.zeros((h, w, 4), np.uint8)
    for y in range(h):
        if data[pos:pos + 2] == b"\x02\x02" and (data[pos + 2] << 8 | data[pos + 3]) == w:
            pos += 4
            for c in range(4):  # four run-length coded component streams
                x = 0
                row = bytearray(w)
                while x < w:
                    n = data[pos]
                    if n > 128:
                        n -= 128
                        row[x:x + n] = bytes([data[pos + 1]]) * n
                        pos += 2
                    else:
                        row[x:x + n] = data[pos + 1:pos + 1 + n]
                        pos += 1 + n
                    x += n
                    if x > w:
                        raise ValueError(f"{path}: scanline {y} overruns its width")
                rgbe[y, :, c] = np.frombuffer(bytes(row), np.uint8)
        else:  # flat scanline
            rgbe[y] = np.frombuffer(data, np.uint8, 4 * w, pos).reshape(w, 4)
            pos += 4 * w
    e = rgbe[:, :, 3].astype(np.int32)
    scale = np.where(e > 0, np.ldexp(1.0, e - 136), 0.0).astype(np.float64)
    return (rgbe[:, :, :3].astype(np.float64) * scale[:, :, None]).astype(np.float32)
