#!/usr/bin/python3
"""Self-test of include_rules.py: on small temporary trees, a clean tree passes, and each kind of
forbidden include fails with the file:line and the rule named. Exit 0 when all cases behave."""

import subprocess
import sys
import tempfile
from pathlib import Path

SCRIPT = Path(__file__).resolve().with_name("include_rules.py")


def tree(root: Path, files: dict):
    for rel, text in files.items():
        p = root / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)


def run(files: dict):
    with tempfile.TemporaryDirectory(prefix="include_rules_") as d:
        tree(Path(d), files)
        r = subprocess.run([sys.executable, str(SCRIPT), "--root", d], capture_output=True,
                           text=True)
        return r.returncode, r.stdout + r.stderr


CLEAN = {
    "core/io/src/f.cpp": '#include "garmcap/io/file_io.h"\n',
    "drafts/src/a.cpp": '#include "garmcap/drafts/a.h"\n#include "garmcap/io/file_io.h"\n',
    "calib/src/b.cpp": '#include "garmcap/calib/b.h"\n#include "garmcap/drafts/a.h"\n',
    "capture/src/c.cpp": '#include "garmcap/capture/c.h"\n#include "garmcap/io/file_io.h"\n',
    "capture/sim/src/s.cpp": '#include "garmcap/sim/s.h"\n#include "garmcap/capture/c.h"\n'
                             '#include "garmcap/calib/b.h"\n',
    "core/garmcap/src/p.cpp": '#include "garmcap/pipeline/p.h"\n#include "garmcap/calib/b.h"\n',
    "daemon/src/d.cpp": '#include "garmcap/sim/s.h"\n#include "garmcap/pipeline/p.h"\n',
}

# (description, file added to the clean tree, its text, what the report must contain)
FORBIDDEN = [
    ("the base io including drafts", "core/io/src/bad.cpp", '#include "garmcap/drafts/a.h"\n',
     "core/io/src/bad.cpp:1: #include \"garmcap/drafts/a.h\": core/io/ may include only garmcap/io"),
    ("capture including calib", "capture/src/bad.cpp",
     '#include <vector>\n#include "garmcap/calib/form_model.h"\n',
     "capture/src/bad.cpp:2: #include \"garmcap/calib/form_model.h\": capture/ may include only"),
    ("drafts including calib", "drafts/include/garmcap/drafts/bad.h",
     '#pragma once\n#include <garmcap/calib/x.h>\n',
     "drafts/include/garmcap/drafts/bad.h:2:"),
    ("core including the simulator", "core/garmcap/src/bad.cpp",
     '\n\n#include "garmcap/sim/scene.h"\n', "core/garmcap/src/bad.cpp:3:"),
    ("core/dsw including capture", "core/dsw/src/bad.cpp", '#include "garmcap/capture/rig.h"\n',
     "core/dsw/ may include only"),
    ("core including the simulator's garment model (once a documented exception)",
     "core/garmcap/src/capture_context.cpp", '#include "garmcap/sim/garment_model.h"\n',
     "core/garmcap/src/capture_context.cpp:1: #include \"garmcap/sim/garment_model.h\": "
     "core/garmcap/ may include only"),
    ("the simulator including the pipeline", "capture/sim/src/bad.cpp",
     '#include "garmcap/pipeline/capture_pipeline.h"\n', "capture/sim/ may include only"),
]


def main():
    failures = []
    code, out = run(CLEAN)
    if code != 0:
        failures.append(f"clean tree: exit {code}, expected 0:\n{out}")
    for what, rel, text, expected in FORBIDDEN:
        code, out = run({**CLEAN, rel: text})
        if code != 1:
            failures.append(f"{what}: exit {code}, expected 1:\n{out}")
        elif expected not in out:
            failures.append(f"{what}: report lacks {expected!r}:\n{out}")
    for f in failures:
        print("FAIL:", f, file=sys.stderr)
    print(f"include_rules self-test: {1 + len(FORBIDDEN) - len(failures)} of "
          f"{len(FORBIDDEN) + 1} cases behave")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
