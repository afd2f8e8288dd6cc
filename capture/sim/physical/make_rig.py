"""Physical rig generator: garments as cloth draped on the dress form by Blender's cloth solver,
path-traced with Cycles through a distorted perspective camera. Shares no code with the
station (docs/physical_rig.md).

    blender -b --python capture/sim/physical/make_rig.py -- --out DIR --count N --seed S \
        [--form FORM.json] [--width W --height H] [--samples 24] [--frames 24] [--start K]

Writes DIR/case_XXX/{empty.jpg, dressed.jpg, truth.json, camera.json} and DIR/rig.json.
"""
import argparse
import json
import math
import os
import shutil
import sys
import time

import bmesh
import bpy
import numpy as np

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import formgeom as fg  # noqa: E402
import garments as gm  # noqa: E402

CM = 0.01  # Blender works in metres


def to_blender(p):
    """Form coordinates (cm; y up, facing +z) to Blender's (m; z up, the form facing -y)."""
    p = np.asarray(p, float)
    return np.column_stack([p[:, 0], -p[:, 2], p[:, 1]]) * CM


def from_blender(p):
    p = np.asarray(p, float) / CM
    return np.column_stack([p[:, 0], p[:, 2], -p[:, 1]])


# ---------------------------------------------------------------- arguments and case plan


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="make_rig.py", description=__doc__.split("\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    default_form = os.path.normpath(os.path.join(
        here, "../../../../shared/data/forms/garmentcode_mean_female/form.json"))
    ap.add_argument("--out", required=True)
    ap.add_argument("--count", type=int, required=True)
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--form", default=default_form)
    ap.add_argument("--width", type=int, default=888)
    ap.add_argument("--height", type=int, default=1184)
    ap.add_argument("--samples", type=int, default=6)
    ap.add_argument("--frames", type=int, default=12, help="cloth settling frames")
    ap.add_argument("--start", type=int, default=0, help="first case index (resume)")
    ap.add_argument("--quality", type=int, default=92, help="JPEG quality")
    ap.add_argument("--hoop", action="store_true",
                    help="make dresses as rigs made before the fix did (full forms before "
                         "h/dress15, torso forms before h/torsogen15): the skirt's waistband "
                         "pinned outside the bodice as cut, a stiff hoop at the waist")
    ap.add_argument("--clearance-parts", action="store_true",
                    help="class sleeve cloth for truth.json as rigs made before h/busttruth15 "
                         "did: below the armpit, only cloth more than the waist ease + 1 cm "
                         "beyond the torso's side (a sleeve's inner side counted in the bust)")
    ap.add_argument("--hem-shape", choices=("level", "high_low", "asymmetric"), default="level",
                    help="cut every skirt's and dress's hem so: high_low (its back 8-18 cm "
                         "longer than its front), asymmetric (one side 8-18 cm longer than the "
                         "other); level as before")
    ap.add_argument("--no-render", action="store_true",
                    help="settle the cloth and write truth.json only (for checking garments)")
    ap.add_argument("--session-size", type=int, default=6,
                    help="cases in a row that share camera, lights and bare-form frame")
    a = ap.parse_args(argv)
    if a.session_size < 1:
        ap.error("--session-size must be at least 1")
    if a.count < 1:
        ap.error("--count must be at least 1")
    if not (300 <= a.width <= 4000 and 300 <= a.height <= 4000):
        ap.error("--width and --height must be 300..4000 px")
    if not os.path.isfile(a.form):
        ap.error(f"--form {a.form}: no such file")
    return a


# Garment kinds in the order cases cycle through them: every type, and the sleeve and skirt
# styles the station's rigs never drew (cap, three-quarter, mid-flare, wide legs).
PLAN = [
    ("top", {"sleeve": "short"}), ("skirt", {"skirt": "h_line"}), ("pants", {"leg": "straight"}),
    ("dress", {"sleeve": "none", "skirt": "a_line"}), ("top", {"sleeve": "three_quarter"}),
    ("skirt", {"skirt": "a_line"}), ("pants", {"leg": "wide"}),
    ("dress", {"sleeve": "short", "skirt": "h_line"}), ("top", {"sleeve": "none"}),
    ("skirt", {"skirt": "mid_flare"}), ("top", {"sleeve": "long"}),
    ("dress", {"sleeve": "cap", "skirt": "mid_flare"}), ("pants", {"leg": "slim"}),
    ("top", {"sleeve": "cap"}), ("dress", {"sleeve": "long", "skirt": "h_line"}),
]
# On a torso form (no arms, no legs): sleeveless tops and dresses and skirts, no pants; the
# station does not read sleeves on an armless form, and a sleeve would hang empty.
TORSO_PLAN = [
    ("top", {"sleeve": "none"}), ("skirt", {"skirt": "h_line"}),
    ("dress", {"sleeve": "none", "skirt": "a_line"}), ("skirt", {"skirt": "a_line"}),
    ("top", {"sleeve": "none"}), ("dress", {"sleeve": "none", "skirt": "h_line"}),
    ("skirt", {"skirt": "mid_flare"}), ("dress", {"sleeve": "none", "skirt": "mid_flare"}),
]
FABRICS = ["light", "dark", "print", "form", "stripes", "mid", "checks", "dark", "light",
           "print", "mid", "form"]


def station_attributes(kind, style):
    """The station's attribute vocabulary (sleeve none/short/long, skirt h_line/a_line): cap
    and short sleeves are short, three-quarter and long are long (a sleeve past the elbow);
    mid-flare and A-line skirts are both a_line (the hem flares out from the hip)."""
    out = {}
    if "sleeve" in style:
        out["sleeve"] = {"none": "none", "cap": "short", "short": "short",
                         "three_quarter": "long", "long": "long"}[style["sleeve"]]
    if "skirt" in style:
        out["skirt"] = "h_line" if style["skirt"] == "h_line" else "a_line"
    return out


# ---------------------------------------------------------------- scene


def clear_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def mesh_object(name, verts_cm, faces, smooth=True):
    me = bpy.data.meshes.new(name)
    me.from_pydata(to_blender(verts_cm).tolist(), [], np.asarray(faces).tolist())
    me.update()
    if smooth:
        me.polygons.foreach_set("use_smooth", [True] * len(me.polygons))
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def evaluated_mesh(ob):
    """Vertices (cm, form coordinates) and triangles of an object with its modifiers applied."""
    dg = bpy.context.evaluated_depsgraph_get()
    ev = ob.evaluated_get(dg)
    me = ev.to_mesh()
    me.calc_loop_triangles()
    v = np.zeros(len(me.vertices) * 3)
    me.vertices.foreach_get("co", v)
    t = np.zeros(len(me.loop_triangles) * 3, np.int64)
    me.loop_triangles.foreach_get("vertices", t)
    mw = np.array(ev.matrix_world)
    v = v.reshape(-1, 3) @ mw[:3, :3].T + mw[:3, 3]
    ev.to_mesh_clear()
    return from_blender(v), t.reshape(-1, 3)


