"""Geometry of a dress form and of settled cloth, in numpy only (cm, form coordinates).

Form coordinates are the sidecar's: y up, feet at y = 0, facing +z (towards the camera).
Nothing here comes from the station's code: sections are cut from the triangles directly, and
the landmarks are found by this module's own rules (see docs/physical_rig.md).
"""
import json
import math
import os

import numpy as np

UNIT_TO_CM = {"mm": 0.1, "cm": 1.0, "m": 100.0, "in": 2.54}


class FormError(Exception):
    pass


def read_obj(path):
    """Vertices (n x 3) and triangles (m x 3, 0-based) of an OBJ file; polygons are fanned."""
    verts, faces = [], []
    with open(path, "r", encoding="utf-8") as f:
        for lineno, line in enumerate(f, 1):
            if line.startswith("v "):
                parts = line.split()
                if len(parts) < 4:
                    raise FormError(f"{path}: line {lineno}: a vertex needs 3 coordinates")
                verts.append([float(parts[1]), float(parts[2]), float(parts[3])])
            elif line.startswith("f "):
                idx = [int(p.split("/")[0]) for p in line.split()[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append([idx[0], idx[k], idx[k + 1]])
    if not verts or not faces:
        raise FormError(f"{path}: no vertices or faces")
    v = np.asarray(verts, float)
    fa = np.asarray(faces, np.int64)
    if fa.min() < 0 or fa.max() >= len(v):
        raise FormError(f"{path}: a face refers to a vertex that does not exist")
    return v, fa


def load_form(sidecar_path):
    """The form's mesh in cm plus its sidecar (dict), feet moved to y = 0."""
    with open(sidecar_path, "r", encoding="utf-8") as f:
        side = json.load(f)
    for key in ("mesh", "mesh_units", "measurements"):
        if key not in side:
            raise FormError(f"{sidecar_path}: missing field '{key}'")
    unit = side["mesh_units"]
    if unit not in UNIT_TO_CM:
        raise FormError(f"{sidecar_path}: mesh_units '{unit}' is not one of mm, cm, m, in")
    mesh_path = os.path.join(os.path.dirname(sidecar_path), side["mesh"])
    if not mesh_path.lower().endswith(".obj"):
        raise FormError(f"{sidecar_path}: only OBJ meshes are read by the physical rig")
    v, f = read_obj(mesh_path)
    v = v * UNIT_TO_CM[unit]
    v[:, 1] -= v[:, 1].min()
    # A torso form cut by torsoform.py carries this generator's own data beside the station's
    # sidecar (which refuses fields it does not know): the uncut body's landmarks and the
    # armhole planes.
    phys = os.path.splitext(sidecar_path)[0] + ".physrig.json"
    if os.path.isfile(phys):
        with open(phys, "r", encoding="utf-8") as fh:
            side = dict(side, physrig=json.load(fh))
    return v, f, side


def _cut(verts, faces, h):
    """Triangles cut by the plane y = h: the crossing points on their two cut edges and the
    edges' keys (sorted vertex pairs), so that neighbouring segments can be chained."""
    y = verts[faces, 1] - h  # m x 3
    above = y > 0
    n_above = above.sum(1)
    cut = (n_above == 1) | (n_above == 2)
    tri = faces[cut]
    ty = y[cut]
    tv = verts[tri]
    # The lone vertex (the one on the minority side) and the other two.
    lone = np.where(n_above[cut] == 1, np.argmax(ty > 0, 1), np.argmax(ty <= 0, 1))
    rows = np.arange(len(tri))
    ends, keys = [], []
    for other in ((lone + 1) % 3, (lone + 2) % 3):
        ya, yb = ty[rows, lone], ty[rows, other]
        t = ya / (ya - yb)
        ends.append(tv[rows, lone] + t[:, None] * (tv[rows, other] - tv[rows, lone]))
        a, b = tri[rows, lone], tri[rows, other]
        keys.append(np.minimum(a, b) * (len(verts) + 1) + np.maximum(a, b))
    return np.stack(ends, 1), np.stack(keys, 1)


def section_segments(verts, faces, h):
    """Segments (k x 2 x 3) where the plane y = h cuts the triangles."""
    return _cut(verts, faces, h)[0]


def section_loops(verts, faces, h):
    """The section at y = h as connected pieces (each an array of points, x y z): segments
    that share a cut edge belong to the same closed loop."""
    seg, keys = _cut(verts, faces, h)
    if len(seg) == 0:
        return []
    uniq, inv = np.unique(keys.ravel(), return_inverse=True)
    inv = inv.reshape(-1, 2)
    parent = np.arange(len(uniq))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b in inv:
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[ra] = rb
    roots = np.array([find(i) for i in range(len(uniq))])
    seg_root = roots[inv[:, 0]]
    return [seg[seg_root == r].reshape(-1, 3) for r in np.unique(seg_root)]


def hull2d(points):
    """Convex hull (counter-clockwise) of 2-D points, Andrew's monotone chain."""
    pts = np.unique(np.round(np.asarray(points, float), 6), axis=0)
    if len(pts) < 3:
        return pts
    pts = pts[np.lexsort((pts[:, 1], pts[:, 0]))]

    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2:
                a, b = out[-2], out[-1]
                if (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) <= 0:
                    out.pop()
                else:
                    break
            out.append(p)
        return out

    lower = half(pts)
    upper = half(pts[::-1])
    return np.asarray(lower[:-1] + upper[:-1])


def perimeter(poly):
    if len(poly) < 2:
        return 0.0
    d = np.diff(np.vstack([poly, poly[:1]]), axis=0)
    return float(np.hypot(d[:, 0], d[:, 1]).sum())


def clusters_by_x(points_xz, gap=2.5):
    """Splits section points into groups separated by gaps in x wider than `gap` cm."""
    if len(points_xz) == 0:
        return []
    order = np.argsort(points_xz[:, 0])
    xs = points_xz[order, 0]
    breaks = np.where(np.diff(xs) > gap)[0]
    groups = np.split(order, breaks + 1)
    return [points_xz[g] for g in groups]


def torso_points(verts, faces, h):
    """Section points (x, z) of the torso at height h: the loop whose x range spans x = 0
    (None below the crotch, where the legs are separate loops)."""
    best = None
    for loop in section_loops(verts, faces, h):
        if loop[:, 0].min() <= 0.0 <= loop[:, 0].max():
            if best is None or len(loop) > len(best):
                best = loop
    return None if best is None else best[:, [0, 2]]


def crosses_axis(verts, faces, h):
    """True when some segment of the section at h crosses the plane x = 0 (torso not parted)."""
    seg = section_segments(verts, faces, h)
    if len(seg) == 0:
        return False
    x0, x1 = seg[:, 0, 0], seg[:, 1, 0]
    return bool(np.any((x0 <= 0) & (x1 >= 0) | (x0 >= 0) & (x1 <= 0)))


class FormGeometry:
    """Landmarks and sections of one form, by this module's rules."""

    def __init__(self, verts, faces, sidecar):
        self.v = verts
        self.f = faces
        self.height = float(verts[:, 1].max())
        given = sidecar.get("landmark_heights", {}) or {}
        phys = sidecar.get("physrig", {})
        self.torso_form = bool(phys.get("torso_form"))
        if self.torso_form:
            # No arms, no legs, no head: the crotch, armpit and side-neck rules cannot work on
            # the torso, so every landmark is the uncut body's (torsoform.py measured them with
            # the rules below). The garments are built on the torso alone, not the stand.
            given = dict(phys["body_landmark_heights_cm"])
            given["neck_base"] = given.pop("neck_side")
            self.bottom = float(phys["bottom_cm"])
            self.armhole_planes = {1: phys["armhole_planes"]["left"], -1: phys["armhole_planes"]["right"]}
            self.shoulder_tips = {1: phys["shoulder_tips_cm"]["left"], -1: phys["shoulder_tips_cm"]["right"]}
            keep = verts[faces, 1].min(1) > self.bottom - 0.01
            self.body_f = faces[keep]
        else:
            self.body_f = faces
        self.crotch = given.get("crotch") or self._find_crotch()
        self.armpit = given.get("armpit") or self._find_armpit()
        self.hip = given.get("hip") or self._extreme(self.crotch + 0.5, self.crotch + 25, np.argmax)
        self.bust = given.get("bust") or self._bust_point()
        self.waist = given.get("waist") or self._extreme(self.hip + 12, self.bust - 8, np.argmin)
        self.neck_side = given.get("neck_base") or self._find_neck_side()
        self.arms = {} if self.torso_form else {s: self._arm(s) for s in (1, -1)}

    def torso_side_x(self, ys):
        """(min x, max x) of the torso's section at each height (n x 2); below the crotch the
        hip's, above the armpit the armpit's (from a 0.5 cm table)."""
        if not hasattr(self, "_side_table"):
            hs = np.arange(self.crotch, self.armpit + 0.01, 0.5)
            xs = []
            for h in hs:
                p = torso_points(self.v, self.f, h)
                xs.append((p[:, 0].min(), p[:, 0].max()) if p is not None else (np.nan, np.nan))
            xs = np.asarray(xs)
            ok = ~np.isnan(xs[:, 0])
            self._side_table = (hs[ok], xs[ok])
        hs, xs = self._side_table
        ys = np.clip(ys, hs[0], hs[-1])
        return np.column_stack([np.interp(ys, hs, xs[:, 0]), np.interp(ys, hs, xs[:, 1])])

    def circ(self, h):
        pts = torso_points(self.v, self.f, h)
        return perimeter(hull2d(pts)) if pts is not None else 0.0

    def torso_hull(self, h):
        pts = torso_points(self.v, self.f, h)
        if pts is None:
            raise FormError(f"form has no torso section at {h:.1f} cm")
        return hull2d(pts)

    def _extreme(self, lo, hi, pick):
        hs = np.arange(lo, hi, 0.25)
        cs = np.array([self.circ(h) for h in hs])
        return float(hs[pick(cs)])

    def _bust_point(self):
        # Bust girth: the first maximum of the girth at or above the bust points (the torso's
        # front-most point), the usual "fullest part of the bust" taken on a form.
        hs = np.arange(self.armpit - 20, self.armpit - 1, 0.25)
        fronts = [torso_points(self.v, self.f, h)[:, 1].max() for h in hs]
        self.bust_point = float(hs[int(np.argmax(fronts))])
        h, c = self.bust_point, self.circ(self.bust_point)
        while h + 0.25 < self.armpit:
            c2 = self.circ(h + 0.25)
            if c2 < c:
                break
            h, c = h + 0.25, c2
        return float(h)

    def _find_crotch(self):
        # Walking down from mid-height, the first height where no section segment crosses the
        # body's centre plane: the legs have parted there.
        for h in np.arange(self.height * 0.62, self.height * 0.3, -0.1):
            if not crosses_axis(self.v, self.f, h):
                return float(h + 0.05)
        raise FormError("no crotch found (the legs never part below mid-height)")

    def _find_armpit(self):
        # Walking up from the waist region, the last height where the arms are separate groups
        # beside the torso.
        last = None
        for h in np.arange(self.height * 0.55, self.height * 0.85, 0.2):
            if len(section_loops(self.v, self.f, h)) >= 3:
                last = h
        if last is None:
            raise FormError("no armpit found (arms never separate from the torso)")
        return float(last)

    def _find_neck_side(self):
        # The neck is the narrowest section between the shoulders and the head; its side meets
        # the shoulder where the section widens past the neck's width + 25 %.
        hs = np.arange(self.armpit + 4, min(self.height - 15, self.armpit + 40), 0.25)
        widths = []
        for h in hs:
            pts = torso_points(self.v, self.f, h)
            widths.append(np.ptp(pts[:, 0]) if pts is not None else np.inf)
        widths = np.array(widths)
        i_neck = int(np.argmin(widths))
        w_neck = widths[i_neck]
        for i in range(i_neck, -1, -1):
            if widths[i] > 1.25 * w_neck:
                return float(hs[i])
        raise FormError("no side neck found")

    def _arm(self, side):
        """Front-view arm axis (2-D, x and y), the shoulder tip, and the arm's radius."""
        v = self.v
        sel = (np.sign(v[:, 0]) == side) & (v[:, 1] < self.armpit - 3) & (v[:, 1] > self.crotch - 15)
        # Arm points are those outside the torso's section half-width at their height.
        pts = v[sel]
        keep = []
        for h in np.arange(self.crotch - 15, self.armpit - 3, 1.0):
            band = pts[(pts[:, 1] >= h) & (pts[:, 1] < h + 1)]
            if len(band) == 0:
                continue
            tor = torso_points(self.v, self.f, h + 0.5)
            if tor is None:
                continue
            edge = tor[:, 0].max() if side > 0 else -tor[:, 0].min()
            keep.append(band[band[:, 0] * side > edge + 1.0])
        arm = np.vstack([k for k in keep if len(k)])
        xy = arm[:, :2]
        c = xy.mean(0)
        _, _, vt = np.linalg.svd(xy - c, full_matrices=False)
        d = vt[0]
        if d[1] > 0:
            d = -d  # pointing down the arm
        # Shoulder tip: the corner of the front outline's upper profile between the side neck
        # and the arm's upper edge at armpit height (the point farthest above their chord).
        up = v[(v[:, 0] * side > 0) & (v[:, 1] > self.armpit - 6) & (v[:, 1] < self.neck_side + 0.5)]
        xs = np.arange(0, np.abs(up[:, 0]).max(), 0.5)
        prof = []
        for x in xs:
            b = up[np.abs(np.abs(up[:, 0]) - x) < 0.25]
            if len(b):
                prof.append((x, b[:, 1].max()))
        prof = np.asarray(prof)
        neck_half = np.ptp(torso_points(self.v, self.f, self.neck_side + 1.0)[:, 0]) / 2
        a = prof[np.argmin(np.abs(prof[:, 0] - neck_half))]
        below = prof[prof[:, 1] <= self.armpit]
        below = below[below[:, 0] > a[0]]
        if len(below) == 0:
            raise FormError("cannot find the arm's upper edge at armpit height")
        b = below[0]
        mid = prof[(prof[:, 0] >= a[0]) & (prof[:, 0] <= b[0])]
        ch = (b - a) / np.linalg.norm(b - a)
        height_above = (mid[:, 0] - a[0]) * (-ch[1]) + (mid[:, 1] - a[1]) * ch[0]
        tip = mid[int(np.argmax(height_above))]
        tip = np.array([tip[0] * side, tip[1]])
        d = np.array([abs(d[0]) * side, d[1]])
        d /= np.linalg.norm(d)
        # Arm radius: distance of arm points from the axis line through their centre.
        rel = xy - c
        perp = np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0])
        length = float(((xy - tip) @ d).max())
        return {"axis_dir": d, "axis_point": c, "shoulder_tip": tip,
                "radius": float(np.percentile(perp, 95)), "length": length}

    def landmarks(self):
        return {"crotch": self.crotch, "hip": self.hip, "waist": self.waist, "bust": self.bust,
                "armpit": self.armpit, "neck_side": self.neck_side}


