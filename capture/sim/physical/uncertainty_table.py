#!/usr/bin/python3
"""Makes uncertainty_cm's table from rig evaluations and scores it on rigs it was not made from.

    capture/sim/physical/uncertainty_table.py EVAL.json... [--level 0.96] [--all-below 40]

Each EVAL.json is what `garmcap rig eval RIG --out DIR` writes (DIR/eval.json), one per rig.
Per measurement the table holds the nearest-rank `level` percentile of |error| over the pooled
rigs' correctly typed readings, or the largest error seen where there are fewer than
`all-below` readings, rounded up to 0.1 cm (pipeline::measurementUncertaintyCm). Its claim is
that 95 % of a new rig's readings lie within it, so every rig is also scored against the table
made from the others (leave one rig out): that coverage, not the pooled rigs' own, is the
estimate of what a new rig will see.
"""
import argparse
import json
import math
import os


def errors_of(path):
    with open(path) as f:
        ev = json.load(f)
    out = {}
    for case in ev["cases"]:
        if case.get("type") != case.get("truth_type"):
            continue  # a mistyped case's readings are not the measurer's to answer for
        for name, err in case.get("error_cm", {}).items():
            out.setdefault(name, []).append(abs(err))
    return out


def table_of(rigs, level, all_below):
    pooled = {}
    for errs in rigs:
        for name, v in errs.items():
            pooled.setdefault(name, []).extend(v)
    table = {}
    for name, v in pooled.items():
        v = sorted(v)
        x = v[math.ceil(level * len(v)) - 1] if len(v) >= all_below else v[-1]
        table[name] = (math.ceil(x * 10 - 1e-9) / 10, len(v))
    return table


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("evals", nargs="+")
    ap.add_argument("--level", type=float, default=0.96)
    ap.add_argument("--all-below", type=int, default=40)
    a = ap.parse_args()
    if not 0 < a.level <= 1:
        ap.error("--level must be in (0, 1]")
    names = [os.path.basename(os.path.dirname(os.path.abspath(p))) for p in a.evals]
    rigs = [errors_of(p) for p in a.evals]
    held = total = 0
    for i, name in enumerate(names):
        table = table_of(rigs[:i] + rigs[i + 1:], a.level, a.all_below)
        n = inside = 0
        outside = []
        for m, v in sorted(rigs[i].items()):
            for e in v:
                n += 1
                if m in table and e <= table[m][0] + 1e-9:
                    inside += 1
                else:
                    outside.append("%s %.2f > %s" % (m, e, table[m][0] if m in table else "none"))
        held += inside
        total += n
        print("%-28s %3d of %3d within the others' table%s" %
              (name, inside, n, ("; outside: " + ", ".join(outside)) if outside else ""))
    print("left out one rig at a time: %d of %d readings within (%.1f %%)" %
          (held, total, 100.0 * held / max(total, 1)))
    print("table from all %d rigs (cm, readings):" % len(rigs))
    for m, (u, n) in sorted(table_of(rigs, a.level, a.all_below).items()):
        print("  %-18s %5.1f  (%d)" % (m, u, n))


if __name__ == "__main__":
    main()