def principled(name, base, rough=0.8, sheen=0.0):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*base, 1.0)
    bsdf.inputs["Roughness"].default_value = rough
    bsdf.inputs["Sheen"].default_value = sheen
    bsdf.inputs["Specular"].default_value = 0.25
    return mat, bsdf


def srgb_to_linear(c):
    c = np.asarray(c, float)
    return tuple(np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4))


def fabric_material(kind, rng, form_rgb):
    """Cycles material of a fabric kind: solids, stripes, checks, prints (procedural, in object
    coordinates, so the pattern is carried over the cloth's folds) and form-coloured."""
    if kind == "light":
        base = rng.choice([(0.92, 0.92, 0.90), (0.95, 0.85, 0.80), (0.80, 0.88, 0.95), (0.95, 0.93, 0.75)])
    elif kind == "dark":
        base = rng.choice([(0.04, 0.04, 0.05), (0.05, 0.06, 0.14), (0.12, 0.04, 0.05), (0.06, 0.08, 0.05)])
    elif kind == "mid":
        base = rng.choice([(0.55, 0.15, 0.15), (0.20, 0.30, 0.60), (0.60, 0.45, 0.20), (0.45, 0.25, 0.45)])
    elif kind == "form":
        base = tuple(np.clip(np.asarray(form_rgb) + rng.uniform(-0.03, 0.03, 3), 0, 1))
    else:
        base = rng.choice([(0.85, 0.85, 0.85), (0.90, 0.80, 0.70), (0.70, 0.80, 0.90)])
    base_lin = srgb_to_linear(base)
    mat, bsdf = principled("fabric", base_lin, rough=float(rng.uniform(0.6, 0.95)),
                           sheen=float(rng.uniform(0.0, 0.5)))
    nt = mat.node_tree
    if kind in ("stripes", "checks", "print"):
        accent = srgb_to_linear(rng.choice([(0.10, 0.15, 0.45), (0.60, 0.10, 0.10), (0.05, 0.05, 0.05), (0.15, 0.40, 0.20)]))
        coord = nt.nodes.new("ShaderNodeTexCoord")
        mix = nt.nodes.new("ShaderNodeMixRGB")
        mix.inputs["Color1"].default_value = (*base_lin, 1)
        mix.inputs["Color2"].default_value = (*accent, 1)
        period = float(rng.uniform(1.5, 4.0)) * CM
        if kind == "stripes":
            tex = nt.nodes.new("ShaderNodeTexWave")
            tex.wave_type = "BANDS"
            tex.bands_direction = str(rng.choice(["X", "Z"]))
            tex.inputs["Scale"].default_value = 0.1 * math.pi / period  # bands of sin(20 s x)
            tex.inputs["Distortion"].default_value = 0.0
            ramp = nt.nodes.new("ShaderNodeValToRGB")
            ramp.color_ramp.interpolation = "CONSTANT"
            ramp.color_ramp.elements[1].position = 0.5
            nt.links.new(coord.outputs["Object"], tex.inputs["Vector"])
            nt.links.new(tex.outputs["Fac"], ramp.inputs["Fac"])
            nt.links.new(ramp.outputs["Color"], mix.inputs["Fac"])
        elif kind == "checks":
            tex = nt.nodes.new("ShaderNodeTexChecker")
            tex.inputs["Scale"].default_value = 1.0 / period
            tex.inputs["Color1"].default_value = (1, 1, 1, 1)
            tex.inputs["Color2"].default_value = (0, 0, 0, 1)
            nt.links.new(coord.outputs["Object"], tex.inputs["Vector"])
            nt.links.new(tex.outputs["Color"], mix.inputs["Fac"])
        else:
            tex = nt.nodes.new("ShaderNodeTexVoronoi")
            tex.inputs["Scale"].default_value = 1.0 / period
            ramp = nt.nodes.new("ShaderNodeValToRGB")
            ramp.color_ramp.interpolation = "CONSTANT"
            ramp.color_ramp.elements[0].color = (1, 1, 1, 1)
            ramp.color_ramp.elements[1].color = (0, 0, 0, 1)
            ramp.color_ramp.elements[1].position = float(rng.uniform(0.25, 0.4))
            nt.links.new(coord.outputs["Object"], tex.inputs["Vector"])
            nt.links.new(tex.outputs["Distance"], ramp.inputs["Fac"])
            nt.links.new(ramp.outputs["Color"], mix.inputs["Fac"])
        nt.links.new(mix.outputs["Color"], bsdf.inputs["Base Color"])
    # A faint weave bump: real cloth is never a flat colour.
    bump = nt.nodes.new("ShaderNodeBump")
    noise = nt.nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 400.0
    bump.inputs["Strength"].default_value = 0.15
    nt.links.new(noise.outputs["Fac"], bump.inputs["Height"])
    nt.links.new(bump.outputs["Normal"], bsdf.inputs["Normal"])
    return mat, {"kind": kind, "base_srgb": [float(c) for c in base]}