def vertex_normals(verts, faces):
    n = np.zeros_like(verts)
    fn = np.cross(verts[faces[:, 1]] - verts[faces[:, 0]], verts[faces[:, 2]] - verts[faces[:, 0]])
    for k in range(3):
        np.add.at(n, faces[:, k], fn)
    ln = np.linalg.norm(n, axis=1)
    ln[ln == 0] = 1
    return n / ln[:, None]


def offset_ring(hull, dist, count, centre=None):
    """`count` points of the hull grown outward by `dist` cm (Minkowski sum with a disc),
    sampled at equal angles around `centre`; ordered counter-clockwise seen from above."""
    if centre is None:
        centre = hull.mean(0)
    ang = np.linspace(0, 2 * np.pi, 48, endpoint=False)
    disc = np.stack([np.cos(ang), np.sin(ang)], 1) * max(dist, 0.0)
    grown = hull2d((hull[:, None, :] + disc[None, :, :]).reshape(-1, 2))
    return resample_polygon_by_angle(grown, centre, count)


def resample_polygon_by_angle(poly, centre, count):
    """Points where rays from `centre` at `count` equal angles leave a convex polygon."""
    out = np.zeros((count, 2))
    p = poly - centre
    q = np.roll(p, -1, axis=0)
    for i, a in enumerate(np.linspace(0, 2 * np.pi, count, endpoint=False)):
        r = np.array([math.cos(a), math.sin(a)])
        # Solve centre + t r = p + s (q - p), 0 <= s <= 1, t > 0.
        e = q - p
        den = r[0] * e[:, 1] - r[1] * e[:, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (p[:, 0] * e[:, 1] - p[:, 1] * e[:, 0]) / den
            s = (p[:, 0] * r[1] - p[:, 1] * r[0]) / den
        ok = (np.abs(den) > 1e-12) & (s >= -1e-9) & (s <= 1 + 1e-9) & (t > 0)
        out[i] = centre + r * t[ok].max()
    return out
