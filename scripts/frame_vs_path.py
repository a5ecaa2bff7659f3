#!/usr/bin/env python3
"""frame_vs_path.py: the fast frame against the path tracer on a few scenes, references cached.

    scripts/frame_vs_path.py [--build DIR] [--refdir DIR] [--spp N] [--size WxH]
                             [--quality JSON] [--device c] SCENE.json ...

For each scene: the path-traced reference (`strandlight reference --path`, two seeds of N spp at
the given size) is rendered once into REFDIR and reused (it does not depend on the fast frame);
then the fast frame (`render --aov MS`, the scene's quality updated with --quality) is rendered
and compared (`strandlight compare --block 4`, corrected for the reference's noise): mean colour
ours / path tracer per channel and the 4x4-block relative RMSE, of the beauty and of multiple
scattering (ours' `MS` layer against the path tracer's indirect light); with --single also single
scattering (ours with multiple scattering off against the path tracer's direct light). Relative paths in the
scene are resolved against the scene's folder; its `output` is dropped. Used for the tables in
docs/results.md ("Multiple scattering: where the light goes after the first event").
"""
import argparse
import hashlib
import json
import os
import subprocess
import sys


def resolve(scene, base):
    for sect, key in (("hair", "file"), ("environment", "file"), ("environment", "lobes")):
        f = scene.get(sect, {}).get(key)
        if isinstance(f, str) and not os.path.isabs(f):
            scene[sect][key] = os.path.normpath(os.path.join(base, f))
    scene.pop("output", None)
    return scene


def compare(sl, ours, refs, layer, ref_layer=None):
    cmd = [sl, "compare", ours] + refs + ["--block", "4", "--csv"]
    if layer:
        cmd += ["--layer", layer]
    if ref_layer:
        cmd += ["--ref-layer", ref_layer]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    ratio, blocks = None, None
    for line in out.splitlines():
        f = line.split(",")
        if f[0] == "ratio":
            ratio = [float(x) for x in f[1:4]]
        if f[0] == "rel_rmse_blocks_corrected":
            blocks = float(f[4])
    return ratio, blocks


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--build", default="build")
    ap.add_argument("--refdir", default=os.path.expanduser("~/.cache/strandlight-frame-vs-path"))
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--size", default="160x120")
    ap.add_argument("--quality", default="{}", help="JSON object merged into the fast frame's quality")
    ap.add_argument("--material", default="{}", help="JSON object merged into the material (both)")
    ap.add_argument("--device", default="c")
    ap.add_argument("--single", action="store_true",
                    help="also single scattering alone (ours with multiple scattering off) against "
                         "the path tracer's direct light")
    a = ap.parse_args()
    sl = os.path.abspath(os.path.join(a.build, "strandlight"))
    w, h = (int(x) for x in a.size.split("x"))
    os.makedirs(a.refdir, exist_ok=True)
    for path in a.scenes:
        scene = resolve(json.load(open(path)), os.path.dirname(os.path.abspath(path)))
        scene.setdefault("material", {}).update(json.loads(a.material))
        scene["image"] = {"width": w, "height": h}
        ref_scene = dict(scene)
        ref_scene.pop("quality", None)
        key = hashlib.sha256(json.dumps([ref_scene, a.spp], sort_keys=True).encode()).hexdigest()[:16]
        name = os.path.splitext(os.path.basename(path))[0]
        stem = os.path.join(a.refdir, f"{name}_{key}")
        with open(stem + ".json", "w") as f:
            json.dump(ref_scene, f)
        refs = []
        for seed in (1, 2):
            ref = f"{stem}_s{seed}.exr"
            if not os.path.exists(ref):
                print(f"{name}: path tracer, seed {seed}, {a.spp} spp at {w}x{h} ...", file=sys.stderr)
                subprocess.run([sl, "--quiet", "reference", stem + ".json", "--path", "--spp",
                                str(a.spp), "--seed", str(seed), "--threads", "2", "-o", ref + ".tmp.exr"],
                               check=True)
                os.replace(ref + ".tmp.exr", ref)
                if os.path.exists(ref + ".tmp.exr.json"):
                    os.replace(ref + ".tmp.exr.json", ref + ".json")
            refs.append(ref)
        scene.setdefault("quality", {}).update(json.loads(a.quality))
        fast = stem + "_fast.json"
        with open(fast, "w") as f:
            json.dump(scene, f)
        ours = stem + "_fast.exr"
        # --method fast: `auto` would take Ren's table where one for the material is in the disk
        # cache (docs/frame.md, "SRBF method"), so the figures would depend on the cache's state
        subprocess.run([sl, "--quiet", "render", fast, "--device", a.device, "--method", "fast",
                        "--aov", "MS", "-o", ours], check=True)
        rb, bb = compare(sl, ours, refs, None)
        rm, bm = compare(sl, ours, refs, "MS")
        line = (f"{name:28s} beauty {rb[0]:.3f} {rb[1]:.3f} {rb[2]:.3f} (4x4 {bb:.3f})   "
                f"MS {rm[0]:.3f} {rm[1]:.3f} {rm[2]:.3f} (4x4 {bm:.3f})")
        if a.single:
            scene["quality"]["multiple_scattering"] = "off"
            with open(fast, "w") as f:
                json.dump(scene, f)
            subprocess.run([sl, "--quiet", "render", fast, "--device", a.device, "--method",
                            "fast", "-o", ours], check=True)
            rs, bs = compare(sl, ours, refs, None, "direct")
            line += f"   S {rs[0]:.3f} {rs[1]:.3f} {rs[2]:.3f} (4x4 {bs:.3f})"
        print(line, flush=True)


if __name__ == "__main__":
    main()
