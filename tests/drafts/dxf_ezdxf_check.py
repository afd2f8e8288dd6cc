#!/usr/bin/env python3
"""DXF-AAMA files of every garment type, written by the real CLI and read by an independent
reader (Debian's python3-ezdxf):

  dxf_ezdxf_check.py [-v] GARMCAP_BINARY OUT_DIR [SIZE ...]     (-v: list the audit's fixes)

For each type of `garmcap draft --list` and each korean_women size (default 44 66 88) the CLI
writes the DXF; ezdxf audits it (no errors allowed) and, for every piece block, the layer-1 cut
line must be one closed polyline enclosing the layer-14 sew line (also one closed polyline)
by the allowance the piece's own text states ("seam allowance 10.0 mm included, hem 30.0 mm,
none on fold"): each sew-line edge's midpoint lies at the seam allowance, the hem allowance,
or 0 on the layer-6 fold line from the cut line, or nearer only beside a fold or a dart; every
layer-4 notch is a 5 mm slit from the cut line inward.
Prints one line per file; exits 1 on any failure.
"""
import json
import math
import re
import subprocess
import sys
from pathlib import Path

import ezdxf

from outline_geometry import inside, path_dist, ring_dist, seg_dist

TOL_MM = 0.05


def closed_polylines(block, layer):
    out = []
    for e in block.query(f'POLYLINE[layer=="{layer}"]'):
        out.append(([(v.dxf.location.x, v.dxf.location.y) for v in e.vertices], e.is_closed))
    return out


def check_block(block, problems):
    name = block.name
    cut = closed_polylines(block, "1")
    sew = closed_polylines(block, "14")
    if len(cut) != 1 or not cut[0][1]:
        problems.append(f"{name}: want one closed layer-1 cut line, found {len(cut)}")
        return
    if len(sew) != 1 or not sew[0][1]:
        problems.append(f"{name}: want one closed layer-14 sew line, found {len(sew)}")
        return
    cut, sew = cut[0][0], sew[0][0]
    note = " ".join(t.dxf.text for t in block.query("TEXT"))
    m = re.search(r"seam allowance ([\d.]+) mm included, hem ([\d.]+) mm", note)
    if not m:
        problems.append(f"{name}: no allowance annotation")
        return
    seam, hem = float(m.group(1)), float(m.group(2))
    folds = [((e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y))
             for e in block.query('LINE[layer=="6"]')]
    if "Annotation: cut on fold" in note:
        # The mirror line: one layer-6 LINE along the sew line's straight edge at its far left
        # or right (the centre line the piece is unfolded about).
        xs = [p[0] for p in sew]
        on_side = lambda q: min(abs(q[0] - min(xs)), abs(q[0] - max(xs))) < 1e-3
        if len(folds) != 1 or not all(on_side(q) and ring_dist(q, sew) < 1e-3 for q in folds[0]) \
                or abs(folds[0][0][0] - folds[0][1][0]) > 1e-3:
            problems.append(f"{name}: cut on fold without one layer-6 mirror line on its centre edge")
    elif folds:
        problems.append(f"{name}: a layer-6 mirror line on a piece not cut on the fold")
    darts = [[(v.dxf.location.x, v.dxf.location.y) for v in e.vertices]
             for e in block.query('POLYLINE[layer=="8"]')]
    for p in sew:
        if not inside(p, cut) and ring_dist(p, cut) > 1e-3:
            problems.append(f"{name}: sew-line vertex {p} outside the cut line")
            return
    for p in cut:
        if inside(p, sew) and ring_dist(p, sew) > 1e-3:
            problems.append(f"{name}: cut-line vertex {p} inside the piece")
            return
    for e in block.query('LINE[layer=="4"]'):
        a, b = (e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y)
        if ring_dist(a, cut) > 1e-3 or not inside(b, cut) or abs(math.hypot(b[0] - a[0], b[1] - a[1]) - 5) > 1e-3:
            problems.append(f"{name}: notch at {a} is no 5 mm slit from the cut line inward")
            return
    n = len(sew)
    # Corners of the sew line (a turn over 30 degrees): where one allowance steps to another.
    corners = []
    for i in range(n):
        a, b, c = sew[i - 1], sew[i], sew[(i + 1) % n]
        u, v = (b[0] - a[0], b[1] - a[1]), (c[0] - b[0], c[1] - b[1])
        lu, lv = math.hypot(*u), math.hypot(*v)
        if lu > 1e-6 and lv > 1e-6 and (u[0] * v[0] + u[1] * v[1]) / (lu * lv) < math.cos(math.radians(30)):
            corners.append(b)
    counts = {"seam": 0, "hem": 0, "fold": 0, "near": 0, "dart": 0}
    for i in range(n):
        a, b = sew[i], sew[(i + 1) % n]
        if math.hypot(b[0] - a[0], b[1] - a[1]) < 1e-6:
            continue
        mid = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
        d = ring_dist(mid, cut)
        if any(path_dist(mid, dp) < 1e-3 for dp in darts):
            counts["dart"] += 1  # a dart leg: crossed by the dart cap, no allowance of its own
            continue
        on_fold = any(seg_dist(mid, f0, f1) < 1e-3 for f0, f1 in folds)
        near_fold = any(seg_dist(mid, f0, f1) < hem + TOL_MM for f0, f1 in folds)
        near_dart = any(path_dist(mid, dp) < hem + TOL_MM for dp in darts)
        if on_fold:
            if d > 1e-3:
                problems.append(f"{name}: fold edge at {mid} is {d:.3f} mm from the cut line")
            counts["fold"] += 1
        elif abs(d - seam) <= TOL_MM:
            counts["seam"] += 1
        elif abs(d - hem) <= TOL_MM:
            counts["hem"] += 1
        elif (near_fold or near_dart) and d < hem + TOL_MM:
            counts["near"] += 1  # beside the fold (no allowance) or a dart's cap
        elif seam - TOL_MM < d < hem and any(math.hypot(mid[0] - q[0], mid[1] - q[1]) < hem for q in corners):
            counts["near"] += 1  # where the hem allowance steps to the seam's at a corner
        else:
            problems.append(f"{name}: sew-line edge at ({mid[0]:.1f}, {mid[1]:.1f}) is {d:.3f} mm "
                            f"from the cut line (allowance {seam} mm, hem {hem} mm)")
            return
    if counts["seam"] == 0:
        problems.append(f"{name}: no edge at the seam allowance")
    return counts