def build_studio(rng, form_rgb):
    scene = bpy.context.scene
    # Green screen: a backdrop behind the form and a floor, with a slight unevenness.
    screen_rgb = (rng.uniform(0.08, 0.16), rng.uniform(0.42, 0.58), rng.uniform(0.10, 0.18))
    mat, bsdf = principled("screen", srgb_to_linear(screen_rgb), rough=0.95)
    nt = mat.node_tree
    noise = nt.nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 2.0
    mix = nt.nodes.new("ShaderNodeMixRGB")
    mix.blend_type = "MULTIPLY"
    mix.inputs["Fac"].default_value = 0.12
    mix.inputs["Color1"].default_value = (*srgb_to_linear(screen_rgb), 1)
    nt.links.new(noise.outputs["Color"], mix.inputs["Color2"])
    nt.links.new(mix.outputs["Color"], bsdf.inputs["Base Color"])
    back_y = rng.uniform(0.7, 1.1)
    bpy.ops.mesh.primitive_plane_add(size=1, location=(0, back_y, 1.4), rotation=(math.pi / 2, 0, 0))
    back = bpy.context.active_object
    back.scale = (6, 4, 1)
    back.data.materials.append(mat)
    bpy.ops.mesh.primitive_plane_add(size=1, location=(0, back_y - 2.5, 0))
    floor = bpy.context.active_object
    floor.scale = (6, 5, 1)
    floor.data.materials.append(mat)
    # Key light above and to one side of the camera: it throws the garment's shadow on the form
    # and on itself. A weak fill and the world light keep the shadow side readable.
    side = rng.choice([-1, 1])
    key_az = math.radians(rng.uniform(20, 45)) * side
    key_el = math.radians(rng.uniform(20, 40))
    dist = 3.0
    kx, ky, kz = dist * math.sin(key_az), -dist * math.cos(key_az), 1.2 + dist * math.sin(key_el)
    key = bpy.data.lights.new("key", "AREA")
    key.size = rng.uniform(0.3, 0.8)
    key.energy = rng.uniform(220, 320)
    kob = bpy.data.objects.new("key", key)
    kob.location = (kx, ky, kz)
    direction = np.array([0, 0, 1.1]) - np.array([kx, ky, kz])
    kob.rotation_euler = direction_to_euler(direction)
    scene.collection.objects.link(kob)
    fill = bpy.data.lights.new("fill", "AREA")
    fill.size = 1.5
    fill.energy = key.energy * rng.uniform(0.15, 0.3)
    fob = bpy.data.objects.new("fill", fill)
    fob.location = (-kx * 0.8, -2.6, 1.3)
    fob.rotation_euler = direction_to_euler(np.array([0, 0, 1.0]) - np.array(fob.location))
    scene.collection.objects.link(fob)
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = rng.uniform(0.08, 0.16)
    scene.world = world
    return {"screen_srgb": [float(c) for c in screen_rgb], "backdrop_m": float(back_y),
            "key_light_m": [float(kx), float(ky), float(kz)], "key_energy_w": float(key.energy),
            "key_size_m": float(key.size), "fill_energy_w": float(fill.energy)}


def direction_to_euler(d):
    from mathutils import Vector
    return Vector(tuple(d)).to_track_quat("-Z", "Y").to_euler()


# Room kept between the form's top and the frame's top edge at the axis plane, cm: the top's
# front stands closer to the camera and the lens bows it outward, so a torso form framed with
# 2.2 cm there touched the edge in its bare frame (seed 5252, session 1) and the station
# rightly refused to calibrate; 4.4 cm was enough (seed 2015, session 1).
TOP_HEADROOM_CM = 4.0


def build_camera(rng, width, height, margin, span=(192, 206), top_cm=None):
    """A perspective camera 2.7-3.1 m in front of the form's axis plane, looking along +y
    (form -z), framing the whole form (top_cm: its highest point) with TOP_HEADROOM_CM above
    it; returns its intrinsics as OpenCV would state them."""
    scene = bpy.context.scene
    distance_cm = rng.uniform(270, 310)
    span_cm = rng.uniform(*span)  # frame height at the axis plane
    fy = (height / 2) / (span_cm / 2 / distance_cm)
    cam = bpy.data.cameras.new("cam")
    cam.sensor_fit = "VERTICAL"
    cam.sensor_height = 24.0
    # Blender's focal length is relative to the whole render, border included.
    cam.lens = fy / (height + 2 * margin) * cam.sensor_height
    ob = bpy.data.objects.new("cam", cam)
    scene.collection.objects.link(ob)
    cx_cm = rng.uniform(-4, 4)
    # The feet (a torso form's foot) 10-16 cm above the frame's bottom edge: registration needs the whole form in
    # view, contact shadow included.
    foot_cm = rng.uniform(10, 16)
    if top_cm is not None:
        # Lower the frame, never the draw: every framing that kept the room is unchanged.
        foot_cm = min(foot_cm, span_cm - top_cm - TOP_HEADROOM_CM)
    cz_cm = span_cm / 2 - foot_cm
    roll = math.radians(rng.uniform(-0.6, 0.6))
    ob.location = (cx_cm * CM, -distance_cm * CM, cz_cm * CM)
    ob.rotation_euler = (math.pi / 2, roll, 0)
    scene.camera = ob
    return {"distance_cm": distance_cm, "fx": fy, "fy": fy, "cx": (width - 1) / 2,
            "cy": (height - 1) / 2, "position_cm": [cx_cm, cz_cm, distance_cm],
            "roll_deg": math.degrees(roll)}


def configure_render(width, height, margin, samples, seed):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False  # the noise is wanted: it is what a sensor adds
    # Adaptive sampling stops early on the flat screen, where most of the frame is.
    scene.cycles.use_adaptive_sampling = True
    scene.cycles.adaptive_threshold = 0.05
    scene.cycles.seed = seed
    # One indirect bounce: the shadow side still gets light from the screen and the cloth.
    scene.cycles.max_bounces = 2
    scene.cycles.diffuse_bounces = 1
    scene.cycles.glossy_bounces = 1
    scene.cycles.transmission_bounces = 0
    scene.cycles.transparent_max_bounces = 0
    scene.render.resolution_x = width + 2 * margin
    scene.render.resolution_y = height + 2 * margin
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_depth = "8"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.render.film_transparent = False


# ---------------------------------------------------------------- garments in Blender


def add_cloth(ob, preset, frames, collider_thickness=0.004):
    """Cloth modifier with a knit or woven preset; pinned vertices in the 'pin' group."""
    mod = ob.modifiers.new("cloth", "CLOTH")
    s = mod.settings
    s.quality = 4
    s.mass = preset["mass"]
    s.air_damping = 2.0
    s.tension_stiffness = preset["tension"]
    s.compression_stiffness = preset["tension"]
    s.shear_stiffness = preset["shear"]
    s.bending_stiffness = preset["bending"]
    s.tension_damping = 10
    s.compression_damping = 10
    s.shear_damping = 10
    if "pin" in ob.vertex_groups:
        s.vertex_group_mass = "pin"
        s.pin_stiffness = 1.0
    c = mod.collision_settings
    c.use_collision = True
    c.distance_min = collider_thickness
    c.use_self_collision = False
    mod.point_cache.frame_start = 1
    mod.point_cache.frame_end = frames
    return mod


CLOTH_PRESETS = {
    # Jersey-like knit: light, soft, little bending resistance.
    "knit": {"mass": 0.2, "tension": 6.0, "shear": 3.0, "bending": 0.05},
    # Woven cotton/poplin to twill: stiffer in plane and in bending.
    "woven": {"mass": 0.3, "tension": 20.0, "shear": 8.0, "bending": 0.6},
}


