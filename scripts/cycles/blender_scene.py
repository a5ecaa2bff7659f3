"""blender_scene.py: the pieces of a Strandlight scene built in Blender 3.4 for Cycles (bpy).

Used by render_cycles.py (hair renders) and check_envmap.py (the frame check of
docs/validation.md). Every setting that could bias Cycles against a plain path tracer is set
explicitly (settings()): no clamping, no Filter Glossy, no light threshold, no adaptive sampling,
no denoising, no path guiding, 32 bounces of every kind (or `bounces`), box pixel filter of one
pixel, fixed seed and sample count, CPU.
"""
import math

import bpy
import numpy as np
from mathutils import Matrix

import frames


class SceneError(Exception):
    """A one-line problem with the inputs (the caller prints it and exits 1)."""


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return bpy.context.scene


def settings(sc, width, height, spp, seed, threads, transparent, bounces=32):
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    cy.feature_set = "SUPPORTED"
    cy.samples = spp
    cy.seed = seed
    cy.use_animated_seed = False
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0  # Filter Glossy widens the hair lobes (bsdf_principled_hair_blur)
    cy.light_sampling_threshold = 0.0
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    cy.use_fast_gi = False
    cy.use_guiding = False
    cy.auto_scrambling_distance = False
    cy.scrambling_distance = 1.0
    cy.max_bounces = bounces
    for k in ("diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces",
              "transparent_max_bounces"):
        setattr(cy, k, bounces)
    cy.min_light_bounces = 0
    cy.min_transparent_bounces = 0
    cy.pixel_filter_type = "BOX"  # our pixels are box-filtered (K x K jittered rays)
    cy.filter_width = 1.0
    cy.film_exposure = 1.0
    sc.cycles_curves.shape = "THICK"  # round 3D curves, not camera-facing ribbons
    r = sc.render
    r.film_transparent = transparent
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_border = False
    r.use_motion_blur = False
    r.use_compositing = False
    r.use_sequencer = False
    r.threads_mode = "FIXED" if threads else "AUTO"
    if threads:
        r.threads = threads
    # scene-linear output, nothing applied on the way (EXR is written linear anyway)
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0


def output_exr(sc, half):
    s = sc.render.image_settings
    s.file_format = "OPEN_EXR"
    s.color_mode = "RGBA"
    s.color_depth = "16" if half else "32"
    s.exr_codec = "ZIP"


