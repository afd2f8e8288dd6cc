#!/usr/bin/env python3
"""Nested grading and markers written by the real CLI, read back by independent readers
(Python's XML parser, ezdxf, poppler's pdfinfo/pdftotext, rsvg-convert when installed):

  nested_marker_check.py GARMCAP_BINARY OUT_DIR

Nested grading (`garmcap sizerun` over korean_women, from a skirt_a and a dress drafted at 66):
- SVG: one group per piece holding one outline per size, exactly one marked as the sample (the
  sample size of the run, drawn thicker), a legend entry per size; every size's outline is that
  size's own pattern JSON (written by sizerun) moved, not reshaped (0.02 mm), and all sizes of a
  piece share one reference point: the same top, and the same left edge, right edge (a fold) or
  middle (0.02 mm);
- DXF: audited clean by ezdxf; one layer per size holding one closed polyline per piece, each
  matching the SVG's outline; the legend names the sample;
- PDF: one page, names the sample size.
Markers (`garmcap marker` for every garment type at 66, and a size run of one type):
- the reported efficiency equals the pieces' areas (read from the SVG) over length x width,
  the length equals the pieces' extent; pieces lie on the fabric and do not overlap; the
  number of pieces is the sum of the panels' cut counts; every grain line runs along the
  fabric's length (rotation 0 or 180 only); each mirrored piece has its partner's area;
- DXF audited clean by ezdxf, one closed polyline per piece on its size's layer.
Exits 1 on any failure.
"""
import json
import math
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import ezdxf

from outline_geometry import inside

SVG = "{http://www.w3.org/2000/svg}"


