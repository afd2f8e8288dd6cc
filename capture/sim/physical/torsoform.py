"""Cuts a torso dress form on a stand from the physical rig's full body form (docs/physical_rig.md,
"Torso form"): the head off above the neck, each arm off by a plane through the armpit and the
shoulder tip, the legs off just above the crotch, every hole capped flat, then a pole and a round
foot under it. Runs in Blender (bmesh does the cuts and the caps); shares no code with calib's
`make-form --torso`.

    blender -b --python capture/sim/physical/torsoform.py -- --out DIR/NAME.obj [--form FORM.json]

Writes NAME.obj (cm, y up, floor at y = 0, facing +z), NAME.json (the station's sidecar,
docs/formats.md) and NAME.physrig.json (this generator's own data for make_rig.py: the body's
landmark heights, measured on the uncut body by formgeom.py's rules, which need arms and legs,
and the armhole planes, which tops are cut by).
"""
import argparse
import json
import os
import sys

import bmesh
import numpy as np

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import formgeom as fg  # noqa: E402
import garments as gm  # noqa: E402

NECK_CAP_CM = 4.0  # the neck cap's top above the side neck (calib's generator: 2.5 % of height)
BOTTOM_ABOVE_CROTCH_CM = 1.5  # above the crotch the body's section is one loop
POLE_RADIUS_CM = 1.25
FOOT_RADIUS_CM = 16.0
FOOT_HEIGHT_CM = 2.0


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(prog="torsoform.py", description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, help="the OBJ to write (sidecars beside it)")
    ap.add_argument("--form", default=os.path.normpath(os.path.join(
        here, "../../../../shared/data/forms/garmentcode_mean_female/form.json")))
    return ap.parse_args(argv)


def armhole_plane(form, side):
    """A point and outward normal (3-D, form coordinates) of the vertical plane through the
    armpit (the torso's side at armpit height) and the shoulder tip, in the front view."""
    xs = form.torso_side_x(np.array([form.armpit]))[0]
    a = np.array([xs[1] if side > 0 else xs[0], form.armpit])
    s = np.asarray(form.arms[side]["shoulder_tip"], float)
    d = (s - a) / np.linalg.norm(s - a)
    n = np.array([d[1], -d[0]])
    if n[0] * side < 0:
        n = -n
    return np.array([a[0], a[1], 0.0]), np.array([n[0], n[1], 0.0])


def cut_torso(form):
    bm = bmesh.new()
    for p in form.v:
        bm.verts.new(tuple(p))
    bm.verts.ensure_lookup_table()
    for tri in form.f:
        try:
            bm.faces.new([bm.verts[i] for i in tri])
        except ValueError:
            pass

    def geom():
        return list(bm.verts) + list(bm.edges) + list(bm.faces)

    def bisect(elements, co, no):
        bmesh.ops.bisect_plane(bm, geom=elements, dist=1e-5, plane_co=tuple(co),
                               plane_no=tuple(no), clear_outer=True)

    top = form.neck_side + NECK_CAP_CM
    bottom = form.crotch + BOTTOM_ABOVE_CROTCH_CM
    bisect(geom(), (0, top, 0), (0, 1, 0))
    planes = {}
    for side in (1, -1):
        co, no = armhole_plane(form, side)
        planes[side] = (co, no)
        # Only the arm and the shoulder beside it: below the armpit the plane's line runs into
        # the torso's side, which must stay.
        elems = []
        for e in geom():
            c = _centre(e)
            k = gm.arm_class(form, c[None, :], 0.5)[0]
            arm = k == (gm.ARM_L if side > 0 else gm.ARM_R)
            if arm or (c[1] > form.armpit - 1.0 and c[0] * side > 5.0):
                elems.append(e)
        bisect(elems, co, no)
    bisect(geom(), (0, bottom, 0), (0, -1, 0))
    keep = _largest_island(bm)
    bmesh.ops.delete(bm, geom=[v for v in bm.verts if v.index not in keep], context="VERTS")
    bmesh.ops.holes_fill(bm, edges=bm.edges[:], sides=0)
    bmesh.ops.triangulate(bm, faces=bm.faces[:], ngon_method="BEAUTY")
    bmesh.ops.recalc_face_normals(bm, faces=bm.faces[:])
    bm.verts.ensure_lookup_table()
    bm.verts.index_update()
    v = np.array([x.co[:] for x in bm.verts])
    f = np.array([[x.index for x in fa.verts] for fa in bm.faces])
    boundary = sum(1 for e in bm.edges if len(e.link_faces) != 2)
    bm.free()
    return v, f, top, bottom, planes, boundary


def _centre(e):
    if isinstance(e, bmesh.types.BMVert):
        return np.array(e.co[:])
    return np.mean([np.array(x.co[:]) for x in e.verts], axis=0)


def _largest_island(bm):
    bm.verts.ensure_lookup_table()
    bm.verts.index_update()
    seen, best = set(), set()
    for start in bm.verts:
        if start.index in seen:
            continue
        comp, stack = {start.index}, [start]
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


