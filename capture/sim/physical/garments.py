"""Garment cloth meshes built around a form (numpy only, cm, form coordinates).

Every builder returns a Piece: vertices, triangles, a class per vertex (which part of the
garment it belongs to, so that truth can be measured on the right part), and the pinned
vertices (a waistband or a seam the cloth hangs from). The meshes start off the form (outside
its convex sections or its surface offset outward) and are then settled by Blender's cloth
solver; the truth is measured on the settled result, never on these starting shapes.
"""
import math

import numpy as np

import formgeom as fg

TORSO, SKIRT, SEAT, LEG_L, LEG_R, ARM_L, ARM_R = range(7)
CLASS_NAMES = ["torso", "skirt", "seat", "leg_left", "leg_right", "arm_left", "arm_right"]


class Piece:
    def __init__(self):
        self.v = np.zeros((0, 3))
        self.f = np.zeros((0, 3), np.int64)
        self.cls = np.zeros(0, np.int64)
        self.pin = np.zeros(0, bool)

    def add(self, v, f, cls, pin):
        base = len(self.v)
        self.v = np.vstack([self.v, v])
        self.f = np.vstack([self.f, np.asarray(f, np.int64) + base])
        self.cls = np.concatenate([self.cls, np.full(len(v), cls)])
        self.pin = np.concatenate([self.pin, pin])


def tube(rings, heights):
    """A tube through closed rings (list of n x 2 arrays of x, z, all of the same n) at the
    given heights (top first): vertices and triangles."""
    n = len(rings[0])
    v = np.vstack([np.column_stack([r[:, 0], np.full(n, h), r[:, 1]]) for r, h in zip(rings, heights)])
    f = []
    for k in range(len(rings) - 1):
        a, b = k * n, (k + 1) * n
        for i in range(n):
            j = (i + 1) % n
            f.append([a + i, b + i, b + j])
            f.append([a + i, b + j, a + j])
    return v, np.asarray(f)


def lerp_knots(h, knots):
    """Piecewise-linear value at h between (height, value) knots, constant outside."""
    hs = [k[0] for k in knots]
    vs = [k[1] for k in knots]
    order = np.argsort(hs)
    return float(np.interp(h, np.asarray(hs)[order], np.asarray(vs)[order]))


def skirt_rings(form, top, hem, ease_waist, ease_hip, hem_factor, n=96, step=1.5):
    """Rings of a skirt from `top` to `hem`: the form's torso section grown by the ease down to
    the hip, then the hip ring widened linearly to `hem_factor` x its circumference at the hem.
    """
    hip_hull = form.torso_hull(form.hip)
    centre = hip_hull.mean(0)
    hip_ring = fg.offset_ring(hip_hull, ease_hip / (2 * math.pi), n, centre)
    heights = list(np.arange(top, hem, -step)) + [hem]
    rings = []
    for h in heights:
        if h >= form.hip:
            t = (h - form.hip) / max(form.waist - form.hip, 1.0)
            ease = ease_hip + (ease_waist - ease_hip) * min(max(t, 0.0), 1.0)
            hull = form.torso_hull(h)
            ring = fg.offset_ring(hull, ease / (2 * math.pi), n, centre)
            # Never inside the straight drop from the hip: a skirt does not follow the waist in.
            rings.append(ring)
        else:
            t = (form.hip - h) / max(form.hip - hem, 1.0)
            s = 1.0 + (hem_factor - 1.0) * t
            rings.append(centre + (hip_ring - centre) * s)
    return rings, heights


def hem_drop(shape, drop, x, z):
    """How far below the level hem (cm, >= 0) a non-level hem hangs at the direction (x, z) from
    the skirt's centre (+z the front): a high-low hem's back `drop` longer than its front, rising
    to the front past the sides; an asymmetric hem's one side (+x) `drop` longer than the other,
    the centre front half way."""
    phi = np.arctan2(x, z)  # 0 at the centre front, +pi/2 at +x
    if shape == "high_low":
        return drop * (1.0 - np.cos(phi)) / 2.0
    if shape == "asymmetric":
        return drop * (1.0 + np.sin(phi)) / 2.0
    return np.zeros_like(phi)


def build_skirt(form, rng, style, length_below_waist, hem_shape="level", drop=0.0):
    """A skirt from 2 cm above the waist to its hem. A non-level hem (`hem_shape` high_low or
    asymmetric, `drop` cm; see hem_drop) lengthens each column of the tube below the hip by its
    own share, so the cloth is cut on that curve; the level hem is at `length_below_waist`."""
    top = form.waist + 2.0
    hem = form.waist - length_below_waist
    factor = {"h_line": rng.uniform(1.0, 1.04), "mid_flare": rng.uniform(1.15, 1.35),
              "a_line": rng.uniform(1.5, 1.9)}[style]
    rings, heights = skirt_rings(form, top, hem, rng.uniform(1.0, 3.0), rng.uniform(3.0, 7.0), factor)
    v, f = tube(rings, heights)
    if hem_shape != "level" and drop > 0:
        centre = form.torso_hull(form.hip).mean(0)
        low = v[:, 1] < form.hip
        extra = hem_drop(hem_shape, drop, v[low, 0] - centre[0], v[low, 2] - centre[1])
        v[low, 1] = form.hip - (form.hip - v[low, 1]) * (form.hip - hem + extra) / (form.hip - hem)
    p = Piece()
    pin = v[:, 1] >= top - 1.6  # the waistband: two rings
    p.add(v, f, SKIRT, pin)
    desc = {"top": top, "hem_start": hem, "hem_factor": factor}
    if hem_shape != "level":
        desc.update({"hem_shape": hem_shape, "hem_drop_cm": drop})
    return p, desc