def offset_form_top(form_v, form_f, ease_knots, voxel_cm):
    """The form's surface grown outward along its normals by an ease that varies with height,
    cleaned into one closed surface by a voxel remesh (vertices cm, triangles)."""
    n = fg.vertex_normals(form_v, form_f)
    d = np.array([gm.lerp_knots(y, ease_knots) for y in form_v[:, 1]])
    ob = mesh_object("offset", form_v + n * d[:, None], form_f, smooth=False)
    rm = ob.modifiers.new("remesh", "REMESH")
    rm.mode = "VOXEL"
    rm.voxel_size = voxel_cm * CM
    v, f = evaluated_mesh(ob)
    bpy.data.objects.remove(ob)
    return v, f


def cut_top(form, v, f, top_h, hem_h, sleeve_len, sleeve_style, clearance):
    """Cuts the offset surface into a top with bmesh bisections (clean straight edges): above
    the neckline height, the torso below the hem, each arm beyond its sleeve end. Returns
    vertices, triangles and the class of each vertex."""
    bm = bmesh.new()
    for p in v:
        bm.verts.new(tuple(p))
    bm.verts.ensure_lookup_table()
    for tri in f:
        try:
            bm.faces.new([bm.verts[i] for i in tri])
        except ValueError:
            pass
    bm.normal_update()

    def geom():
        return list(bm.verts) + list(bm.edges) + list(bm.faces)

    def bisect(elements, co, no):
        bmesh.ops.bisect_plane(bm, geom=elements, dist=1e-5, plane_co=tuple(co), plane_no=tuple(no),
                               clear_outer=True)

    bisect(geom(), (0, top_h, 0), (0, 1, 0))
    if form.torso_form:
        # Armholes: the grown surface over the form's flat armhole cap cut by the cap's own plane
        # 1 cm inward, above 1 cm below the armpit (lower, the plane runs into the torso's side
        # at the bust). The cap shows through as on a sleeveless top on a shop's form.
        for side in (1, -1):
            pl = form.armhole_planes[side]
            no = np.asarray(pl["normal"], float)
            co = np.asarray(pl["point"], float) - no * 1.0
            elems = [e for e in geom()
                     if _centre(e)[1] > form.armpit - 1.0 and _centre(e)[0] * side > 5.0]
            bisect(elems, co, no)
        bisect(geom(), (0, hem_h, 0), (0, -1, 0))
    else:
        # Sleeves: bisect each arm where it ends (sleeveless: at the armhole, 0 cm).
        for side in (1, -1):
            length = sleeve_len if sleeve_style != "none" else 0.0
            co, no = gm.sleeve_plane(form, side, length)
            bisect(_elements_of(form, geom(), clearance, gm.ARM_L if side > 0 else gm.ARM_R), co, no)
        # Torso hem.
        bisect(_elements_of(form, geom(), clearance, gm.TORSO), (0, hem_h, 0), (0, -1, 0))
    # Drop loose bits (hands below the hem that the torso cut separated, and the like): keep the
    # largest connected part.
    keep = _largest_island(bm)
    bmesh.ops.delete(bm, geom=[vv for vv in bm.verts if vv.index not in keep], context="VERTS")
    bmesh.ops.triangulate(bm, faces=bm.faces[:])
    bm.verts.ensure_lookup_table()
    bm.verts.index_update()
    out_v = np.array([vv.co[:] for vv in bm.verts])
    out_f = np.array([[vv.index for vv in fa.verts] for fa in bm.faces])
    bm.free()
    cls = (np.full(len(out_v), gm.TORSO) if form.torso_form
           else gm.arm_class(form, out_v, clearance))
    return out_v, out_f, cls


def parts_by_construction(form, cut_v, cls):
    """The truth's part of each vertex of a cut top (the starting mesh, before the cloth
    moves; the cloth keeps its vertices, so a part holds wherever it settles). Below the
    armpit the offset surfaces of torso and arm merge into one sheet (the gap between them, 3.5
    cm at the bust on the mean form, is less than the two eases and the 1.6 cm voxel), so
    neither is a separate tube: each vertex takes the part of the form vertex nearest to it,
    the part it was grown over, and the seam between bodice and sleeve runs where the sheet
    leaves the torso's side for the arm. The clearance rule (gm.arm_class) counted the
    sleeve's inner half as bodice when it hung within the waist ease + 1 cm of the torso (case
    007 of rig_physical: its bust section reached 4 cm beyond the form). Above the armpit
    the parts are cls's (the shoulder rule). The form's own arms stand apart from its torso
    below the armpit, so a form vertex is arm when it lies more than 0.5 cm beyond the torso's
    side; above the armpit, beyond the armpit's side (a vertical armhole: gm.arm_class's
    shoulder rule there classes the torso's back and front beside the armpit as arm, and cloth
    at the bodice's back corners, which starts just below the armpit, took it: case_014)."""
    from mathutils.kdtree import KDTree

    side_x = form.torso_side_x(form.v[:, 1])  # the armpit's sides above it
    form_cls = np.full(len(form.v), gm.TORSO)
    form_cls[form.v[:, 0] > side_x[:, 1] + 0.5] = gm.ARM_L
    form_cls[-form.v[:, 0] > -side_x[:, 0] + 0.5] = gm.ARM_R
    tree = KDTree(len(form.v))
    for i, p in enumerate(form.v):
        tree.insert(tuple(p), i)
    tree.balance()
    out = cls.copy()
    for i in np.nonzero(cut_v[:, 1] < form.armpit)[0]:
        out[i] = form_cls[tree.find(tuple(cut_v[i]))[1]]
    return out


def _centre(e):
    if isinstance(e, bmesh.types.BMVert):
        return np.array(e.co[:])
    return np.mean([np.array(x.co[:]) for x in e.verts], axis=0)


def _elements_of(form, elems, clearance, cls):
    """The mesh elements whose centre belongs to part `cls` (gm.arm_class)."""
    cents = np.array([_centre(e) for e in elems])
    c = gm.arm_class(form, cents, clearance)
    return [e for e, k in zip(elems, c) if k == cls]


def _largest_island(bm):
    bm.verts.ensure_lookup_table()
    bm.verts.index_update()
    seen = set()
    best = set()
    for start in bm.verts:
        if start.index in seen:
            continue
        comp = {start.index}
        stack = [start]
        while stack:
            x = stack.pop()
            for ed in x.link_edges:
                o = ed.other_vert(x)
                if o.index not in comp:
                    comp.add(o.index)
                    stack.append(o)
        seen |= comp
        if len(comp) > len(best):
            best = comp
    return best


