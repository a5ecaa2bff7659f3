"""hairfile.py: Cem Yuksel's cyHair .hair format, read with numpy (no Blender needed).

The layout is ../shared/data/README.md's: a 128-byte header ("HAIR", strands S, points P, flags,
default segments, thickness, transparency, colour, 88 bytes of text), then the arrays whose flag
bit is set, in this order: u16 segments[S], f32 points[P][3], thickness[P], transparency[P],
colour[P][3]. `strandlight export` writes segments, points and thickness (= 2 x radius) always.
Errors are ValueError with a one-line message naming the file.
"""
import struct

import numpy as np

HEADER = 128


class Hair:
    """strand_first: S + 1 offsets into points; points: (P, 3) float32; radius: (P,) float32."""

    def __init__(self, strand_first, points, radius, info):
        self.strand_first, self.points, self.radius, self.info = strand_first, points, radius, info

    @property
    def num_strands(self):
        return len(self.strand_first) - 1


def read(path):
    data = open(path, "rb").read()
    if len(data) < HEADER or data[:4] != b"HAIR":
        raise ValueError(f"{path}: not a cyHair .hair file (no 128-byte \"HAIR\" header)")
    S, P, flags, def_seg = struct.unpack_from("<4I", data, 4)
    def_thick, = struct.unpack_from("<f", data, 20)
    info = data[40:128].split(b"\0", 1)[0].decode("ascii", "replace")
    if flags & ~0x1F or not flags & 2 or S == 0:
        raise ValueError(f"{path}: bad header (flags 0x{flags:x}, {S} strands)")
    sizes = [(1, 2 * S), (2, 12 * P), (4, 4 * P), (8, 4 * P), (16, 12 * P)]
    want = HEADER + sum(n for bit, n in sizes if flags & bit)
    if want != len(data):
        raise ValueError(f"{path}: {len(data)} bytes, the header declares {want}")
    off = HEADER
    if flags & 1:
        seg = np.frombuffer(data, "<u2", S, off).astype(np.int64)
        off += 2 * S
    else:
        seg = np.full(S, def_seg, np.int64)
    if np.any(seg < 1) or int(np.sum(seg + 1)) != P:
        raise ValueError(f"{path}: segment counts do not add up to the {P} points")
    first = np.zeros(S + 1, np.int64)
    first[1:] = np.cumsum(seg + 1)
    points = np.frombuffer(data, "<f4", 3 * P, off).reshape(P, 3).astype(np.float32)
    off += 12 * P
    if flags & 4:
        radius = 0.5 * np.frombuffer(data, "<f4", P, off).astype(np.float32)
    else:
        radius = np.full(P, 0.5 * def_thick, np.float32)
    if not (np.all(np.isfinite(points)) and np.all(np.isfinite(radius)) and np.all(radius >= 0)):
        raise ValueError(f"{path}: non-finite point or negative thickness")
    return Hair(first, points, radius, info)
