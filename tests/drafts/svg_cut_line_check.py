#!/usr/bin/env python3
"""The web UI's pattern.svg (the draft SVG of svg.h) of every garment type, written by the real
CLI and read back with Python's own XML parser, sharing no code with the writer:

  svg_cut_line_check.py GARMCAP_BINARY OUT_DIR [SIZE ...]

For each type of `garmcap draft --list` and each korean_women size (default 44 88) the CLI writes
the SVG; every panel group must hold one cut-line polygon (solid, no dash) and one sew-line
polygon (dashed). The cut line encloses the sew line, and each sew-line edge's midpoint lies at
the allowance the legend states ("seam allowance 10.0 mm included, hem 30.0 mm, none on fold")
from the cut line within 0.5 mm, or on it (a fold, only on a piece cut on the fold), or nearer
only beside a fold, a dart or a corner where the hem allowance steps to the seam's. When
rsvg-convert is installed the SVG is rendered too (it must render without error).
Prints one line per file; exits 1 on any failure.
"""
import json
import math
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

from outline_geometry import inside, path_dist, ring_dist, seg_dist

SVG = "{http://www.w3.org/2000/svg}"
TOL_CM = 0.05  # 0.5 mm


def points(el):
    return [tuple(float(v) for v in q.split(",")) for q in el.get("points").split()]


def check_panel(g, seam, hem, problems):
    name = g.get("id")
    cuts = [e for e in g.findall(SVG + "polygon") if e.get("class") == "cut-line"]
    sews = [e for e in g.findall(SVG + "polygon") if e.get("class") == "sew-line"]
    if len(cuts) != 1 or len(sews) != 1:
        problems.append(f"{name}: want one cut-line and one sew-line polygon, found {len(cuts)}/{len(sews)}")
        return None
    if cuts[0].get("stroke-dasharray") or not sews[0].get("stroke-dasharray"):
        problems.append(f"{name}: the cut line must be solid and the sew line dashed")
    cut, sew = points(cuts[0]), points(sews[0])
    on_fold_piece = "on fold" in " ".join(t.text or "" for t in g.iter(SVG + "text"))
    darts = [points(e) for e in g.findall(SVG + "polyline") if e.get("class") == "dart"]
    for p in sew:
        if not inside(p, cut) and ring_dist(p, cut) > 1e-3:
            problems.append(f"{name}: sew-line vertex {p} outside the cut line")
            return None
    n = len(sew)
    edges = [(sew[i], sew[(i + 1) % n]) for i in range(n)
             if math.hypot(sew[(i + 1) % n][0] - sew[i][0], sew[(i + 1) % n][1] - sew[i][1]) > 1e-6]
    mid = lambda e: ((e[0][0] + e[1][0]) / 2, (e[0][1] + e[1][1]) / 2)
    folds = [e for e in edges if ring_dist(mid(e), cut) < 2e-3]
    corners = []
    for i in range(n):
        a, b, c = sew[i - 1], sew[i], sew[(i + 1) % n]
        u, v = (b[0] - a[0], b[1] - a[1]), (c[0] - b[0], c[1] - b[1])
        lu, lv = math.hypot(*u), math.hypot(*v)
        if lu > 1e-6 and lv > 1e-6 and (u[0] * v[0] + u[1] * v[1]) / (lu * lv) < math.cos(math.radians(30)):
            corners.append(b)
    counts = {"seam": 0, "hem": 0, "fold": 0, "near": 0, "dart": 0}
    for e in edges:
        m = mid(e)
        d = ring_dist(m, cut)
        if any(path_dist(m, dp) < 1e-3 for dp in darts):
            counts["dart"] += 1  # a dart leg opened in the outline: crossed by the dart cap
        elif d < 2e-3:
            if not on_fold_piece:
                problems.append(f"{name}: edge at ({m[0]:.1f}, {m[1]:.1f}) has no allowance on a piece not cut on the fold")
                return None
            counts["fold"] += 1
        elif abs(d - seam) <= TOL_CM:
            counts["seam"] += 1
        elif abs(d - hem) <= TOL_CM:
            counts["hem"] += 1
        elif d < hem + TOL_CM and (any(seg_dist(m, *f) < hem + TOL_CM for f in folds)
                                   or any(path_dist(m, dp) < hem + TOL_CM for dp in darts)):
            counts["near"] += 1
        elif seam - TOL_CM < d < hem and any(math.hypot(m[0] - q[0], m[1] - q[1]) < hem for q in corners):
            counts["near"] += 1
        else:
            problems.append(f"{name}: sew-line edge at ({m[0]:.1f}, {m[1]:.1f}) is {d * 10:.2f} mm from "
                            f"the cut line (allowance {seam * 10:.1f} mm, hem {hem * 10:.1f} mm)")
            return None
    if counts["seam"] == 0:
        problems.append(f"{name}: no edge at the seam allowance")
    return counts


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    garmcap, out = sys.argv[1], Path(sys.argv[2])
    sizes = sys.argv[3:] or ["44", "88"]
    out.mkdir(parents=True, exist_ok=True)
    rsvg = shutil.which("rsvg-convert")
    types = [t["name"] for t in json.loads(subprocess.run(
        [garmcap, "draft", "--list"], check=True, capture_output=True, text=True).stdout)["types"]]
    failed = 0
    for t in types:
        for size in sizes:
            svg = out / f"{t}_{size}.svg"
            subprocess.run([garmcap, "draft", "--type", t, "--chart", "korean_women", "--size", size,
                            "--out", str(out / f"{t}_{size}.json"), "--svg", str(svg)],
                           check=True, capture_output=True, text=True)
            problems = []
            root = ET.parse(svg).getroot()
            legend = root.find(f".//{SVG}g[@id='legend']")
            note = " ".join(x.text or "" for x in legend.iter(SVG + "text")) if legend is not None else ""
            m = re.search(r"seam allowance ([\d.]+) mm included, hem ([\d.]+) mm", note)
            if not m or "sew line" not in note:
                problems.append("no legend naming the cut line's allowance and the sew line")
                seam = hem = 0.0
            else:
                seam, hem = float(m.group(1)) / 10, float(m.group(2)) / 10
            panels = [g for g in root.iter(SVG + "g") if (g.get("id") or "").startswith("panel-")]
            if not panels:
                problems.append("no panels")
            summary = {"seam": 0, "hem": 0, "fold": 0, "near": 0, "dart": 0}
            if m:
                for g in panels:
                    for k, v in (check_panel(g, seam, hem, problems) or {}).items():
                        summary[k] += v
            if t != "bodice" and summary["hem"] == 0:
                problems.append("no edge at the hem allowance")
            rendered = "not rendered (no rsvg-convert)"
            if rsvg:
                r = subprocess.run([rsvg, "-o", str(svg.with_suffix(".png")), "-z", "0.5", str(svg)],
                                   capture_output=True, text=True)
                if r.returncode != 0 or svg.with_suffix(".png").stat().st_size == 0:
                    problems.append(f"rsvg-convert failed: {r.stderr.strip()}")
                rendered = "rendered by rsvg-convert"
            print(f"{'ok  ' if not problems else 'FAIL'} {svg.name}: {len(panels)} panels, sew-line edges at "
                  f"seam/hem/fold/beside-corner-fold-or-dart {summary['seam']}/{summary['hem']}/"
                  f"{summary['fold']}/{summary['near']}, dart legs {summary['dart']}; {rendered}")
            for p in problems:
                print("     " + p)
            failed += bool(problems)
    print(f"{failed} of {len(types) * len(sizes)} files failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