def settle_alone(v, f, preset, frames):
    """Vertices (cm) of a cloth piece settled alone on the scene's collider for `frames` frames
    (no pins: it rests where the form holds it up)."""
    ob = mesh_object("settle", v, f)
    add_cloth(ob, preset, frames)
    scene = bpy.context.scene
    for fr in range(1, frames + 1):
        scene.frame_set(fr)
    out, _ = evaluated_mesh(ob)
    bpy.data.objects.remove(ob)
    scene.frame_set(1)
    if len(out) != len(v):
        raise RuntimeError("cloth changed the bodice's vertex count")
    return out


def make_garment(form, kind, style, rng, settle_frames=0, hem_cut=("level", 0.0)):
    """The garment's starting mesh (cm): a Piece plus a description for truth.json.

    With `settle_frames`, a dress's bodice is first settled alone and the skirt's waist seam
    placed on the settled bodice; the piece then carries `start`, the positions the cloth starts
    from (the bodice as settled), while `v` stays the cut bodice, its rest shape. Without it
    (`--hoop`, rigs made before h/dress15) the waistband is pinned outside the bodice as cut."""
    piece = gm.Piece()
    desc = {"kind": kind, "style": dict(style)}
    fabric = "knit" if (kind == "top" and rng.random() < 0.5) else ("knit" if rng.random() < 0.2 else "woven")
    desc["cloth"] = fabric
    if kind in ("top", "dress"):
        knit = fabric == "knit"
        e_b = rng.uniform(0.5, 1.0) if knit else rng.uniform(1.0, 2.2)
        e_w = e_b + (rng.uniform(0.0, 0.6) if knit else rng.uniform(0.8, 2.5))
        knots = [(form.neck_side + 5, 0.5), (form.armpit, e_b), (form.bust, e_b), (form.waist, e_w),
                 (form.hip, e_w + 0.3), (form.crotch - 10, e_w + 0.3)]
        v, f = offset_form_top(form.v, form.body_f, knots, voxel_cm=1.6)
        s = style["sleeve"]
        lengths = {"none": 0.0, "cap": rng.uniform(6, 9), "short": rng.uniform(14, 24),
                   "three_quarter": rng.uniform(38, 46)}
        if form.torso_form:
            if s != "none":
                raise ValueError("a torso form has no arms to hang a sleeve on")
        else:
            arm_len = min(form.arms[1]["length"], form.arms[-1]["length"])
            lengths["long"] = min(rng.uniform(54, 60), arm_len - 8)
        sleeve = lengths[s]
        if kind == "top":
            # Above the crotch: lower, the offset surface would follow each leg like shorts.
            # (A torso form ends 1.5 cm above the body's crotch: the same range holds.)
            hem = rng.uniform(max(form.crotch, getattr(form, "bottom", 0.0)) + 2.0, form.hip + 10.0)
        else:
            hem = form.waist - 5.0  # the bodice ends under the skirt's waist seam
            if settle_frames:
                # The bodice ends at the seam, the lower of the skirt's two pinned waistband
                # rings (gm.build_skirt: waist + 2 and 1.5 cm below), and is held there (below).
                # Lower, its loose edge hung outside the skirt once settled (no self-collision
                # between the two). Only the torso is cut there: sleeves keep their own ends.
                hem = form.waist + 0.5
        tv, tf, tcls = cut_top(form, v, f, form.neck_side, hem, sleeve, s, clearance=e_w + 1.0)
        piece.add(tv, tf, 0, np.zeros(len(tv), bool))
        piece.cls[:] = tcls
        desc.update({"ease_offset_cm": {"bust": e_b, "waist": e_w}, "sleeve_cut_cm": sleeve,
                     "hem_cut_cm": hem})
        if kind == "dress":
            sk = style["skirt"]
            length = rng.uniform(50, 75) if sk != "a_line" else rng.uniform(50, 65)
            sp, sdesc = gm.build_skirt(form, rng, sk, length, *hem_cut)
            # The skirt hangs from the waist seam, outside the bodice there (not the sleeves,
            # which hang beside it at the same height).
            bodice = tv
            if settle_frames:
                # The seam is where the bodice hangs, not where it was cut: the cut bodice
                # stands 2-4 cm off the form at the waist (the waist ease) and falls in to the
                # form from the bust as it settles. A waistband pinned outside the cut bodice
                # stayed there as a stiff hoop over the fallen bodice (cases 7 and 10 of the
                # torso rig, seed 2015, read as a skirt under a roll; the full form's dresses
                # alike, h/dress15). No rng draws here, so every case keeps its plan.
                bodice = settle_alone(tv, tf, CLOTH_PRESETS[fabric], settle_frames)
            sp.v = _push_outside(sp.v, bodice[tcls == gm.TORSO], margin=0.6)
            if bodice is not tv:
                sp.v = _taper_from_seam(form, sp.v)
            piece.add(sp.v, sp.f, gm.SKIRT, sp.pin)
            if bodice is not tv:
                piece.start = piece.v.copy()
                piece.start[:len(tv)] = bodice
                # The seam allowance (the cut bodice's lowest 1.5 cm, inside the pinned
                # waistband) is held where the bodice settled, as the waistband is: the two
                # are sewn. (By the cut heights: the cut can leave a loose vertex, no face,
                # that falls.) The torso's only: a long sleeve hangs below the seam's height
                # beside it and is not sewn to it.
                piece.pin[:len(tv)] = (tv[:, 1] < hem + 1.5) & (tcls == gm.TORSO)
            desc.update({"skirt_start": sdesc})
    elif kind == "skirt":
        length = rng.uniform(45, 72)
        sp, sdesc = gm.build_skirt(form, rng, style["skirt"], length, *hem_cut)
        piece = sp
        desc.update(sdesc)
    elif kind == "pants":
        outseam = rng.uniform(70, 100) if style["leg"] != "slim" else rng.uniform(60, 90)
        outseam = min(outseam, form.waist - 3.0)
        piece, pdesc = gm.build_pants(form, rng, style["leg"], outseam)
        desc.update(pdesc)
    return piece, desc


def _taper_from_seam(form, skirt_v, n=96):
    """A dress's skirt cut to its seam: between the waist seam (the lower pinned ring, sewn to
    the bodice and as wide as it) and the hip, each ring at least as wide as the seam's ring
    blended linearly into its own (the skirt's ease over the form) at the hip. Without it the
    skirt stepped in from the bodice's width to the form's just under the seam, a tuck no
    dress has. Rings share the hip section's centre and their points its angles
    (gm.skirt_rings), so point i of every ring lies on one ray."""
    rings = skirt_v.reshape(-1, n, 3).copy()
    c = form.torso_hull(form.hip).mean(0)
    seam = rings[1]
    hs = float(seam[0, 1])
    r_seam = np.hypot(seam[:, 0] - c[0], seam[:, 2] - c[1])
    for k in range(2, len(rings)):
        h = float(rings[k, 0, 1])
        if h <= form.hip:
            break
        t = (hs - h) / (hs - form.hip)
        r = np.hypot(rings[k, :, 0] - c[0], rings[k, :, 2] - c[1])
        scale = np.maximum((1 - t) * r_seam + t * r, r) / np.maximum(r, 1e-9)
        rings[k, :, 0] = c[0] + (rings[k, :, 0] - c[0]) * scale
        rings[k, :, 2] = c[1] + (rings[k, :, 2] - c[1]) * scale
    return rings.reshape(-1, 3)


