#!/usr/bin/env python3
"""Can a grading CAD rebuild every size from the sample block and the .RUL?

  grade_rebuild_check.py GARMCAP_BINARY OUT_DIR

For each garment type the real CLI drafts the pattern at korean_women 66 and grades it over the
chart (`garmcap sizerun`), writing graded.dxf and graded.rul. This script reads them as a
grading CAD does, sharing no code with the writers: the DXF through Debian's python3-ezdxf, the
RUL with its own parser. From the sample size's block it takes the sew line (layer 14) and the
grade points (the "# N" texts on layer 2); it moves each grade point by its rule's delta for a
size and every other point by proportional curve grading (the deltas of the grade points before
and after it, weighted by its arc-length position between them on the sample), then compares the
rebuilt outline with that size's own block. Every point of every size must be within TOL_MM.
It also reports what turn points alone (layer-2 POINTs) would give, the way the file was graded
before curve points carried rules. Prints one line per type; exits 1 on any failure.
"""
import math
import re
import subprocess
import sys
from pathlib import Path

import ezdxf

TOL_MM = 0.6  # the writer's 0.5 mm, plus the files' 0.001 mm rounding
TYPES = ["bodice", "dress", "dress_shift", "skirt_a", "skirt_h", "skirt_high_waist", "pants", "blouse", "sweater"]


def read_rul(path):
    text = Path(path).read_text(encoding="ascii")
    sizes = re.search(r"^SIZE LIST:(.*)$", text, re.M).group(1).split()
    sample = re.search(r"^SAMPLE SIZE:\s*(\S+)", text, re.M).group(1)
    rules = {}
    for m in re.finditer(r"^RULE: DELTA (\d+)\r?\n(.*?)(?=^RULE:|^END)", text, re.M | re.S):
        pairs = [tuple(float(v) for v in p.split(",")) for p in m.group(2).split()]
        if len(pairs) != len(sizes):
            raise SystemExit(f"{path}: rule {m.group(1)} has {len(pairs)} pairs for {len(sizes)} sizes")
        rules[int(m.group(1))] = dict(zip(sizes, pairs))
    return sizes, sample, rules


def sew_line(block):
    lines = [e for e in block if e.dxftype() == "POLYLINE" and e.dxf.layer == "14"]
    if len(lines) != 1:
        raise SystemExit(f"block {block.name}: {len(lines)} sew lines on layer 14")
    return [(v.dxf.location.x, v.dxf.location.y) for v in lines[0].vertices]


def nearest(points, p):
    best = min(range(len(points)), key=lambda i: math.dist(points[i], p))
    return best if math.dist(points[best], p) < 1e-3 else None


def rebuild(sample_pts, graded, deltas):
    """graded: vertex index -> (dx, dy) of this size. Proportional curve grading between them."""
    n = len(sample_pts)
    keys = sorted(graded)
    out = [None] * n
    for a_i, a in enumerate(keys):
        b = keys[(a_i + 1) % len(keys)]
        span = (b - a) % n or n
        arc = [0.0]
        for k in range(1, span + 1):
            arc.append(arc[-1] + math.dist(sample_pts[(a + k - 1) % n], sample_pts[(a + k) % n]))
        da, db = deltas[a], deltas[b]
        for k in range(span):
            t = arc[k] / arc[span] if arc[span] > 0 else 0.0
            v = (a + k) % n
            out[v] = (sample_pts[v][0] + (1 - t) * da[0] + t * db[0],
                      sample_pts[v][1] + (1 - t) * da[1] + t * db[1])
    return out


def check_type(garmcap, out, gtype):
    d = out / gtype
    d.mkdir(parents=True, exist_ok=True)
    pattern = d / "pattern.json"
    subprocess.run([garmcap, "draft", "--type", gtype, "--size", "66", "--chart", "korean_women",
                    "--out", str(pattern)], check=True, capture_output=True)
    subprocess.run([garmcap, "sizerun", "--pattern", str(pattern), "--chart", "korean_women",
                    "--out", str(d)], check=True, capture_output=True)
    doc = ezdxf.readfile(d / "graded.dxf")
    sizes, sample, rules = read_rul(d / "graded.rul")
    pieces = sorted({b.name.rsplit("_", 1)[0] for b in doc.blocks
                     if not b.name.startswith("*") and b.name.endswith("_" + sample)})
    worst, worst_turns, where = 0.0, 0.0, ""
    n_rules = 0
    for piece in pieces:
        block = doc.blocks.get(f"{piece}_{sample}")
        pts = sew_line(block)
        # "# N" texts follow their point; map each to its sew-line vertex.
        rule_at, turn_vertices = {}, set()
        for e in block:
            if e.dxftype() == "TEXT" and e.dxf.layer == "2" and e.dxf.text.startswith("# "):
                v = nearest(pts, (e.dxf.insert.x, e.dxf.insert.y))
                if v is None:
                    raise SystemExit(f"{gtype} {piece}: grade rule {e.dxf.text} is on no sew-line point")
                rule_at[v] = int(e.dxf.text[2:])
            elif e.dxftype() == "POINT" and e.dxf.layer == "2":
                v = nearest(pts, (e.dxf.location.x, e.dxf.location.y))
                if v is not None:
                    turn_vertices.add(v)
        if not rule_at:
            raise SystemExit(f"{gtype} {piece}: no grade rules in the sample block")
        n_rules += len(rule_at)
        for size in sizes:
            target = sew_line(doc.blocks.get(f"{piece}_{size}"))
            if len(target) != len(pts):
                raise SystemExit(f"{gtype} {piece} {size}: {len(target)} points, sample {len(pts)}")
            deltas = {v: rules[r][size] for v, r in rule_at.items()}
            got = rebuild(pts, rule_at, deltas)
            err = max(math.dist(g, t) for g, t in zip(got, target))
            if err > worst:
                worst, where = err, f"{piece} size {size}"
            # The same rebuild with rules on turn points only (the deltas read off the blocks).
            turns = sorted(turn_vertices) or [0]
            tdeltas = {v: (target[v][0] - pts[v][0], target[v][1] - pts[v][1]) for v in turns}
            tgot = rebuild(pts, dict.fromkeys(turns), tdeltas)
            worst_turns = max(worst_turns, max(math.dist(g, t) for g, t in zip(tgot, target)))
    ok = worst <= TOL_MM
    print(f"{'ok  ' if ok else 'FAIL'} {gtype}: {len(pieces)} pieces, {n_rules} rules, "
          f"{len(sizes)} sizes (sample {sample}): rebuilt within {worst:.3f} mm (worst {where}); "
          f"turn points alone: {worst_turns:.1f} mm")
    return ok


def main():
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    garmcap, out = sys.argv[1], Path(sys.argv[2])
    results = [check_type(garmcap, out, t) for t in TYPES]
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
