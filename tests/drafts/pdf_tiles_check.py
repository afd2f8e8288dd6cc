#!/usr/bin/env python3
"""Tiled pattern PDFs written by the real CLI, read back with poppler (pdfinfo, pdftotext,
pdftoppm) and measured from the raster:

  pdf_tiles_check.py GARMCAP_BINARY OUT_DIR

For A4, US Letter and A0 and a few garment types (`garmcap draft --pattern-pdf --paper`):
- every page has the paper's size, and there are fewer pages than the full grid of tiles when
  the layout leaves tiles empty (no blank pages): each page shows black ink (pattern lines)
  inside its frame outside the strips it shares with its left and upper neighbours;
- the test square on page 1, rendered at 254 dpi (100 px per cm), measures 10 cm (A4, A0) or
  4 in (Letter) within 0.5 mm, and its size is printed;
- two horizontally neighbouring tiles (labels from pdftotext) overlap by 1 cm within 0.5 mm:
  the same red match mark lies 1 cm less than the frame width further left on the right tile;
- the seam allowance statement is printed.
Exits 1 on any failure.
"""
import re
import subprocess
import sys
from pathlib import Path

PAPERS = {  # name: (width pt, height pt, test square mm, label)
    "a4": (595.276, 841.89, 100.0, "10 cm"),
    "letter": (612.0, 792.0, 101.6, "4 in"),
    "a0": (2383.937, 3370.394, 100.0, "10 cm"),
}
TYPES = ["dress", "skirt_a", "pants"]


