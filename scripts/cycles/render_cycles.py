"""render_cycles.py: a Strandlight scene rendered by Blender Cycles, the outside yardstick of
docs/validation.md ("Against Blender Cycles"). Blender is never a build or test dependency.

  blender -b --factory-startup --python-exit-code 1 -P scripts/cycles/render_cycles.py -- \\
      SCENE.json OUT.exr --spp N --seed S [--hair FILE.hair] [--width W --height H] \\
      [--threads T] [--bounces B] [--offset-sign flip|same] [--env-interp closest|linear] [--half]

Inputs: SCENE.json itself (read here with the json module: material, environment) and what
`strandlight export SCENE.json -o FILE.hair` wrote: the strands as the renderer sees them
(FILE.hair) and FILE.hair.camera.json (the resolved camera and image size, and the material and
environment as strandlight parsed them, which must agree with this script's reading).
--hair defaults to OUT with .hair for .exr. scripts/cycles/render.sh runs both steps.

Cycles: Principled Hair BSDF (model chiang required; Melanin parametrisation, or Absorption
Coefficient when the scene gives sigma_a), random_* 0; world = the map as our loader decodes it
(blender_scene.env_image), strength = intensity, rotation_deg applied; film transparent, no
clamping, 32 bounces of every kind (--bounces B: B of every kind; B = 0 is one scattering
event, B the B + 1 events of the path tracer's cap), box filter, no denoising
(blender_scene.settings).
--offset-sign flip (default) gives Cycles the negated offset so that its lobes shift the way ours
do (Cycles 3.4 tilts theta_i, docs/validation.md); same passes it unchanged.
--env-interp closest (default): each map pixel is constant radiance, as our loader's lookups.
Output: OUT.exr, RGBA premultiplied scene-linear float (half with --half), ZIP; OUT.exr.json
records the settings, Blender's version and the render time. Both written atomically.
Errors: one line "render_cycles.py: ..." on stderr, exit 1.
"""
import json
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy  # noqa: E402

import blender_scene as bs  # noqa: E402
import hairfile  # noqa: E402

CHIANG_DEFAULTS = {"melanin": 0.8, "melanin_redness": 1.0, "tint": [1.0, 1.0, 1.0],
                   "roughness": 0.3, "radial_roughness": 0.3, "coat": 0.0, "offset_deg": 2.0,
                   "eta": 1.55}  # numerics.md sec. 2


def fail(msg):
    sys.stderr.write(f"render_cycles.py: {msg}\n")
    sys.stderr.flush()
    sys.exit(1)


def parse_args(argv):
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    o = {"spp": None, "seed": None, "hair": None, "width": None, "height": None, "threads": 0,
         "bounces": 32,
         "offset_sign": "flip", "env_interp": "closest", "half": False}
    pos = []
    i = 0
    ints = {"--spp": "spp", "--seed": "seed", "--width": "width", "--height": "height",
            "--threads": "threads", "--bounces": "bounces"}
    while i < len(args):
        a = args[i]
        if a in ints or a in ("--hair", "--offset-sign", "--env-interp"):
            if i + 1 >= len(args):
                fail(f"{a} needs a value")
            v = args[i + 1]
            i += 2
            if a in ints:
                try:
                    o[ints[a]] = int(v)
                except ValueError:
                    fail(f"{a}: expected an integer, got '{v}'")
                if o[ints[a]] < (0 if a in ("--seed", "--threads", "--bounces") else 1):
                    fail(f"{a}: out of range: {v}")
            elif a == "--hair":
                o["hair"] = v
            elif a == "--offset-sign":
                if v not in ("flip", "same"):
                    fail(f"--offset-sign: flip or same, got '{v}'")
                o["offset_sign"] = v
            else:
                if v not in ("closest", "linear"):
                    fail(f"--env-interp: closest or linear, got '{v}'")
                o["env_interp"] = v
        elif a == "--half":
            o["half"] = True
            i += 1
        elif a.startswith("-"):
            fail(f"unknown option '{a}'")
        else:
            pos.append(a)
            i += 1
    if len(pos) != 2:
        fail("usage: ... -P render_cycles.py -- SCENE.json OUT.exr --spp N --seed S [options]")
    if o["spp"] is None or o["seed"] is None:
        fail("--spp N and --seed S are required")
    o["scene"], o["out"] = pos
    if not o["out"].lower().endswith(".exr"):
        fail(f"{o['out']}: the output must be a .exr file")
    if o["hair"] is None:
        o["hair"] = o["out"][:-4] + ".hair"
    return o


def read_scene(path):
    """Material and environment of SCENE.json with numerics.md's defaults (chiang only)."""
    try:
        s = json.load(open(path))
    except (OSError, ValueError) as ex:
        fail(f"{path}: {ex}")
    mj = s.get("material", {})
    if mj.get("model", "marschner") != "chiang":
        fail(f"{path}: material.model: Cycles' Principled Hair is model chiang, "
             f"got '{mj.get('model', 'marschner')}'")
    if "strand_sigma_a" in mj:
        fail(f"{path}: material.strand_sigma_a: per-strand absorption is not rendered in Cycles")
    m = dict(CHIANG_DEFAULTS)
    for k in list(CHIANG_DEFAULTS) + ["sigma_a"]:
        if k in mj:
            m[k] = mj[k]
    m["sigma_a_given"] = "sigma_a" in mj
    if m["sigma_a_given"] and not isinstance(m["sigma_a"], list):
        m["sigma_a"] = [m["sigma_a"]] * 3
    ej = s.get("environment", {})
    if not ej.get("file"):
        fail(f"{path}: environment.file: Cycles needs the map itself (lobes alone are not enough)")
    env = {"file": os.path.realpath(os.path.join(os.path.dirname(path), ej["file"])),
           "rotation_deg": float(ej.get("rotation_deg", 0.0)),
           "intensity": float(ej.get("intensity", 1.0))}
    return m, env


