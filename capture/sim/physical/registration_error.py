#!/usr/bin/python3
"""Scores the station's registration of the form against the camera the renderer used.

    capture/sim/physical/registration_error.py RIG... [--garmcap build/bin/garmcap]

Per session of a physical rig (cases that share a bare frame are registered once): runs
`garmcap calibrate` on empty.jpg as calibrate_rig.py does (camera.json and the tape-measured
distance) into a scratch folder, then compares the fitted pose with truth.json's camera: the
camera height and distance it implies, and the error of a height read through it on the form's
axis plane at 40 and 100 cm (a hem and a waist) for a point 10 cm in front of the axis. The
truth is the renderer's own camera, so this shares nothing with the registration it scores.
It does not need the committed calibration.json (which holds the registration of its day).
"""
import argparse
import hashlib
import json
import os
import subprocess
import sys
import tempfile


def height_error(pose, camera, h, z=10.0):
    """Error (cm) of height h at depth z read through the registered pose, seen by the true camera."""
    fx = pose["intrinsics"]["fx"]
    cy = pose["intrinsics"]["cy"]
    d = pose["distance_cm"]
    cam_y = (pose["offset_px"][1] - cy) * d / fx
    true_y, true_d = camera["position_cm"][1], camera["position_cm"][2]
    row = cy + fx * (true_y - h) / (true_d - z)
    return cam_y - (row - cy) * (d - z) / fx - h


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("rigs", nargs="+")
    ap.add_argument("--garmcap", default=os.path.join(os.path.dirname(__file__), "../../../build/bin/garmcap"))
    a = ap.parse_args()
    errors = []
    with tempfile.TemporaryDirectory() as scratch:
        for rig_dir in a.rigs:
            with open(os.path.join(rig_dir, "rig.json")) as f:
                rig = json.load(f)
            seen = set()
            for case in rig["cases"]:
                cdir = os.path.join(rig_dir, case["dir"])
                with open(os.path.join(cdir, "empty.jpg"), "rb") as f:
                    key = hashlib.sha1(f.read()).hexdigest()
                if key in seen or not os.path.exists(os.path.join(cdir, "truth.json")):
                    continue
                seen.add(key)
                with open(os.path.join(cdir, "truth.json")) as f:
                    truth = json.load(f)
                form = os.path.normpath(os.path.join(cdir, truth["form"]["path"]))
                out = os.path.join(scratch, key + ".json")
                cmd = [a.garmcap, "calibrate", "--form", form, "--empty", os.path.join(cdir, "empty.jpg"),
                       "--camera", os.path.join(cdir, "camera.json"),
                       "--distance-cm", f"{truth['camera']['distance_cm']:.1f}", "--out", out]
                r = subprocess.run(cmd, capture_output=True, text=True)
                if r.returncode:
                    print(f"{rig_dir} {case['id']}: calibrate failed: {r.stderr.strip()}", file=sys.stderr)
                    errors.append(float("inf"))
                    continue
                with open(out) as f:
                    cal = json.load(f)
                pose, cam = cal["pose"], truth["camera"]
                cam_y = (pose["offset_px"][1] - pose["intrinsics"]["cy"]) * pose["distance_cm"] / pose["intrinsics"]["fx"]
                e40, e100 = height_error(pose, cam, 40.0), height_error(pose, cam, 100.0)
                errors += [abs(e40), abs(e100)]
                print(f"{os.path.basename(os.path.normpath(rig_dir)):24s} {case['id']:18s} "
                      f"camera height {cam_y - cam['position_cm'][1]:+.2f} cm, distance "
                      f"{pose['distance_cm'] - cam['position_cm'][2]:+.2f} cm; height read at 40 cm "
                      f"{e40:+.2f}, at 100 cm {e100:+.2f}; IoU {cal['fit']['iou']}")
    if errors:
        print(f"{len(errors) // 2} sessions: mean |height error| {sum(errors) / len(errors):.3f} cm, "
              f"max {max(errors):.3f} cm")


if __name__ == "__main__":
    main()