def _push_outside(ring_v, inner_v, margin):
    """Moves skirt vertices at the bodice's heights radially outward so they clear it."""
    out = ring_v.copy()
    for h in np.unique(np.round(out[:, 1], 3)):
        sel = np.abs(out[:, 1] - h) < 1e-3
        band = inner_v[np.abs(inner_v[:, 1] - h) < 1.0]
        if len(band) < 3:
            continue
        c = out[sel][:, [0, 2]].mean(0)
        ang_b = np.arctan2(band[:, 2] - c[1], band[:, 0] - c[0])
        r_b = np.hypot(band[:, 2] - c[1], band[:, 0] - c[0])
        pts = out[sel]
        ang = np.arctan2(pts[:, 2] - c[1], pts[:, 0] - c[0])
        r = np.hypot(pts[:, 2] - c[1], pts[:, 0] - c[0])
        need = np.zeros_like(r)
        for i, a in enumerate(ang):
            near = np.abs(np.angle(np.exp(1j * (ang_b - a)))) < 0.08
            if near.any():
                need[i] = r_b[near].max() + margin
        scale = np.maximum(r, need) / np.maximum(r, 1e-9)
        pts[:, 0] = c[0] + (pts[:, 0] - c[0]) * scale
        pts[:, 2] = c[1] + (pts[:, 2] - c[1]) * scale
        out[sel] = pts
    return out


# ---------------------------------------------------------------- truth on the settled cloth


def section_hull_perimeter(v, f, h, mask):
    """Convex-hull perimeter (cm) of the cloth's section at h over triangles whose three
    vertices are in `mask`; 0 when the plane misses them."""
    ff = f[mask[f].all(1)]
    seg = fg.section_segments(v, ff, h)
    if len(seg) < 2:
        return 0.0
    return fg.perimeter(fg.hull2d(seg.reshape(-1, 3)[:, [0, 2]]))