def cross_check(scene, m, env, side):
    """This script's reading of the scene against strandlight's (the sidecar)."""
    sm, se = side["material"], side["environment"]
    keys = ["eta", "sigma_a_given"] + (["sigma_a"] if m["sigma_a_given"] else [
        "melanin", "melanin_redness", "tint"]) + ["roughness", "radial_roughness", "coat",
                                                  "offset_deg"]
    for k in keys:
        a, b = m[k], sm.get(k)
        same = (a == b) if isinstance(a, bool) else b is not None and all(
            math.isclose(x, y, rel_tol=1e-9, abs_tol=1e-12)
            for x, y in zip(a if isinstance(a, list) else [a], b if isinstance(b, list) else [b]))
        if not same:
            fail(f"{scene}: material.{k}: read here as {a}, strandlight export parsed {b}")
    if os.path.realpath(se["file"]) != env["file"]:
        fail(f"{scene}: environment.file: {env['file']} here, {se['file']} for strandlight")
    for k in ("rotation_deg", "intensity"):
        if not math.isclose(se[k], env[k], rel_tol=1e-12, abs_tol=1e-12):
            fail(f"{scene}: environment.{k}: {env[k]} here, {se[k]} for strandlight")
    if side.get("strand_sigma_a"):
        fail(f"{scene}: material.strand_sigma_a is not rendered in Cycles")


def main():
    o = parse_args(sys.argv)
    m, env = read_scene(o["scene"])
    side_path = o["hair"] + ".camera.json"
    try:
        side = json.load(open(side_path))
        h = hairfile.read(o["hair"])
    except (OSError, ValueError) as ex:
        fail(f"{ex} (run strandlight export {o['scene']} -o {o['hair']} first)")
    cross_check(o["scene"], m, env, side)
    W, H = side["image"]["width"], side["image"]["height"]
    if (o["width"] or W) != W or (o["height"] or H) != H:
        fail(f"{side_path}: the camera was resolved for {W} x {H}; export again with "
             f"--width {o['width'] or W} --height {o['height'] or H}")
    if h.num_strands != side["strands"] or len(h.points) != side["points"]:
        fail(f"{o['hair']}: {h.num_strands} strands, {side_path} says {side['strands']}")

    try:
        sc = bs.reset()
        bs.settings(sc, W, H, o["spp"], o["seed"], o["threads"], transparent=True,
                    bounces=o["bounces"])
        bs.output_exr(sc, o["half"])
        bs.world(sc, bs.env_image(env["file"]), env["rotation_deg"], env["intensity"],
                 "Closest" if o["env_interp"] == "closest" else "Linear")
        c = side["camera"]
        lo, hi = side["bounds"]["lo"], side["bounds"]["hi"]
        diag = math.dist(lo, hi)
        dist = math.dist(c["eye"], [(a + b) / 2 for a, b in zip(lo, hi)])
        bs.camera(sc, c["eye"], c["right"], c["up_ortho"], c["forward"], c["fov_deg"],
                  clip_start=1e-5 * (dist + diag), clip_end=10 * (dist + diag))
        sign = -1.0 if o["offset_sign"] == "flip" else 1.0
        ob = bs.hair(sc, h, bs.hair_material(m, sign))
        bs.check_hair(ob, h)
    except (bs.SceneError, OSError, ValueError) as ex:
        fail(str(ex))

    out = os.path.abspath(o["out"])
    os.makedirs(os.path.dirname(out), exist_ok=True)
    tmp = f"{out}.tmp{os.getpid()}.exr"
    sc.render.filepath = tmp
    sc.render.use_file_extension = False
    t0 = time.time()
    bpy.ops.render.render(write_still=True)
    seconds = time.time() - t0
    if not os.path.isfile(tmp):
        fail(f"{out}: Cycles wrote nothing")
    record = {"blender": bpy.app.version_string, "scene": o["scene"], "hair": o["hair"],
              "width": W, "height": H, "spp": o["spp"], "seed": o["seed"],
              "threads": sc.render.threads, "render_seconds": round(seconds, 2),
              "offset_sign": o["offset_sign"], "env_interp": o["env_interp"],
              "half": o["half"], "material": m, "environment": env,
              "settings": {"max_bounces": o["bounces"], "clamp": 0, "filter": "box 1 px",
                           "film_transparent": True, "denoising": False,
                           "adaptive_sampling": False, "curve_shape": "THICK"}}
    with open(out + ".json.tmp", "w") as f:
        json.dump(record, f, indent=1)
        f.write("\n")
    os.replace(tmp, out)
    os.replace(out + ".json.tmp", out + ".json")
    print(f"render_cycles.py: {out}: {W} x {H}, {o['spp']} spp, seed {o['seed']}, "
          f"{seconds:.1f} s (Blender {bpy.app.version_string})")


main()
