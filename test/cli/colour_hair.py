# colour_hair.py OUT.hair NFIBERS RADIUS R G B: a slab of NFIBERS straight fibers of RADIUS
# along x from -2 to 2 at uniform random (y, z) in [-2, 2] x [-0.5, 0.5] (seed 7), 4 points
# each, as a cyHair file with a per-point colour array (bit 4) of the one colour (R, G, B): a
# hair that carries its colours, for material.strand_sigma_a "colors" (test_strand_ms.sh).
import random, struct, sys

out, nf, r = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
col = [float(v) for v in sys.argv[4:7]]
npt = 4
random.seed(7)
with open(out, "wb") as f:
    # flags: bit 1 points, bit 4 colours; default segments npt - 1, thickness 2 r
    hdr = b"HAIR" + struct.pack("<IIII", nf, npt * nf, 2 | 16, npt - 1)
    hdr += struct.pack("<ff", 2 * r, 0.0) + struct.pack("<fff", 0.5, 0.5, 0.5)
    f.write(hdr + b"\0" * (128 - len(hdr)))
    for i in range(nf):
        y, z = random.uniform(-2, 2), random.uniform(-0.5, 0.5)
        for k in range(npt):
            f.write(struct.pack("<3f", -2 + 4 * k / (npt - 1), y, z))
    for i in range(nf * npt):
        f.write(struct.pack("<3f", *col))