def boundary_vertices(f, nverts):
    """Vertices on the mesh's open edges (edges used by one triangle)."""
    e = np.sort(np.vstack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), 1)
    key = e[:, 0] * nverts + e[:, 1]
    uniq, counts = np.unique(key, return_counts=True)
    b = uniq[counts == 1]
    return np.unique(np.concatenate([b // nverts, b % nverts]))


def hem_height(v, f, mask, half_width):
    """The hem's height at centre front: median height of the open-edge vertices of the lowest
    edge loop that lie in front (z above the part's centre) within `half_width` of x = 0."""
    bv = boundary_vertices(f[mask[f].all(1)], len(v))
    bv = bv[mask[bv]]
    pts = v[bv]
    low = pts[pts[:, 1] < pts[:, 1].min() + 25]
    zc = v[mask, 2].mean()
    front = low[(np.abs(low[:, 0]) < half_width) & (low[:, 2] > zc)]
    if len(front) < 3:
        front = low
    return float(np.median(front[:, 1]))


def sleeve_length(form, v, cls, side):
    """Along the arm's front-view axis from the shoulder tip to the farthest sleeve vertex on
    the outer half of the arm (away from the body)."""
    a = form.arms[side]
    d, tip, c = a["axis_dir"], a["shoulder_tip"], a["axis_point"]
    sel = cls == (gm.ARM_L if side > 0 else gm.ARM_R)
    if not sel.any():
        return 0.0
    p = v[sel][:, :2]
    t = (p - tip) @ d
    # Outer side of the axis: the side of the normal pointing away from the body (and up).
    nrm = np.array([-d[1], d[0]])
    if nrm[0] * side < 0:
        nrm = -nrm
    outer = (p - c) @ nrm > 0
    if not outer.any():
        return 0.0
    return float(t[outer].max())


def measure_truth(form, kind, style, v, f, cls):
    m = {}
    all_mask = np.ones(len(v), bool)
    torso = cls == gm.TORSO
    skirt = cls == gm.SKIRT
    if kind in ("top", "dress"):
        m["bust_circ"] = section_hull_perimeter(v, f, form.bust, torso)
        m["waist_circ"] = section_hull_perimeter(v, f, form.waist, torso | skirt)
        body = torso if kind == "top" else skirt
        hem = hem_height(v, f, body, 8.0)
        m["hem_circ"] = section_hull_perimeter(v, f, hem + 1.25, body)
        m["garment_length"] = float(v[torso, 1].max() - hem)
        if style["sleeve"] == "none":
            m["sleeve_length"] = 0.0
        else:
            m["sleeve_length"] = float(np.median([sleeve_length(form, v, cls, s) for s in (1, -1)]))
        if kind == "dress":
            m["hip_circ"] = section_hull_perimeter(v, f, form.hip, torso | skirt)
            m["skirt_length"] = float(form.waist - hem)
        heights = {"top": float(v[torso, 1].max()), "hem": hem}
    elif kind == "skirt":
        hem = hem_height(v, f, all_mask, 8.0)
        m["waist_circ"] = section_hull_perimeter(v, f, form.waist, all_mask)
        m["hip_circ"] = section_hull_perimeter(v, f, form.hip, all_mask)
        m["hem_circ"] = section_hull_perimeter(v, f, hem + 1.25, all_mask)
        m["skirt_length"] = float(form.waist - hem)
        heights = {"top": float(v[:, 1].max()), "hem": hem}
    else:
        seat = cls == gm.SEAT
        m["waist_circ"] = section_hull_perimeter(v, f, form.waist, seat)
        m["hip_circ"] = section_hull_perimeter(v, f, form.hip, seat)
        hems, opens = [], []
        for c in (gm.LEG_L, gm.LEG_R):
            leg = cls == c
            bv = boundary_vertices(f[leg[f].all(1)], len(v))
            bv = bv[leg[bv]]
            yb = v[bv, 1]
            low = np.median(yb[yb < yb.min() + 6])
            hems.append(low)
            opens.append(section_hull_perimeter(v, f, low + 1.25, leg))
        hem = float(np.mean(hems))
        # Crotch: where the seat's lower edge crosses the body's centre line in front.
        sv = v[seat]
        front = sv[(np.abs(sv[:, 0]) < 2.0) & (sv[:, 2] > v[seat, 2].mean())]
        crotch = float(front[:, 1].min())
        m["outseam"] = float(form.waist - hem)
        m["inseam"] = crotch - hem
        m["leg_opening_circ"] = float(np.mean(opens))
        heights = {"top": float(v[seat, 1].max()), "hem": hem, "crotch": crotch}
    return {k: round(float(x), 2) for k, x in m.items()}, heights


# ---------------------------------------------------------------- lens and output


def distort(img, cam, k1, k2, margin):
    """Applies radial distortion (OpenCV's k1, k2) to a frame rendered through the ideal pinhole
    with `margin` px of extra border: each output pixel samples the ideal image at its
    undistorted position (fixed-point inversion), bilinearly."""
    h, w = img.shape[0] - 2 * margin, img.shape[1] - 2 * margin
    ys, xs = np.mgrid[0:h, 0:w].astype(np.float64)
    xd = (xs - cam["cx"]) / cam["fx"]
    yd = (ys - cam["cy"]) / cam["fy"]
    xu, yu = xd.copy(), yd.copy()
    for _ in range(8):
        r2 = xu * xu + yu * yu
        s = 1 + k1 * r2 + k2 * r2 * r2
        xu, yu = xd / s, yd / s
    u = xu * cam["fx"] + cam["cx"] + margin
    v = yu * cam["fy"] + cam["cy"] + margin
    u = np.clip(u, 0, img.shape[1] - 1.001)
    v = np.clip(v, 0, img.shape[0] - 1.001)
    u0, v0 = np.floor(u).astype(int), np.floor(v).astype(int)
    a, b = (u - u0)[..., None], (v - v0)[..., None]
    out = (img[v0, u0] * (1 - a) * (1 - b) + img[v0, u0 + 1] * a * (1 - b) +
           img[v0 + 1, u0] * (1 - a) * b + img[v0 + 1, u0 + 1] * a * b)
    return out


def render_frame(path_jpg, cam, k1, k2, margin, quality, tmpdir):
    scene = bpy.context.scene
    tmp = os.path.join(tmpdir, "render.png")
    scene.render.filepath = tmp
    bpy.ops.render.render(write_still=True)
    im = bpy.data.images.load(tmp)
    W, H = im.size
    px = np.empty(W * H * 4, np.float32)
    im.pixels.foreach_get(px)
    bpy.data.images.remove(im)
    img = px.reshape(H, W, 4)[::-1, :, :3].astype(np.float64)  # top row first
    out = distort(img, cam, k1, k2, margin)
    h, w = out.shape[:2]
    rgba = np.ones((h, w, 4), np.float32)
    rgba[..., :3] = np.clip(np.round(out * 255) / 255, 0, 1)[::-1]
    o = bpy.data.images.new("out", w, h, alpha=False)
    o.pixels.foreach_set(rgba.ravel())
    o.filepath_raw = path_jpg
    o.file_format = "JPEG"
    o.save(quality=quality)
    bpy.data.images.remove(o)


def camera_json(cam, k1, k2, width, height):
    """The camera model in calib's camera.json format (docs/formats.md): known exactly from the
    renderer, so no board and no reprojection error."""
    return {"image_size": [width, height],
            "camera_matrix": [[cam["fx"], 0, cam["cx"]], [0, cam["fy"], cam["cy"]], [0, 0, 1]],
            "distortion": [k1, k2, 0.0, 0.0, 0.0], "rms_px": 0.0, "views": 0,
            "board": {"inner_corners": [0, 0], "square_mm": 0.0}}


# ---------------------------------------------------------------- one case


def make_case(args, form, sidecar_path, index, out_dir):
    """One case. Cases of one session (--session-size of them in a row) share the station:
    camera, lens, lights, screen and form cover, and so one bare-form frame, as a real station
    keeps its pose for garment after garment."""
    t0 = time.time()
    session = index // args.session_size
    srng = np.random.default_rng([args.seed, 1_000_000 + session])
    rng = np.random.default_rng([args.seed, index])
    plan = TORSO_PLAN if form.torso_form else PLAN
    kind, style = plan[index % len(plan)]
    fabric_kind = FABRICS[(index * 5 + index // len(plan)) % len(FABRICS)]
    clear_scene()
    scene = bpy.context.scene
    form_rgb = tuple(srng.choice([(0.86, 0.78, 0.66), (0.93, 0.91, 0.87), (0.80, 0.72, 0.62), (0.20, 0.20, 0.21)])
                     if srng.random() < 0.35 else (0.88, 0.80, 0.68))
    form_mat, _ = principled("form", srgb_to_linear(form_rgb), rough=0.9, sheen=0.3)
    form_ob = mesh_object("form", form.v, form.f)
    form_ob.data.materials.append(form_mat)
    # The collider: a decimated copy (the solver's cost grows with its triangles), not rendered.
    col = mesh_object("collider", form.v, form.f, smooth=False)
    dec = col.modifiers.new("decimate", "DECIMATE")
    dec.ratio = 0.15
    cv, cf = evaluated_mesh(col)
    bpy.data.objects.remove(col)
    col = mesh_object("collider", cv, cf, smooth=False)
    col.hide_render = True
    col.modifiers.new("collision", "COLLISION")
    col.collision.thickness_outer = 0.003
    col.collision.cloth_friction = 8.0
    studio = build_studio(srng, form_rgb)
    margin = 32
    # A torso form is 145 cm tall: the frame spans it and its foot as a station would frame it.
    cam = build_camera(srng, args.width, args.height, margin,
                       (160, 172) if form.torso_form else (192, 206), form.height)
    configure_render(args.width, args.height, margin, args.samples, 0)
    k1 = float(srng.uniform(-0.10, -0.02))
    k2 = float(srng.uniform(0.0, 0.04))
    empty_seed = int(srng.integers(1 << 30))

    hem = ("level", 0.0)
    if args.hem_shape != "level" and kind in ("skirt", "dress"):
        # Its own stream: the case's other draws stay as they are without the option.
        drop = float(np.random.default_rng([args.seed, index, 7]).uniform(8.0, 18.0))
        hem = (args.hem_shape, drop)
    piece, desc = make_garment(form, kind, style, rng, 0 if args.hoop else args.frames, hem)
    if (kind in ("top", "dress") and style["sleeve"] != "none" and not form.torso_form
            and not args.clearance_parts):
        # A sleeveless cut has no sleeve part: its parts stay as the cut classed them, and
        # every truth made before holds for it.
        top = piece.cls != gm.SKIRT
        piece.cls[top] = parts_by_construction(form, piece.v[top], piece.cls[top])
    g = mesh_object("garment", piece.v, piece.f)
    start = getattr(piece, "start", None)
    if start is not None:
        # The cloth starts from the settled bodice (a shape key evaluated before the cloth)
        # with its rest lengths from the cut one (the basis), so it is not stretched twice.
        g.shape_key_add(name="Basis")
        key = g.shape_key_add(name="start")
        key.data.foreach_set("co", to_blender(start).ravel())
        key.value = 1.0
    vg = g.vertex_groups.new(name="pin")
    pinned = np.where(piece.pin)[0].tolist()
    if pinned:
        vg.add(pinned, 1.0, "REPLACE")
    mat, fabric = fabric_material(fabric_kind, rng, form_rgb)
    g.data.materials.append(mat)
    preset = CLOTH_PRESETS[desc["cloth"]]
    mod = add_cloth(g, preset, args.frames)
    if start is not None:
        mod.settings.rest_shape_key = g.data.shape_keys.key_blocks["Basis"]
    scene.frame_start = 1
    scene.frame_end = args.frames
    t_sim = time.time()
    for fr in range(1, args.frames + 1):
        scene.frame_set(fr)
    sim_s = time.time() - t_sim
    v, f = evaluated_mesh(g)
    if len(v) != len(piece.v):
        raise RuntimeError("cloth changed the vertex count; cannot map parts")
    meas, heights = measure_truth(form, kind, style, v, f, piece.cls)
    settle = float(np.abs(v - piece.v).max())

    case_id = f"case_{index:03d}"
    cdir = os.path.join(out_dir, case_id)
    os.makedirs(cdir, exist_ok=True)
    t_r = time.time()
    first = os.path.join(out_dir, f"case_{session * args.session_size:03d}", "empty.jpg")
    if args.no_render:
        pass
    elif index % args.session_size != 0 and os.path.isfile(first):
        shutil.copyfile(first, os.path.join(cdir, "empty.jpg"))
    else:
        g.hide_render = True
        scene.cycles.seed = empty_seed
        render_frame(os.path.join(cdir, "empty.jpg"), cam, k1, k2, margin, args.quality, cdir)
        g.hide_render = False
    scene.cycles.seed = int(rng.integers(1 << 30))
    if not args.no_render:
        render_frame(os.path.join(cdir, "dressed.jpg"), cam, k1, k2, margin, args.quality, cdir)
        os.remove(os.path.join(cdir, "render.png"))
    render_s = time.time() - t_r

    attrs = station_attributes(kind, style)
    hard = fabric_kind in ("dark", "form", "print") or style.get("leg") == "wide"
    subtype = ",".join(f"{k}:{v}" for k, v in sorted(style.items()))
    truth = {
        "type": kind, "subtype": subtype, "attributes": attrs, "style": style, "units": "cm",
        "measurements": meas, "hard": bool(hard), "seed": int(args.seed), "index": index,
        "model": "cloth draped by Blender's cloth solver on the form (docs/physical_rig.md); "
                 "circumferences are convex-hull perimeters of the settled cloth's sections",
        "form": {"path": os.path.relpath(sidecar_path, cdir),
                 "landmark_heights_cm": {k: round(float(x), 2) for k, x in form.landmarks().items()},
                 "shoulder_tips_cm": {s: [round(float(c), 2) for c in (
                     form.shoulder_tips[k] if form.torso_form else form.arms[k]["shoulder_tip"])]
                                      for s, k in (("left", 1), ("right", -1))},
                 "torso_form": form.torso_form},
        "session": session,
        "garment_heights_cm": {k: round(float(x), 2) for k, x in heights.items()},
        "garment": desc, "fabric": fabric, "studio": studio,
        "camera": {**{k: (round(x, 4) if isinstance(x, float) else x) for k, x in cam.items()},
                   "k1": k1, "k2": k2, "file": "camera.json"},
        "render": {"engine": "cycles", "device": "CPU", "samples": args.samples,
                   "adaptive_threshold": 0.05, "max_bounces": 2, "jpeg_quality": args.quality},
        "cloth": {"preset": preset, "frames": args.frames, "settle_max_move_cm": round(settle, 2)},
        "timing_s": {"cloth": round(sim_s, 1), "render": round(render_s, 1),
                     "total": round(time.time() - t0, 1)},
    }
    truth["garment"] = json.loads(json.dumps(truth["garment"], default=float))
    with open(os.path.join(cdir, "truth.json"), "w") as fh:
        json.dump(truth, fh, indent=2, sort_keys=True, default=float)
    with open(os.path.join(cdir, "camera.json"), "w") as fh:
        json.dump(camera_json(cam, k1, k2, args.width, args.height), fh, indent=2)
    print(f"physrig: {case_id} {kind} {subtype} {fabric_kind}: cloth {sim_s:.1f} s, "
          f"render {render_s:.1f} s, {meas}", flush=True)
    return {"id": case_id, "dir": case_id, "type": kind, "attributes": attrs, "hard": bool(hard)}


def write_index(args, out_dir, sidecar_path):
    cases = []
    for name in sorted(os.listdir(out_dir)):
        tp = os.path.join(out_dir, name, "truth.json")
        if name.startswith("case_") and os.path.isfile(tp):
            with open(tp) as fh:
                t = json.load(fh)
            cases.append({"id": name, "dir": name, "type": t["type"], "attributes": t["attributes"],
                          "hard": t["hard"]})
    index = {"format": "garmcap-rig", "version": 1,
             "generator": "capture/sim/physical/make_rig.py (Blender cloth + Cycles, docs/physical_rig.md)",
             "form": os.path.relpath(sidecar_path, out_dir), "width": args.width,
             "height": args.height, "seed": args.seed, "image_format": "jpg",
             "jpeg_quality": args.quality, "cases": cases}
    with open(os.path.join(out_dir, "rig.json"), "w") as fh:
        json.dump(index, fh, indent=2, sort_keys=True)


def main():
    args = parse_args()
    os.makedirs(args.out, exist_ok=True)
    v, f, side = fg.load_form(args.form)
    form = fg.FormGeometry(v, f, side)
    print(f"physrig: form landmarks {form.landmarks()}", flush=True)
    for i in range(args.start, args.start + args.count):
        # One stream per case, so a case can be re-made alone (--start i --count 1).
        make_case(args, form, os.path.abspath(args.form), i, os.path.abspath(args.out))
        write_index(args, os.path.abspath(args.out), os.path.abspath(args.form))


if __name__ == "__main__":
    try:
        main()
    except (fg.FormError, RuntimeError, ValueError) as e:
        print(f"make_rig.py: error: {e}", file=sys.stderr)
        sys.exit(1)
