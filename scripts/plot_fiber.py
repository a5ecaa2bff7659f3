#!/usr/bin/python3
"""plot_fiber.py: SVG plot of the Marschner scattering function per mode (f_R, f_TT, f_TRT, f)
for a material (default: numerics.md sec. 2 defaults), vs phi at fixed inclinations and vs
theta_o at fixed theta_i and phi, from `strandlight eval scatter` CSV output.

    python3 scripts/plot_fiber.py [--sl build/strandlight] [--backend reference]
                                  [--material m.json] [--out docs/fiber_plot.svg]
"""
import argparse
import csv
import io
import math
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MODES = ["f_R", "f_TT", "f_TRT", "f"]


def evaluate(sl, backend, material, rows):
    text = "theta_i,phi_i,theta_o,phi_o\n" + "".join("%.9g,%.9g,%.9g,%.9g\n" % r for r in rows)
    cmd = [sl, "eval", "scatter", "--backend", backend]
    if material:
        cmd += ["--material", material]
    res = subprocess.run(cmd, input=text, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit("plot_fiber.py: %s failed: %s" % (" ".join(cmd), res.stderr.strip()))
    return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(io.StringIO(res.stdout))]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sl", default="build/strandlight")
    ap.add_argument("--backend", default="reference")
    ap.add_argument("--material", default=None)
    ap.add_argument("--out", default="docs/fiber_plot.svg")
    a = ap.parse_args()

    n = 721
    theta_i = math.radians(20.0)
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    # vs phi: theta_o = -theta_i (specular cone), phi_i = 0
    phis = [-math.pi + 2 * math.pi * (k + 0.5) / n for k in range(n)]
    rows = evaluate(a.sl, a.backend, a.material, [(theta_i, 0.0, -theta_i + math.radians(-15.0), p) for p in phis])
    for m in MODES:
        ax[0].plot([math.degrees(p) for p in phis], [r[m] for r in rows], label=m,
                   lw=2.0 if m == "f" else 1.2)
    ax[0].set_yscale("log")
    ax[0].set_ylim(1e-4, None)
    ax[0].set_xlabel("phi = phi_o - phi_i (deg)")
    ax[0].set_ylabel("f (1/sr)")
    ax[0].set_title("theta_i = 20 deg, theta_o = -35 deg")
    ax[0].legend()
    # vs theta_o: phi = 0 (R, TRT side) and phi = pi (TT side)
    ths = [-math.pi / 2 + math.pi * (k + 0.5) / n for k in range(n)]
    for phi, ls in ((0.0, "-"), (math.pi, "--")):
        rows = evaluate(a.sl, a.backend, a.material, [(theta_i, 0.0, t, phi) for t in ths])
        for m in MODES:
            ax[1].plot([math.degrees(t) for t in ths], [r[m] for r in rows], ls,
                       label="%s, phi=%d" % (m, round(math.degrees(phi))))
    ax[1].set_yscale("log")
    ax[1].set_ylim(1e-4, None)
    ax[1].set_xlabel("theta_o (deg)")
    ax[1].set_title("theta_i = 20 deg")
    ax[1].legend(fontsize=7, ncol=2)
    fig.suptitle("Marschner scattering function per mode (%s backend, %s)"
                 % (a.backend, a.material or "default material"))
    fig.tight_layout()
    fig.savefig(a.out, format="svg")
    print("wrote %s" % a.out)


if __name__ == "__main__":
    main()