def main():
    verbose = "-v" in sys.argv
    args = [a for a in sys.argv[1:] if a != "-v"]
    if len(args) < 2:
        print(__doc__)
        return 2
    garmcap, out = args[0], Path(args[1])
    sizes = args[2:] or ["44", "66", "88"]
    out.mkdir(parents=True, exist_ok=True)
    types = [t["name"] for t in json.loads(subprocess.run(
        [garmcap, "draft", "--list"], check=True, capture_output=True, text=True).stdout)["types"]]
    failed = 0
    for t in types:
        for size in sizes:
            dxf = out / f"{t}_{size}.dxf"
            subprocess.run([garmcap, "draft", "--type", t, "--chart", "korean_women", "--size", size,
                            "--out", str(out / f"{t}_{size}.json"), "--dxf", str(dxf)],
                           check=True, capture_output=True, text=True)
            doc = ezdxf.readfile(dxf)
            auditor = doc.audit()
            problems = [f"audit: {e.message}" for e in auditor.errors]
            # ezdxf 0.18.1 re-owns the SEQEND of every POLYLINE in a block of an R12 file, also
            # in R12 files it writes itself; any other fix is a problem of the file.
            problems += [f"audit fix: {f.message}" for f in auditor.fixes
                         if not re.fullmatch(r"Deleted SEQEND\(#\w+\) entity with invalid owner handle #None\.", f.message)]
            if verbose:
                for f in auditor.fixes:
                    print("     fix:", f.message)
            blocks = [b for b in doc.blocks if not b.name.startswith("*")]
            if not blocks:
                problems.append("no piece blocks")
            summary = {"seam": 0, "hem": 0, "fold": 0, "near": 0, "dart": 0}
            for b in blocks:
                c = check_block(b, problems)
                for k, v in (c or {}).items():
                    summary[k] += v
            if t != "bodice" and summary["hem"] == 0:
                problems.append("no edge at the hem allowance")
            status = "ok  " if not problems else "FAIL"
            print(f"{status} {dxf.name}: {len(blocks)} pieces, audit {len(auditor.errors)} errors "
                  f"{len(auditor.fixes)} fixes, sew-line edges at seam/hem/fold/beside-corner-fold-or-dart "
                  f"{summary['seam']}/{summary['hem']}/{summary['fold']}/{summary['near']}, dart legs {summary['dart']}")
            for p in problems:
                print("     " + p)
            failed += bool(problems)
    print(f"{failed} of {len(types) * len(sizes)} files failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
