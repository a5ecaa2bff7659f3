# slab_hair.py OUT.hair NFIBERS RADIUS: the random slab of the transmittance tests
# (test_transmittance.sh, test_forward_transmittance.sh): NFIBERS straight fibers of RADIUS along
# x from -2 to 2 at uniform random (y, z) in [-2, 2] x [-1, 0] (seed 5), as a cyHair file
# (2 points per strand, thickness = 2 RADIUS, transparency 0, colour 0.5).
import random, struct, sys

out, nf, r = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
random.seed(5)
with open(out, "wb") as f:
    hdr = b"HAIR" + struct.pack("<IIII", nf, 2 * nf, 2, 1) + struct.pack("<ff", 2 * r, 0.0)
    hdr += struct.pack("<fff", 0.5, 0.5, 0.5)
    f.write(hdr + b"\0" * (128 - len(hdr)))
    for i in range(nf):
        y, z = random.uniform(-2, 2), random.uniform(-1, 0)
        f.write(struct.pack("<6f", -2, y, z, 2, y, z))
