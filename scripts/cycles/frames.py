"""frames.py: Strandlight's world and map conventions expressed in Blender's.

Ours (numerics.md sec. 4): right-handed, +Y up; lat-long pixel (x, y) of a W x H map has polar
angle th = pi (y + 0.5) / H from +Y and azimuth ph = 2 pi (x + 0.5) / W - pi, direction
(sin th sin ph, cos th, -sin th cos ph): the image centre looks down -Z.
Blender: right-handed, +Z up; its equirectangular lookup puts u = 0.5 (the image centre) at +X,
u = -atan2(Y, X) / (2 pi) + 0.5, v = atan2(Z, hypot(X, Y)) / pi + 0.5 (v = 0 at the bottom row).
So ours (x, y, z) is Blender (X, Y, Z) = (-z, -x, y), a proper rotation (det +1): the image
centre -Z goes to +X, +Y up to +Z, and u agrees: -atan2(-x, -z) = atan2(x, -z) = ph.
environment.rotation_deg (host/scene/env_lighting.c, sl_lobes_transform) turns the lit
environment by +rotation about +Y: light that came from d now comes from R_y(r) d, so the map is
looked up at R_y(-r) d; R_y maps to R_Z under the frame change, so Blender looks up R_Z(-r) d.
docs/validation.md records the renders that checked all this.
"""
import math

import numpy as np

# rows: Blender axes in our coordinates
OURS_TO_BLENDER = np.array([[0, 0, -1], [-1, 0, 0], [0, 1, 0]], dtype=np.float64)


def to_blender(v):
    """Points or directions (..., 3) from our world to Blender's."""
    return np.asarray(v, np.float64) @ OURS_TO_BLENDER.T


def map_dir(w, h, x, y):
    """Our world direction of the centre of map pixel (x, y) (numerics.md sec. 4)."""
    th = math.pi * (y + 0.5) / h
    ph = 2 * math.pi * (x + 0.5) / w - math.pi
    return np.array([math.sin(th) * math.sin(ph), math.cos(th), -math.sin(th) * math.cos(ph)])


def dir_to_pixel(w, h, d):
    """Our direction -> the map pixel (x, y) it falls in (nearest-pixel lookup)."""
    d = np.asarray(d, np.float64) / np.linalg.norm(d)
    th = math.acos(max(-1.0, min(1.0, d[1])))
    ph = math.atan2(d[0], -d[2])
    x = int(math.floor((ph + math.pi) / (2 * math.pi) * w)) % w
    y = min(h - 1, int(math.floor(th / math.pi * h)))
    return x, y


def rot_y(deg):
    """R_y(deg) in our frame, as sl_lobes_transform applies it (x' = c x + s z, z' = -s x + c z)."""
    r = math.radians(deg)
    c, s = math.cos(r), math.sin(r)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
