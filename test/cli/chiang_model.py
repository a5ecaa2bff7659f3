#!/usr/bin/env python3
"""chiang_model.py: model chiang written again from its sources, for test/cli/test_eval_chiang.sh.

pbrt-v4's HairBxDF::f (Mp, Ap, Np, the scale tilt by sin/cos of 2^k alpha, pbrt's own
phi = phi_i - phi_o) times |cos theta_i| (numerics.md's measure), averaged over h in [-1, 1] by a
plain composite Gauss-Legendre rule, with Blender/Cycles' parameter mappings (numerics.md sec. 3).
Nothing here is shared with the C code, so agreement checks conventions as well as numbers.

  chiang_model.py check MATERIAL.json OUT.csv TOL   compares eval scatter --backend reference rows
"""
import csv
import json
import math
import sys

GL5 = [(-0.9061798459386640, 0.2369268850561891), (-0.5384693101056831, 0.4786286704993665),
       (0.0, 0.5688888888888889), (0.5384693101056831, 0.4786286704993665),
       (0.9061798459386640, 0.2369268850561891)]


def material(d):
    """Cycles' mappings: variances v[0..3], logistic scale s, sigma_a (rgb), eta, alpha."""
    def var(b):
        return (0.726 * b + 0.812 * b ** 2 + 3.7 * b ** 20) ** 2
    bl = d.get("roughness", 0.3)
    b = d.get("radial_roughness", 0.3)
    coat = d.get("coat", 0.0)
    v0 = var(bl)
    v = [var(bl * (1 - coat)), v0 / 4, 4 * v0, 4 * v0]
    s = math.sqrt(math.pi / 8) * (0.265 * b + 1.194 * b ** 2 + 5.372 * b ** 22)
    if "sigma_a" in d:
        sa = d["sigma_a"]
        sa = sa if isinstance(sa, list) else [sa] * 3
    else:
        mel, red = d.get("melanin", 0.8), d.get("melanin_redness", 1.0)
        tint = d.get("tint", [1.0, 1.0, 1.0])
        q = -math.log(max(1 - mel, 1e-4))
        eu, ph = q * (1 - red), q * red
        den = 5.969 - 0.215 * b + 2.532 * b ** 2 - 10.73 * b ** 3 + 5.574 * b ** 4 + 0.245 * b ** 5
        sa = [eu * e + ph * p + (math.log(t) / den) ** 2
              for e, p, t in zip((0.506, 0.841, 1.653), (0.343, 0.733, 1.924), tint)]
    return dict(v=v, s=s, sigma_a=sa, eta=d.get("eta", 1.55),
                alpha=math.radians(d.get("offset_deg", 2.0)))


def log_i0(x):
    """log I0: the power series below 50, else Hankel's series (A&S 9.7.1) to its least term."""
    if x < 50:
        t, term, tot = 0.25 * x * x, 1.0, 1.0
        for k in range(1, 400):
            term *= t / (k * k)
            tot += term
            if term < 1e-17 * tot:
                break
        return math.log(tot)
    term, tot = 1.0, 1.0
    for k in range(1, 100):
        nxt = term * (2 * k - 1) ** 2 / (8 * k * x)
        if nxt >= term:
            break
        term = nxt
        tot += term
    return x - 0.5 * math.log(2 * math.pi * x) + math.log(tot)


def mp(cti, cto, sti, sto, v):
    """d'Eon Eq. 7 as pbrt writes it, in logs: csch(1/v)/(2v) exp(-b) I0(a)."""
    a, b = cti * abs(cto) / v, sti * sto / v
    log_csch = math.log(2) - 1 / v - math.log1p(-math.exp(-2 / v))
    return math.exp(log_csch - math.log(2 * v) - b + log_i0(a))


def fresnel(cos_i, eta):
    cos_i = min(abs(cos_i), 1.0)
    sin_t = math.sqrt(max(0.0, 1 - cos_i * cos_i)) / eta
    cos_t = math.sqrt(1 - sin_t * sin_t)
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return 0.5 * (rs * rs + rp * rp)


def trimmed_logistic(x, s):
    x = abs(x)
    e = math.exp(-x / s)
    return e / (s * (1 + e) ** 2) / (1 / (1 + math.exp(-math.pi / s)) - 1 / (1 + math.exp(math.pi / s)))


def f_width_average(m, ch, ti, phi_i, to, phi_o, panels=2000):
    """[f_0, f_1, f_2, f_rest, f]: 1/2 integral over h of pbrt's f |cos theta_i|."""
    eta, s, sig = m["eta"], m["s"], m["sigma_a"][ch]
    sto, cto, sti, cti = math.sin(to), math.cos(to), math.sin(ti), math.cos(ti)
    sin2k = [math.sin(m["alpha"] * 2 ** k) for k in range(3)]
    cos2k = [math.cos(m["alpha"] * 2 ** k) for k in range(3)]
    tilt = [(sto * cos2k[1] - cto * sin2k[1], cto * cos2k[1] + sto * sin2k[1]),
            (sto * cos2k[0] + cto * sin2k[0], cto * cos2k[0] - sto * sin2k[0]),
            (sto * cos2k[2] + cto * sin2k[2], cto * cos2k[2] - sto * sin2k[2]),
            (sto, cto)]
    M = [mp(cti, tilt[p][1], sti, tilt[p][0], m["v"][p]) for p in range(4)]
    phi = phi_i - phi_o  # pbrt's azimuth
    sin_tt = sto / eta
    cos_tt = math.sqrt(1 - sin_tt ** 2)
    etap = math.sqrt(eta * eta - sto * sto) / cto
    out = [0.0] * 4
    H = math.pi / panels
    for k in range(panels):
        for x, w in GL5:
            g = -math.pi / 2 + (k + 0.5) * H + 0.5 * H * x  # h = sin(gamma_o), dh = cos g dg
            h = math.sin(g)
            wt = 0.5 * 0.5 * H * w * math.cos(g)
            sgt = h / etap
            cgt = math.sqrt(1 - sgt * sgt)
            gt = math.asin(sgt)
            T = math.exp(-sig * (2 * cgt / cos_tt))
            f = fresnel(cto * math.cos(g), eta)
            ap = [f, (1 - f) ** 2 * T]
            ap.append(ap[1] * T * f)
            ap.append(ap[2] * f * T / (1 - T * f) if 1 - T * f > 0 else 0.0)
            for p in range(3):
                dphi = phi - (2 * p * gt - 2 * g + p * math.pi)
                dphi = math.remainder(dphi, 2 * math.pi)
                out[p] += wt * M[p] * ap[p] * trimmed_logistic(dphi, s)
            out[3] += wt * M[3] * ap[3] / (2 * math.pi)
    return out + [sum(out)]


def check(mat_path, out_path, tol):
    m = material(json.load(open(mat_path)))
    rows = list(csv.DictReader(open(out_path)))
    assert rows, "no rows"
    worst = 0.0
    for r in rows:
        a = [float(r[k]) for k in ("theta_i", "phi_i", "theta_o", "phi_o")]
        for ch, c in enumerate("rgb"):
            want = f_width_average(m, ch, *a)
            for k, name in enumerate(("f_0", "f_1", "f_2", "f_rest", "f")):
                got = float(r["%s_%s" % (name, c)])
                err = abs(got - want[k]) / max(want[k], 1e-9 * want[4], 1e-300)
                worst = max(worst, err)
                assert err <= tol, (name, c, a, got, want[k], err)
    print("worst relative error %.2e" % worst)


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "check":
        check(sys.argv[2], sys.argv[3], float(sys.argv[4]))
    else:
        sys.exit(__doc__)
