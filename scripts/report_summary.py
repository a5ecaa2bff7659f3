#!/usr/bin/env python3
"""report_summary.py: the summary table docs/results.md shows for one `strandlight report`
directory (results.csv): both references (settings, time, own convergence), then the runs on
either Pareto front, the scene's base settings (MS on and off) and the diagnostic runs, with
their errors against both references and the speed-ups over each reference's time.

usage: scripts/report_summary.py REPORT_DIR"""
import csv
import math
import sys


def num(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def f3(v, fmt="%.3f"):
    v = num(v)
    return "-" if math.isnan(v) else fmt % v


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    rows = list(csv.DictReader(open(sys.argv[1] + "/results.csv")))
    ref = next(r for r in rows if r["backend"] == "reference")
    frag = next((r for r in rows if r["backend"] == "reference_fragments"), None)
    runs = [r for r in rows if r["backend"] in ("c", "opencl")]
    print("| reference | settings | time s | own error per pixel | own 4x4 |")
    print("|---|---|---|---|---|")
    print("| pixel | %s x %s, %s lights, aa %s, MS %s | %s | %s | %s |" % (
        ref["width"], ref["height"], ref["lights"], ref["aa"], ref["ms"], f3(ref["time_s"], "%.1f"),
        f3(ref["rel_rmse"]), f3(ref["rel_rmse_4x4"])))
    if frag:
        print("| fragments | the fast path's K-buffer, %s lights, MS %s | %s | %s | %s |" % (
            frag["lights"], frag["ms"], f3(frag["time_s"], "%.1f"), f3(frag["rel_rmse"]),
            f3(frag["rel_rmse_4x4"])))
    print()
    tr, tf = num(ref["time_s"]), num(frag["time_s"]) if frag else math.nan

    def label(r):
        s = "%s %s, %s lobes, K %s" % (r["backend"], r["method"], r["lobes"], r["layers"])
        if r["method"] == "xu":
            s += ", m %s" % r["m"]
        s += ", kappa %s, voxels %s, MS %s" % (r["kappa"], r["voxels"], r["ms"])
        if r.get("shading_rate") == "fragment":
            s += ", **rate fragment**"
        if r.get("broad_lobes") == "split":
            s += ", **broad split**"
        return s

    def keep(r):
        return (r["pareto"] == "1" or r["pareto_frag"] == "1" or r.get("shading_rate") == "fragment"
                or r.get("broad_lobes") == "split")

    sel = sorted([r for r in runs if keep(r)], key=lambda r: num(r["time_s"]))
    print("| run | time s | rel. RMSE | 4x4 | frag | frag 4x4 | frag R / TT / TRT / MS | x pixel ref | x frag ref |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in sel:
        mark = ("*" if r["pareto"] == "1" else "") + ("f" if r["pareto_frag"] == "1" else "")
        t = num(r["time_s"])
        print("| %s %s | %s | %s | %s | %s | %s | %s / %s / %s / %s | %.0f | %.0f |" % (
            label(r), mark, f3(t, "%.2f"), f3(r["rel_rmse"]), f3(r["rel_rmse_4x4"]),
            f3(r["rel_rmse_frag"]), f3(r.get("rel_rmse_frag_4x4")), f3(r["rel_rmse_frag_R"], "%.2f"),
            f3(r["rel_rmse_frag_TT"], "%.2f"), f3(r["rel_rmse_frag_TRT"], "%.2f"),
            f3(r["rel_rmse_frag_MS"], "%.2f"), tr / t, tf / t))
    best = lambda k: min(runs, key=lambda r: num(r[k]))
    print()
    print("Best: per pixel %s, 4x4 %s, frag %s, frag 4x4 %s; fastest run %.2f s." % (
        f3(best("rel_rmse")["rel_rmse"]), f3(best("rel_rmse_4x4")["rel_rmse_4x4"]),
        f3(best("rel_rmse_frag")["rel_rmse_frag"]),
        f3(best("rel_rmse_frag_4x4")["rel_rmse_frag_4x4"]),
        min(num(r["time_s"]) for r in runs)))


main()