def run(cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout


def points(s):
    return [tuple(float(v) for v in p.split(",")) for p in s.split()]


def area(ring):
    return abs(sum(ring[i][0] * ring[(i + 1) % len(ring)][1] - ring[(i + 1) % len(ring)][0] *
                   ring[i][1] for i in range(len(ring)))) / 2


def audit(path, problems):
    doc = ezdxf.readfile(path)
    auditor = doc.audit()
    if auditor.has_errors:
        problems.append(f"{path}: ezdxf audit errors {[str(e) for e in auditor.errors]}")
    return doc


def nested(garmcap, out, gtype, problems):
    d = out / f"nested_{gtype}"
    d.mkdir(exist_ok=True)
    pattern = d / "base.json"
    run([garmcap, "draft", "--type", gtype, "--size", "66", "--chart", "korean_women", "--out",
         str(pattern)])
    run([garmcap, "sizerun", "--pattern", str(pattern), "--chart", "korean_women", "--out",
         str(d)])
    ptype = json.loads(pattern.read_text())["type"]
    sizes = sorted({re.match(rf"{re.escape(ptype)}_(.+)\.json$", f.name).group(1)
                    for f in d.glob(f"{ptype}_*.json")}, key=float)
    pats = {s: json.loads((d / f"{ptype}_{s}.json").read_text()) for s in sizes}
    root = ET.parse(d / "nested_grading.svg").getroot()
    legend = [g.get("data-size") for g in root.iter(f"{SVG}g") if g.get("class") == "legend"]
    if sorted(legend, key=float) != sizes:
        problems.append(f"{gtype}: legend {legend}, sizes {sizes}")
    samples = set()
    svg_rings = {}
    for g in root.iter(f"{SVG}g"):
        if g.get("class") != "piece":
            continue
        name = g.get("id")
        polys = g.findall(f"{SVG}polygon")
        by_size = {p.get("data-size"): p for p in polys}
        if sorted(by_size, key=float) != sizes or len(polys) != len(sizes):
            problems.append(f"{gtype}/{name}: outlines for {sorted(by_size)}, want {sizes}")
            continue
        marked = [p for p in polys if p.get("data-sample") == "1"]
        if len(marked) != 1:
            problems.append(f"{gtype}/{name}: {len(marked)} outlines marked as sample")
            continue
        samples.add(marked[0].get("data-size"))
        widths = {p.get("data-size"): float(p.get("stroke-width")) for p in polys}
        if widths[marked[0].get("data-size")] <= max(v for k, v in widths.items()
                                                     if k != marked[0].get("data-size")):
            problems.append(f"{gtype}/{name}: the sample is not drawn thicker")
        refs = []
        for s, poly in by_size.items():
            panel = next(p for p in pats[s]["panels"] if p["name"] == name)
            pts = points(poly.get("points"))
            ref = [(10 * x, 10 * y) for x, y in panel["outline"]]
            if len(pts) != len(ref):
                problems.append(f"{gtype}/{name}/{s}: {len(pts)} points, JSON has {len(ref)}")
                continue
            # The drawn outline is the size's own outline moved, not reshaped.
            shift = (pts[0][0] - ref[0][0], pts[0][1] - ref[0][1])
            err = max(math.hypot(p[0] - q[0] - shift[0], p[1] - q[1] - shift[1])
                      for p, q in zip(pts, ref))
            if err > 0.02:  # the SVG has 0.01 mm, the JSON its own rounding
                problems.append(f"{gtype}/{name}/{s}: not a moved copy of its JSON ({err:.3f} mm)")
            xs, ys = [p[0] for p in pts], [p[1] for p in pts]
            refs.append((min(ys), min(xs), max(xs), (min(xs) + max(xs)) / 2))
            svg_rings[(name, s)] = pts
        # One reference for all sizes: the same top, and the same left edge, right edge (a fold)
        # or middle.
        if refs:
            spread = [max(r[j] for r in refs) - min(r[j] for r in refs) for j in range(4)]
            if spread[0] > 0.02 or min(spread[1:]) > 0.02:
                problems.append(f"{gtype}/{name}: sizes not aligned at one point {spread}")
    if len(samples) != 1:
        problems.append(f"{gtype}: sample sizes {samples}")
    doc = audit(d / "nested_grading.dxf", problems)
    msp = doc.modelspace()
    for s in sizes:
        layer = f"SIZE_{s}"
        polys = [e for e in msp.query(f'POLYLINE[layer=="{layer}"]') if e.is_closed]
        if len(polys) != len({k[0] for k in svg_rings}):
            problems.append(f"{gtype}: DXF layer {layer} has {len(polys)} closed outlines")
        for e in polys:
            pts = [(v.dxf.location.x, -v.dxf.location.y) for v in e.vertices]
            if not any(len(r) == len(pts) and max(math.hypot(a[0] - b[0], a[1] - b[1])
                                                 for a, b in zip(r, pts)) < 0.01
                       for (n, rs), r in svg_rings.items() if rs == s):
                problems.append(f"{gtype}: DXF {layer} outline matches no SVG outline")
    legend_text = " ".join(t.dxf.text for t in msp.query("TEXT"))
    if f"size {next(iter(samples), '?')} (sample)" not in legend_text:
        problems.append(f"{gtype}: DXF legend does not name the sample")
    info = run(["pdfinfo", str(d / "nested_grading.pdf")])
    if not re.search(r"Pages:\s+1\n", info):
        problems.append(f"{gtype}: nested PDF is not one page")
    if "(sample)" not in run(["pdftotext", str(d / "nested_grading.pdf"), "-"]):
        problems.append(f"{gtype}: nested PDF does not name the sample")
    if shutil.which("rsvg-convert"):
        subprocess.run(["rsvg-convert", "-o", str(d / "nested.png"), "-w", "400",
                        str(d / "nested_grading.svg")], check=True)
    print(f"nested {gtype}: {len(sizes)} sizes, sample {samples}, "
          f"{len({k[0] for k in svg_rings})} pieces")


def segs_cross(a, b, c, d):
    def orient(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    o1, o2, o3, o4 = orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b)
    return o1 * o2 < 0 and o3 * o4 < 0


def bbox(r):
    return (min(p[0] for p in r), min(p[1] for p in r), max(p[0] for p in r),
            max(p[1] for p in r))


def overlap(r1, r2):
    b1, b2 = bbox(r1), bbox(r2)
    if b1[2] < b2[0] or b2[2] < b1[0] or b1[3] < b2[1] or b2[3] < b1[1]:
        return False
    lo = (max(b1[0], b2[0]), max(b1[1], b2[1]), min(b1[2], b2[2]), min(b1[3], b2[3]))

    def edges(r):
        for i in range(len(r)):
            a, b = r[i], r[(i + 1) % len(r)]
            if max(a[0], b[0]) >= lo[0] and min(a[0], b[0]) <= lo[2] and \
               max(a[1], b[1]) >= lo[1] and min(a[1], b[1]) <= lo[3]:
                yield a, b
    e2 = list(edges(r2))
    for a, b in edges(r1):
        for c, d in e2:
            if segs_cross(a, b, c, d):
                return True
    return inside(r1[0], r2) or inside(r2[0], r1)


def marker(garmcap, out, gtype, sizes, problems):
    stem = out / f"marker_{gtype}_{'_'.join(sizes)}"
    cmd = [garmcap, "marker", "--type", gtype, "--chart", "korean_women", "--width", "150",
           "--svg", f"{stem}.svg", "--pdf", f"{stem}.pdf", "--dxf", f"{stem}.dxf"]
    for s in sizes:
        cmd += ["--size", s]
    rep = json.loads(run(cmd))
    want = 0
    for s in sizes:
        pj = out / f"{gtype}_{s}.json"
        run([garmcap, "draft", "--type", gtype, "--size", s, "--chart", "korean_women", "--out",
             str(pj)])
        want += sum(max(1, p.get("cut_count", p.get("cutCount", 1)))
                    for p in json.loads(pj.read_text())["panels"])
    root = ET.parse(f"{stem}.svg").getroot()
    fabric = next(r for r in root.iter(f"{SVG}rect") if r.get("class") == "fabric")
    fx, fy = float(fabric.get("x")), float(fabric.get("y"))
    fw, fh = float(fabric.get("width")), float(fabric.get("height"))
    rings, pieces = [], []
    for g in root.iter(f"{SVG}g"):
        if g.get("class") != "piece":
            continue
        ring = points(g.find(f"{SVG}polygon").get("points"))
        grain = points(g.find(f"{SVG}polyline").get("points"))
        rings.append(ring)
        pieces.append(g)
        (ax, ay), (bx, by) = grain[0], grain[-1]
        if abs(by - ay) > 1e-6 * max(1.0, abs(bx - ax)) + 0.02:
            problems.append(f"{stem.name}: grain of {g.get('data-panel')} not along the length")
    if len(rings) != want or len(rings) != len(rep["pieces"]):
        problems.append(f"{stem.name}: {len(rings)} pieces, cut counts say {want}")
    xs = [p[0] for r in rings for p in r]
    ys = [p[1] for r in rings for p in r]
    if min(xs) < fx - 0.01 or max(xs) > fx + fw + 0.01 or min(ys) < fy - 0.01 or \
       max(ys) > fy + fh + 0.01:
        problems.append(f"{stem.name}: a piece lies off the fabric")
    length_mm = max(xs) - min(xs)
    total = sum(area(r) for r in rings)
    eff = total / (length_mm * fh)
    if abs(length_mm - 10 * rep["length_cm"]) > 0.05 or abs(eff - rep["efficiency"]) > 1e-3:
        problems.append(f"{stem.name}: SVG gives length {length_mm / 10:.2f} cm efficiency "
                        f"{eff:.4f}; reported {rep['length_cm']:.2f} / {rep['efficiency']:.4f}")
    for i in range(len(rings)):
        for j in range(i + 1, len(rings)):
            if overlap(rings[i], rings[j]):
                problems.append(f"{stem.name}: pieces {i} and {j} overlap")
    for k, p in enumerate(rep["pieces"]):
        if p["mirrored"]:
            partner = [q for q in rep["pieces"] if q["panel"] == p["panel"] and
                       q["size"] == p["size"] and not q["mirrored"]]
            if not partner or abs(partner[0]["area_cm2"] - p["area_cm2"]) > 1e-6:
                problems.append(f"{stem.name}: mirrored {p['panel']} has no equal partner")
    doc = audit(f"{stem}.dxf", problems)
    msp = doc.modelspace()
    closed = sum(1 for s in sizes for e in msp.query(f'POLYLINE[layer=="SIZE_{s}"]')
                 if e.is_closed)
    if closed != len(rings):
        problems.append(f"{stem.name}: DXF has {closed} piece outlines, SVG {len(rings)}")
    if not re.search(r"Pages:\s+1\n", run(["pdfinfo", f"{stem}.pdf"])):
        problems.append(f"{stem.name}: marker PDF is not one page")
    print(f"marker {gtype} {'+'.join(sizes)}: {len(rings)} pieces, length "
          f"{rep['length_cm']:.1f} cm on 150 cm, efficiency {100 * rep['efficiency']:.1f} %")


def main():
    garmcap, out = sys.argv[1], Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    problems = []
    for gtype in ("skirt_a", "dress"):
        nested(garmcap, out, gtype, problems)
    types = [t["name"] for t in json.loads(run([garmcap, "draft", "--list"]))["types"]]
    for gtype in types:
        try:
            marker(garmcap, out, gtype, ["66"], problems)
        except subprocess.CalledProcessError as e:
            problems.append(f"marker {gtype}: {e.stderr.strip()}")
    marker(garmcap, out, "skirt_a", ["55", "66", "77"], problems)
    for p in problems:
        print("FAIL", p)
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
