#!/usr/bin/env python3
"""Runs `camplace evaluate --json --voxels-out` with two binaries on the same scenes, cameras,
resolutions, modes and refinement levels, and reports every difference apart from timing.

Usage: compare_binaries.py OLD_BINARY NEW_BINARY [--cams DIR] [--threads N]
                           [--scene SCENE_FILE=CAMERA_FILE ...] [--only-extra]
Camera files: data/paper_basic_corners.json for paper_basic, plus DIR/<scene>/run-*.json (run
files, e.g. of `camplace optimize data/<scene>.json --max-evals 60 --out DIR/<scene>`).
--scene adds a scene file with its camera file (e.g. a paper_basic variant with finer meshes and
data/paper_basic_corners.json); --only-extra runs only those.
Run from the repository root. Use it to show that a refactoring changed no result.
Exit status 0 when every output is identical, 1 otherwise.
"""
import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile

SCENES = ["paper_basic", "cell_catalogue", "small_cell"]
RESOLUTIONS = ["16x12x12", "36x27x27"]


def strip(value):
    if isinstance(value, dict):
        return {k: strip(v) for k, v in value.items() if k not in ("timing_ms",)}
    if isinstance(value, list):
        return [strip(v) for v in value]
    return value


def run(binary, scene, cams, res, mode, refine, threads, out_dir):
    path = scene if scene.endswith(".json") else f"data/{scene}.json"
    cmd = [binary, "evaluate", path, "--cameras", cams, "--json",
           "--resolution", res, "--mode", mode, "--threads", str(threads),
           "--voxels-out", os.path.join(out_dir, "model.npy")]
    if refine:
        cmd += ["--refine", str(refine)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        return {"exit": p.returncode, "stderr": p.stderr.strip()}, {}
    files = {}
    for path in sorted(glob.glob(os.path.join(out_dir, "*"))):
        with open(path, "rb") as f:
            files[os.path.basename(path)] = f.read()
    return strip(json.loads(p.stdout)), files


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--cams", default="")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--max-refine", type=int, default=3)
    ap.add_argument("--scene", action="append", default=[])
    ap.add_argument("--only-extra", action="store_true")
    args = ap.parse_args()
    cases = failures = 0
    jobs = []
    for scene in [] if args.only_extra else SCENES:
        cam_files = sorted(glob.glob(os.path.join(args.cams, scene, "run-*.json"))) if args.cams else []
        if scene == "paper_basic":
            cam_files.append("data/paper_basic_corners.json")
        jobs += [(scene, cams) for cams in cam_files]
    for item in args.scene:
        scene, _, cams = item.partition("=")
        jobs.append((scene, cams))
    for scene, cams in jobs:
        for res in RESOLUTIONS:
            for mode, refine in [("center", 0)] + [("conservative", r)
                                                   for r in range(args.max_refine + 1)]:
                with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
                    old = run(args.old, scene, cams, res, mode, refine, args.threads, a)
                    new = run(args.new, scene, cams, res, mode, refine, args.threads, b)
                cases += 1
                tag = f"{os.path.basename(scene)} {os.path.basename(cams)} {res} {mode} refine {refine}"
                if old[0] != new[0]:
                    failures += 1
                    print(f"DIFFERENT JSON: {tag}")
                elif old[1] != new[1]:
                    failures += 1
                    print(f"DIFFERENT FILES: {tag}: {sorted(old[1])} vs {sorted(new[1])}")
                else:
                    print(f"same: {tag} (err {old[0].get('err')})")
                sys.stdout.flush()
    print(f"{cases} cases, {failures} different")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