def leg_rings(form, side, top, hem, thigh_ease, opening_circ, n=64, step=1.5):
    """Rings of one trouser leg: the form's leg section grown by `thigh_ease` at the top,
    narrowing or widening linearly to a leg opening of `opening_circ`; never inside the leg
    (1 cm clearance) and never across the body's centre plane (the other leg is there)."""
    heights = list(np.arange(top, hem, -step)) + [hem]
    top_hull = leg_hull(form, side, top)
    top_centre = top_hull.mean(0)
    top_ring = fg.offset_ring(top_hull, thigh_ease / (2 * math.pi), n, top_centre)
    top_circ = fg.perimeter(top_ring)
    rings = []
    for h in heights:
        t = (top - h) / max(top - hem, 1.0)
        hull = leg_hull(form, side, h)
        centre = hull.mean(0) if hull is not None else top_centre
        want = top_circ + (opening_circ - top_circ) * t
        ring = top_centre + (top_ring - top_centre) * (want / top_circ)
        ring = ring - top_centre + centre
        if hull is not None:
            clear = fg.offset_ring(hull, 1.0, n, centre)
            r_want = np.linalg.norm(ring - centre, axis=1)
            r_clear = np.linalg.norm(clear - centre, axis=1)
            ring = centre + (ring - centre) * (np.maximum(r_want, r_clear) / np.maximum(r_want, 1e-9))[:, None]
        ring[:, 0] = side * np.maximum(side * ring[:, 0], 0.4)
        rings.append(ring)
    return rings, heights


def leg_hull(form, side, h):
    """Convex hull (x, z) of one leg's section at h: the section loop on that side of x = 0."""
    best = None
    for loop in fg.section_loops(form.v, form.f, h):
        cx = loop[:, 0].mean()
        if cx * side > 3.0 and abs(cx) < 30 and (best is None or len(loop) > len(best)):
            best = loop
    return None if best is None else fg.hull2d(best[:, [0, 2]])


def build_pants(form, rng, style, outseam):
    top = form.waist + 2.0
    hem = form.waist - outseam
    crotch = form.crotch - rng.uniform(1.0, 3.0)
    seat_rings, seat_h = skirt_rings(form, top, crotch, rng.uniform(1.0, 3.0), rng.uniform(3.0, 6.0), 1.0)
    p = Piece()
    v, f = tube(seat_rings, seat_h)
    p.add(v, f, SEAT, v[:, 1] >= top - 1.6)
    # Under the seat's lower edge (the crotch seam), where the form's legs have parted.
    leg_top = min(crotch + 1.0, form.crotch - 0.5)
    thigh = leg_hull(form, 1, leg_top)
    thigh_circ = fg.perimeter(thigh)
    opening = {"straight": rng.uniform(0.75, 0.85), "wide": rng.uniform(1.25, 1.5),
               "slim": rng.uniform(0.55, 0.62)}[style] * thigh_circ
    thigh_ease = rng.uniform(4.0, 8.0) if style != "wide" else rng.uniform(10.0, 14.0)
    for side, cls in ((1, LEG_L), (-1, LEG_R)):
        rings, heights = leg_rings(form, side, leg_top, hem, thigh_ease, opening)
        v, f = tube(rings, heights)
        p.add(v, f, cls, v[:, 1] >= leg_top - 0.1)
    return p, {"top": top, "hem_start": hem, "crotch_start": crotch, "opening_start": opening}


def arm_class(form, pts, clearance=2.5):
    """ARM_L / ARM_R for points of a top that lie on an arm, else TORSO. Below the armpit the
    arms hang apart from the torso: a point is on an arm when it lies more than `clearance` cm
    beyond the torso's side there. Above it, a point is on an arm when it lies more than 2 cm
    down the arm's axis from the shoulder tip."""
    out = np.full(len(pts), TORSO)
    side_x = form.torso_side_x(pts[:, 1])
    for side, cls in ((1, ARM_L), (-1, ARM_R)):
        a = form.arms[side]
        d, tip = a["axis_dir"], a["shoulder_tip"]
        t = (pts[:, :2] - tip) @ d
        low = pts[:, 1] < form.armpit
        beyond = side * pts[:, 0] > np.where(side > 0, side_x[:, 1], -side_x[:, 0]) + clearance
        arm = np.where(low, beyond, (t > 2.0) & (side * pts[:, 0] > 8.0))
        out[arm & (side * pts[:, 0] > 0)] = cls
    return out


def build_top(form, rng, sleeve_len, hem, ease):
    """A top that follows the form: the form's surface grown outward by the ease (a closed,
    clean surface from a voxel remesh in Blender), cut at the neck, the hem and the sleeve
    ends. Returns the offset form mesh and the cutting plan; the cut happens in Blender."""
    return {"ease": ease, "hem": hem, "top": form.neck_side, "sleeve": sleeve_len}


def sleeve_plane(form, side, length):
    """A point and normal (form coordinates, 3-D) of the plane that ends a sleeve `length` cm
    down the arm from the shoulder tip; the normal points towards the hand."""
    a = form.arms[side]
    d = a["axis_dir"]
    tip = a["shoulder_tip"]
    p = tip + d * length
    return np.array([p[0], p[1], 0.0]), np.array([d[0], d[1], 0.0])