def run(cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout


def ppm(path):
    data = Path(path).read_bytes()
    m = re.match(rb"P6\s+(\d+)\s+(\d+)\s+(\d+)\s", data)
    assert m, path
    w, h = int(m.group(1)), int(m.group(2))
    return w, h, data[m.end():m.end() + w * h * 3]


def render(pdf, page, dpi, out, crop=None):
    cmd = ["pdftoppm", "-r", str(dpi), "-f", str(page), "-l", str(page), "-aa", "no",
           "-aaVector", "no", "-singlefile"]
    if crop:
        cmd += ["-x", str(crop[0]), "-y", str(crop[1]), "-W", str(crop[2]), "-H", str(crop[3])]
    subprocess.run(cmd + [str(pdf), str(out)], check=True)
    return ppm(str(out) + ".ppm")


def classify(px, i):
    r, g, b = px[i], px[i + 1], px[i + 2]
    if r < 90 and g < 90 and b < 90:
        return "black"
    if r > 200 and g < 80 and b < 80:
        return "red"
    if 90 <= r <= 170 and abs(r - g) < 8 and abs(r - b) < 8:
        return "grey"
    return None


def frame(w, h, px):
    """The grey tile frame: (left, top, right, bottom) in px: the rows and columns that are
    grey over more than a third of the page's width or height."""
    grey = [[classify(px, (y * w + x) * 3) == "grey" for x in range(w)] for y in range(h)]
    rows = [y for y in range(h) if sum(grey[y]) > w / 3]
    cols = [x for x in range(w) if sum(grey[y][x] for y in range(h)) > h / 3]
    return min(cols), min(rows), max(cols), max(rows)


def red_marks(w, h, px, dpi):
    """Centres of the red match marks (dot and cross, 8 mm across) in px."""
    seen = bytearray(w * h)
    marks = []
    for start in range(w * h):
        if seen[start] or classify(px, start * 3) != "red":
            continue
        stack, comp = [start], []
        seen[start] = 1
        while stack:
            k = stack.pop()
            comp.append(k)
            x, y = k % w, k // w
            for nx, ny in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
                if 0 <= nx < w and 0 <= ny < h:
                    n = ny * w + nx
                    if not seen[n] and classify(px, n * 3) == "red":
                        seen[n] = 1
                        stack.append(n)
        xs = [k % w for k in comp]
        ys = [k // w for k in comp]
        size = dpi / 2.54 * 0.8
        if abs(max(xs) - min(xs) - size) < 0.2 * size and abs(max(ys) - min(ys) - size) < 0.2 * size:
            marks.append(((max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2))
    return marks


def check(garmcap, out, typ, paper, problems):
    pdf = out / f"{typ}_{paper}.pdf"
    run([garmcap, "draft", "--type", typ, "--chart", "korean_women", "--size", "66", "--out",
         str(out / f"{typ}.json"), "--pattern-pdf", str(pdf), "--paper", paper, "--style", "T-1"])
    wpt, hpt, square_mm, label = PAPERS[paper]
    info = run(["pdfinfo", str(pdf)])
    pages = int(re.search(r"Pages:\s+(\d+)", info).group(1))
    m = re.search(r"Page size:\s+([\d.]+) x ([\d.]+) pts", info)
    if abs(float(m.group(1)) - wpt) > 0.5 or abs(float(m.group(2)) - hpt) > 0.5:
        problems.append(f"{pdf.name}: page size {m.group(0)}")
    text = run(["pdftotext", "-layout", str(pdf), "-"])
    page_texts = text.split("\f")[:pages]
    tiles = [re.search(r"tile ([A-Z]+\d+) ", t).group(1) for t in page_texts]
    grid = re.search(r"p 1/(\d+)", page_texts[0])
    if int(grid.group(1)) != pages:
        problems.append(f"{pdf.name}: label says {grid.group(1)} pages, file has {pages}")
    if f"{label} test square" not in page_texts[0]:
        problems.append(f"{pdf.name}: page 1 does not name the {label} test square")
    if "seam allowance 10.0 mm included" not in text:
        problems.append(f"{pdf.name}: no seam allowance statement")
    # No blank page: black ink inside the frame (10 mm margins), outside the left/top strips
    # shared with the neighbours.
    def ink(p, dpi, guard_px):
        w, h, px = render(pdf, p, dpi, out / f"ink_{typ}_{paper}_{p}")
        cm = dpi / 2.54
        # The frame from the 10 mm margin (its 0.3 pt grey line may vanish at a low dpi).
        l, t, r, b = cm, cm, w - cm, h - cm
        n = 0
        for y in range(int(t + cm + guard_px), int(b - guard_px)):
            for x in range(int(l + cm + guard_px), int(r - guard_px)):
                n += classify(px, (y * w + x) * 3) == "black"
        return n

    for p in range(1, pages + 1):
        # Quick look at a low dpi (2 px off the strips); a page that seems empty is looked at
        # again at 100 dpi, 1 px off the strips (a piece may reach only 1 mm past a strip).
        if ink(p, 20 if paper != "a0" else 8, 2) < 3 and ink(p, 100, 1) < 3:
            problems.append(f"{pdf.name}: page {p} (tile {tiles[p - 1]}) is blank")
    # Test square: 254 dpi = 100 px/cm; crop the page's top-left 16 cm.
    w, h, px = render(pdf, 1, 254, out / f"sq_{typ}_{paper}", (0, 0, 1600, 1600))
    row = 100 + 300  # sheet y 3 cm: crosses only the square's two vertical sides
    runs, x = [], 0
    while x < w:
        if classify(px, (row * w + x) * 3) == "black":
            x0 = x
            while x < w and classify(px, (row * w + x) * 3) == "black":
                x += 1
            runs.append((x0 + x - 1) / 2)
        x += 1
    if len(runs) < 2:
        problems.append(f"{pdf.name}: test square not found ({runs})")
    else:
        side_mm = (runs[1] - runs[0]) / 10.0
        print(f"{pdf.name}: {pages} pages, test square {side_mm:.2f} mm (want {square_mm})")
        if abs(side_mm - square_mm) > 0.5:
            problems.append(f"{pdf.name}: test square {side_mm:.2f} mm, want {square_mm}")
    # Overlap of two horizontal neighbours, measured from their rasters at 100 dpi.
    pairs = [(i, tiles.index(re.sub(r"\d+$", lambda n: str(int(n.group()) + 1), t)))
             for i, t in enumerate(tiles)
             if re.sub(r"\d+$", lambda n: str(int(n.group()) + 1), t) in tiles]
    if paper != "a0" and not pairs:
        problems.append(f"{pdf.name}: no two neighbouring tiles to check the overlap")
    for i, j in pairs[:1]:
        dpi = 100
        wa, ha, pa = render(pdf, i + 1, dpi, out / f"ov_{typ}_{paper}_a")
        wb, hb, pb = render(pdf, j + 1, dpi, out / f"ov_{typ}_{paper}_b")
        la, ta, ra, ba = frame(wa, ha, pa)
        lb, tb, rb, bb = frame(wb, hb, pb)
        ma = [m for m in red_marks(wa, ha, pa, dpi) if m[0] > (la + ra) / 2]
        mb = [m for m in red_marks(wb, hb, pb, dpi) if m[0] < (lb + rb) / 2]
        if not ma or not mb:
            problems.append(f"{pdf.name}: no match marks between {tiles[i]} and {tiles[j]}")
            continue
        # The same sheet point: on the left tile at xa - la, on the right one at xb - lb.
        xa, ya = min(ma, key=lambda m: m[1])
        xb, yb = min(mb, key=lambda m: m[1])
        step_mm = ((xa - la) - (xb - lb)) * 25.4 / dpi
        overlap_mm = (ra - la) * 25.4 / dpi - step_mm
        dy_mm = ((ya - ta) - (yb - tb)) * 25.4 / dpi
        print(f"{pdf.name}: tiles {tiles[i]}|{tiles[j]} overlap {overlap_mm:.2f} mm, "
              f"marks {dy_mm:.2f} mm apart vertically")
        if abs(overlap_mm - 10.0) > 0.5 or abs(dy_mm) > 0.5:
            problems.append(f"{pdf.name}: overlap {overlap_mm:.2f} mm (dy {dy_mm:.2f})")


def main():
    garmcap, out = sys.argv[1], Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    problems = []
    for paper in PAPERS:
        for typ in (TYPES if paper != "a0" else TYPES[:1]):
            check(garmcap, out, typ, paper, problems)
    for p in problems:
        print("FAIL", p)
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