def env_image(path):
    """The map as our loader sees it (float32 (H, W, 3), row 0 top): .hdr decoded the stb way
    (rgbe.py), .exr through Blender with negatives clamped to 0 as host/io/envmap does."""
    if path.lower().endswith(".hdr"):
        import rgbe
        return rgbe.read(path)
    img = bpy.data.images.load(path, check_existing=False)
    img.colorspace_settings.name = "Linear"
    w, h = img.size
    px = np.empty(4 * w * h, np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    rgb = px.reshape(h, w, 4)[::-1, :, :3]  # Blender rows run bottom-up
    if not np.all(np.isfinite(rgb)):
        raise SceneError(f"{path}: NaN or Inf pixels (strandlight refuses them too)")
    return np.maximum(rgb, 0.0)


def world(sc, rgb, rotation_deg, intensity, interpolation):
    """World = Environment Texture of the float pixels rgb (our row order), Background strength
    = intensity, looked up at R_Z(-rotation) d (frames.py)."""
    h, w = rgb.shape[:2]
    img = bpy.data.images.new("strandlight_env", w, h, alpha=True, float_buffer=True)
    img.colorspace_settings.name = "Linear"
    rgba = np.ones((h, w, 4), np.float32)
    rgba[:, :, :3] = rgb[::-1]
    img.pixels.foreach_set(rgba.ravel())
    img.update()
    wd = bpy.data.worlds.new("strandlight_world")
    sc.world = wd
    wd.use_nodes = True
    nt = wd.node_tree
    nt.nodes.clear()
    tc = nt.nodes.new("ShaderNodeTexCoord")
    mp = nt.nodes.new("ShaderNodeMapping")
    mp.vector_type = "POINT"
    mp.inputs["Rotation"].default_value = (0.0, 0.0, -math.radians(rotation_deg))
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = img
    env.projection = "EQUIRECTANGULAR"
    env.interpolation = interpolation
    bg = nt.nodes.new("ShaderNodeBackground")
    bg.inputs["Strength"].default_value = intensity
    out = nt.nodes.new("ShaderNodeOutputWorld")
    nt.links.new(tc.outputs["Generated"], mp.inputs["Vector"])
    nt.links.new(mp.outputs["Vector"], env.inputs["Vector"])
    nt.links.new(env.outputs["Color"], bg.inputs["Color"])
    nt.links.new(bg.outputs["Background"], out.inputs["Surface"])
    # importance map on the map's own pixel grid (unbiased either way; this is the least noisy)
    wd.cycles.sampling_method = "MANUAL"
    wd.cycles.sample_map_resolution = w
    return img


def camera(sc, eye, right, up, forward, fov_deg, clip_start, clip_end):
    """A pinhole camera at our eye with our orthonormal frame (Blender cameras look down their
    local -Z with +Y up) and vertical field of view fov_deg."""
    cam = bpy.data.cameras.new("strandlight_camera")
    cam.type = "PERSP"
    cam.sensor_fit = "VERTICAL"
    cam.angle_y = math.radians(fov_deg)
    cam.shift_x = cam.shift_y = 0.0
    cam.clip_start, cam.clip_end = clip_start, clip_end
    ob = bpy.data.objects.new("strandlight_camera", cam)
    sc.collection.objects.link(ob)
    x, y, z = (frames.to_blender(v) for v in (right, up, -np.asarray(forward, np.float64)))
    e = frames.to_blender(eye)
    ob.matrix_world = Matrix([[x[0], y[0], z[0], e[0]], [x[1], y[1], z[1], e[1]],
                              [x[2], y[2], z[2], e[2]], [0, 0, 0, 1]])
    sc.camera = ob
    return ob


def hair_material(m, offset_sign):
    """Principled Hair BSDF (Chiang) from the parsed material m (render_cycles.py's dict):
    Melanin parametrisation, or Absorption Coefficient when sigma_a was given; random_* = 0.
    offset_sign -1 hands Cycles the negated offset (docs/validation.md: Cycles 3.4 tilts the
    incident angle, so its Offset shifts the lobes the other way from ours)."""
    mat = bpy.data.materials.new("strandlight_hair")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    hb = nt.nodes.new("ShaderNodeBsdfHairPrincipled")
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(hb.outputs["BSDF"], out.inputs["Surface"])

    def put(name, value):
        if name not in hb.inputs:
            raise SceneError(f"Principled Hair BSDF has no input '{name}' in this Blender")
        hb.inputs[name].default_value = value

    if m["sigma_a_given"]:
        hb.parametrization = "ABSORPTION"
        put("Absorption Coefficient", tuple(m["sigma_a"]))
    else:
        hb.parametrization = "MELANIN"
        put("Melanin", m["melanin"])
        put("Melanin Redness", m["melanin_redness"])
        put("Tint", tuple(m["tint"]) + (1.0,))
    put("Roughness", m["roughness"])
    put("Radial Roughness", m["radial_roughness"])
    put("Coat", m["coat"])
    put("IOR", m["eta"])
    put("Offset", offset_sign * math.radians(m["offset_deg"]))
    put("Random Color", 0.0)
    put("Random Roughness", 0.0)
    put("Random", 0.0)
    return mat


def hair(sc, h, mat):
    """The strands of hairfile.Hair h as a Curves object: a hidden mesh of edges turned into
    poly curves by Geometry Nodes (Mesh to Curve, Set Curve Radius from a point attribute, Set
    Material). Blender 3.4's Python cannot size a Curves data-block itself, and the curves of a
    mesh object's nodes are rendered as a legacy curve (nothing), so the nodes sit on a Curves
    object, which Cycles renders as hair. Returns the object; check_hair() verifies it."""
    pts = frames.to_blender(h.points).astype(np.float32)
    P, S = len(pts), h.num_strands
    first = h.strand_first
    idx = np.arange(P, dtype=np.int64)
    last = np.zeros(P, bool)
    last[first[1:] - 1] = True
    a = idx[~last]
    edges = np.stack([a, a + 1], axis=1).astype(np.int32)
    me = bpy.data.meshes.new("strandlight_strands")
    me.vertices.add(P)
    me.vertices.foreach_set("co", pts.ravel())
    me.edges.add(len(edges))
    me.edges.foreach_set("vertices", edges.ravel())
    at = me.attributes.new("sl_radius", "FLOAT", "POINT")
    at.data.foreach_set("value", h.radius.astype(np.float32))
    me.update()
    mob = bpy.data.objects.new("strandlight_strands", me)
    sc.collection.objects.link(mob)
    mob.hide_render = True

    cv = bpy.data.hair_curves.new("strandlight_hair")
    cv.materials.append(mat)
    ob = bpy.data.objects.new("strandlight_hair", cv)
    sc.collection.objects.link(ob)
    ng = bpy.data.node_groups.new("strandlight_mesh_to_hair", "GeometryNodeTree")
    ng.inputs.new("NodeSocketGeometry", "Geometry")
    ng.outputs.new("NodeSocketGeometry", "Geometry")
    n, l = ng.nodes, ng.links
    go = n.new("NodeGroupOutput")
    oi = n.new("GeometryNodeObjectInfo")
    oi.inputs["Object"].default_value = mob
    oi.transform_space = "ORIGINAL"
    m2c = n.new("GeometryNodeMeshToCurve")
    rad = n.new("GeometryNodeSetCurveRadius")
    na = n.new("GeometryNodeInputNamedAttribute")
    na.data_type = "FLOAT"
    na.inputs["Name"].default_value = "sl_radius"
    sm = n.new("GeometryNodeSetMaterial")
    sm.inputs["Material"].default_value = mat
    l.new(oi.outputs["Geometry"], m2c.inputs["Mesh"])
    l.new(m2c.outputs["Curve"], rad.inputs["Curve"])
    # Named Attribute has one output per data type; only the FLOAT one is enabled
    l.new([o for o in na.outputs if o.enabled][0], rad.inputs["Radius"])
    l.new(rad.outputs["Curve"], sm.inputs["Geometry"])
    l.new(sm.outputs["Geometry"], go.inputs["Geometry"])
    mod = ob.modifiers.new("strandlight_mesh_to_hair", "NODES")
    mod.node_group = ng
    return ob


def check_hair(ob, h):
    """The evaluated curves must be the strands exactly: same count, each root first (Mesh to
    Curve walks a chain from its lowest vertex; a reversed strand would flip the cuticle tilt),
    same points and radii. Raises SceneError otherwise."""
    dg = bpy.context.evaluated_depsgraph_get()
    cv = ob.evaluated_get(dg).data
    if ob.evaluated_get(dg).type != "CURVES" or len(cv.curves) != h.num_strands:
        raise SceneError(f"Blender made {len(cv.curves)} curves of {h.num_strands} strands")
    P = len(cv.points)
    pos = np.empty(3 * P, np.float32)
    cv.points.foreach_get("position", pos)
    rad = np.empty(P, np.float32)
    cv.points.foreach_get("radius", rad)
    off = np.empty(len(cv.curves) + 1, np.int32)
    cv.curve_offset_data.foreach_get("value", off)
    want = frames.to_blender(h.points).astype(np.float32)
    if P != len(want) or not np.array_equal(off, h.strand_first.astype(np.int32)) \
            or not np.allclose(pos.reshape(-1, 3), want, rtol=0, atol=1e-5 * (1 + np.abs(want).max())) \
            or not np.allclose(rad, h.radius, rtol=1e-6, atol=0):
        raise SceneError("Blender's curves differ from the .hair strands (order, points or radii)")