def cylinder(cx, cz, r, y0, y1, n=32):
    """A closed cylinder (vertices, triangles) with flat caps."""
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.column_stack([cx + r * np.cos(a), cz + r * np.sin(a)])
    v = np.vstack([np.column_stack([ring[:, 0], np.full(n, y), ring[:, 1]]) for y in (y0, y1)]
                  + [[[cx, y0, cz]], [[cx, y1, cz]]])
    f = []
    for i in range(n):
        j = (i + 1) % n
        f += [[i, j, n + j], [i, n + j, n + i], [2 * n, j, i], [2 * n + 1, n + i, n + j]]
    return v, np.asarray(f)


def write_obj(path, parts, header):
    with open(path, "w") as fh:
        fh.write(f"# {header}\n")
        base = 0
        for v, f in parts:
            for p in v:
                fh.write(f"v {p[0]:.4f} {p[1]:.4f} {p[2]:.4f}\n")
            for t in f:
                fh.write(f"f {t[0] + base + 1} {t[1] + base + 1} {t[2] + base + 1}\n")
            base += len(v)


def main():
    a = parse_args()
    v, f, side = fg.load_form(a.form)
    form = fg.FormGeometry(v, f, side)
    tv, tf, top, bottom, planes, boundary = cut_torso(form)
    if boundary:
        raise fg.FormError(f"the cut torso has {boundary} open edges after capping")
    # The stand stands under the centre of the torso's bottom; its pole stops 0.2 mm short of
    # the bottom cap so the torso stays one closed surface of its own.
    hull = fg.hull2d(tv[tv[:, 1] < bottom + 0.01][:, [0, 2]])
    cx, cz = hull.mean(0)
    pole = cylinder(cx, cz, POLE_RADIUS_CM, FOOT_HEIGHT_CM, bottom - 0.02)
    foot = cylinder(cx, cz, FOOT_RADIUS_CM, 0.0, FOOT_HEIGHT_CM, 64)
    out = os.path.abspath(a.out)
    stem = os.path.splitext(out)[0]
    name = os.path.basename(stem)
    write_obj(out, [(tv, tf), pole, foot],
              f"torso dress form cut from {os.path.basename(side['mesh'])} by "
              f"capture/sim/physical/torsoform.py; cm, y up, floor at y = 0, facing +z")
    lm = form.landmarks()
    meas = {k: side["measurements"][k] for k in ("bust_circ", "waist_circ", "hip_circ")
            if k in side["measurements"]}
    meas["height"] = round(float(top), 2)
    sidecar = {
        "mesh": os.path.basename(out), "mesh_units": "cm", "units": "cm",
        "name": f"{side.get('name', 'garmentcode mean female')} torso form (physical rig)",
        "orientation": "y up, floor at y = 0, facing +z; torso dress form (neck cap, no head, "
                       "arms or legs) on a pole and a round foot",
        "source": "capture/sim/physical/torsoform.py: the bundled garmentcode_mean_female body "
                  "cut at the neck, the shoulders and above the crotch, holes capped; "
                  "measurements are the body's (its yaml), height is the form's own",
        "measurements": meas,
        # Heights on the body the torso was cut from, by formgeom.py's rules (the torso sits
        # where the body's torso was, so they hold for it).
        "landmark_heights": {k: round(float(lm[k]), 2) for k in ("bust", "waist", "hip")},
    }
    with open(stem + ".json", "w") as fh:
        json.dump(sidecar, fh, indent=2, sort_keys=True)
        fh.write("\n")
    phys = {
        "torso_form": True,
        "body_landmark_heights_cm": {k: round(float(x), 2) for k, x in lm.items()},
        "bottom_cm": round(float(bottom), 2), "neck_cap_cm": round(float(top), 2),
        "armhole_planes": {("left" if s > 0 else "right"): {
            "point": [round(float(c), 3) for c in planes[s][0]],
            "normal": [round(float(c), 5) for c in planes[s][1]]} for s in (1, -1)},
        "shoulder_tips_cm": {("left" if s > 0 else "right"):
                             [round(float(c), 2) for c in form.arms[s]["shoulder_tip"]]
                             for s in (1, -1)},
        "stand": {"pole_radius_cm": POLE_RADIUS_CM, "foot_radius_cm": FOOT_RADIUS_CM,
                  "foot_height_cm": FOOT_HEIGHT_CM, "centre_xz_cm": [round(float(cx), 3),
                                                                      round(float(cz), 3)]},
    }
    with open(stem + ".physrig.json", "w") as fh:
        json.dump(phys, fh, indent=2, sort_keys=True)
        fh.write("\n")
    print(f"torsoform: {out}: {len(tv)} vertices, {len(tf)} triangles, bottom {bottom:.2f}, "
          f"neck cap {top:.2f} cm; landmarks {lm}", flush=True)


if __name__ == "__main__":
    try:
        main()
    except (fg.FormError, RuntimeError, ValueError) as e:
        print(f"torsoform.py: error: {e}", file=sys.stderr)
        sys.exit(1)
