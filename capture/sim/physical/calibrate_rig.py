#!/usr/bin/python3
"""Registers the form in every case of a physical rig the station's way and writes the case's
calibration.json (what `garmcap rig eval` and the rig tests read).

    capture/sim/physical/calibrate_rig.py RIG [--garmcap build/bin/garmcap]

Per case: `garmcap calibrate --form F --empty empty.jpg --camera camera.json --distance-cm D`,
with the camera model the renderer used (camera.json: intrinsics and k1, k2) and the camera's
distance from the form's axis as a station would tape-measure it (truth.json). The bare frame
is undistorted by calibrate before the form is fitted; the pose is never taken from the scene.
Paths in the written file are made relative to the case folder, so the rig can move.
"""
import argparse
import json
import os
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("rig")
    ap.add_argument("--garmcap", default=os.path.join(os.path.dirname(__file__), "../../../build/bin/garmcap"))
    a = ap.parse_args()
    with open(os.path.join(a.rig, "rig.json")) as f:
        rig = json.load(f)
    form = os.path.normpath(os.path.join(a.rig, rig["form"]))
    failed = 0
    for case in rig["cases"]:
        cdir = os.path.join(a.rig, case["dir"])
        with open(os.path.join(cdir, "truth.json")) as f:
            truth = json.load(f)
        out = os.path.join(cdir, "calibration.json")
        cmd = [a.garmcap, "calibrate", "--form", form, "--empty", os.path.join(cdir, "empty.jpg"),
               "--camera", os.path.join(cdir, "camera.json"),
               "--distance-cm", f"{truth['camera']['distance_cm']:.1f}", "--out", out]
        r = subprocess.run(cmd, capture_output=True, text=True)
        overlay = os.path.join(cdir, "calibration.overlay.png")
        if os.path.exists(overlay):
            os.remove(overlay)
        if r.returncode != 0:
            failed += 1
            print(f"{case['id']}: calibrate failed: {r.stderr.strip()}", file=sys.stderr)
            continue
        with open(out) as f:
            cal = json.load(f)
        cal["form"] = os.path.relpath(form, cdir)
        cal["empty_frame"] = "empty.jpg"
        with open(out, "w") as f:
            json.dump(cal, f, indent=2, sort_keys=True)
            f.write("\n")
        iou = cal["fit"]["iou"]
        print(f"{case['id']}: px/cm {cal['pose']['px_per_cm']:.4f}, IoU {iou:.4f}")
    if failed:
        sys.exit(f"{failed} case(s) could not be calibrated")


if __name__ == "__main__":
    main()
