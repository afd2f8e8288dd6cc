#!/usr/bin/python3
"""Checks the dependency rules of docs/architecture.md on the sources' #include lines.

Every `#include "garmcap/<lib>/..."` (or <...>) in a folder must name a library that folder may
use. Exit status 0 when every include keeps the rules, 1 when one breaks them (each printed as
file:line, the include and the rule), 2 for a usage error.

    tests/arch/include_rules.py [--root REPO]
"""

import argparse
import re
import sys
from pathlib import Path

# Folder (relative to the repository root) -> libraries its sources may include. The most
# specific folder wins (capture/sim before capture). Libraries are the first path component
# after "garmcap/" in an include: core/garmcap's headers are garmcap/pipeline/..., core/dsw's
# garmcap/dsw/..., capture/sim's garmcap/sim/....
ALLOWED = {
    # core/io is the base beneath drafts and capture (which may not include each other): every
    # library may include it, and it includes no other garmcap library.
    "core/io": {"io"},
    "drafts": {"drafts", "io"},
    "calib": {"calib", "drafts", "io"},
    "capture": {"capture", "io"},
    "capture/sim": {"sim", "capture", "calib", "drafts", "io"},
    # core never includes the simulator or the camera back ends ("core shares no code with any
    # simulator"; "core does not do I/O on devices"). Everything of the simulator, its garment
    # model and form generator included, is under garmcap/sim/.
    "core/garmcap": {"pipeline", "dsw", "calib", "drafts", "io"},
    "core/dsw": {"dsw", "drafts", "io"},
    "daemon": None,  # the daemon and the CLI tools may use every library
    # The hub serves with the daemon's HTTP layer and never links the capture pipeline; it writes
    # the stations' stored patterns as files with the drafts library's own writers.
    "daemon/hub": {"hub", "daemon", "drafts", "io"},
}

SOURCE_SUFFIXES = {".h", ".hpp", ".cpp", ".cc"}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"](garmcap/([A-Za-z0-9_]+)/[^>"]+)[>"]')


def rule_folder(rel: str):
    """The most specific folder of ALLOWED that holds `rel`, or None."""
    best = None
    for folder in ALLOWED:
        if rel == folder or rel.startswith(folder + "/"):
            if best is None or len(folder) > len(best):
                best = folder
    return best


def check(root: Path):
    """Returns the violations, each a printable line."""
    violations = []
    for path in sorted(root.rglob("*")):
        if path.suffix not in SOURCE_SUFFIXES or not path.is_file():
            continue
        rel = path.relative_to(root).as_posix()
        if rel.startswith("build") or "/build/" in rel:
            continue
        folder = rule_folder(rel)
        if folder is None:
            continue
        allowed = ALLOWED[folder]
        try:
            lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
        except OSError as e:
            violations.append(f"{rel}: cannot read: {e}")
            continue
        for number, line in enumerate(lines, start=1):
            m = INCLUDE.match(line)
            if not m:
                continue
            header, lib = m.group(1), m.group(2)
            where = f"{rel}:{number}: #include \"{header}\""
            if allowed is not None and lib not in allowed:
                violations.append(
                    f"{where}: {folder}/ may include only "
                    f"{', '.join('garmcap/' + a for a in sorted(allowed))} (docs/architecture.md)")
    return violations


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", type=Path, default=Path(__file__).resolve().parents[2],
                        help="repository root (default: this checkout)")
    args = parser.parse_args(argv)
    if not args.root.is_dir():
        print(f"include_rules: {args.root}: not a directory", file=sys.stderr)
        return 2
    violations = check(args.root)
    for v in violations:
        print(v, file=sys.stderr)
    if violations:
        print(f"include_rules: {len(violations)} include(s) against docs/architecture.md",
              file=sys.stderr)
        return 1
    print("include_rules: every include keeps the dependency rules")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
