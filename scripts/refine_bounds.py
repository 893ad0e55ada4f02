#!/usr/bin/env python3
"""The conservative lower bound of Err per group of a study and refinement level.

For every group of a study file (default data/studies/paper.json) this generates the group's
scene (`camplace generate`), lets `camplace optimize --mode conservative --refine L` set up its
evaluator for L = 0..MAX (one evaluation budget, so it only reports the bound) and reads the
proven lower bound of Err and the tolerance from the run file. It prints a Markdown table and the
smallest L whose bound lies below the tolerance (the refinement rule of
data/studies/paper_conservative.json), or "none" when no L up to MAX does (or memory refuses it).

    python3 scripts/refine_bounds.py [--camplace build/release/app/camplace]
        [--study data/studies/paper.json] [--max-refine 3] [--csv FILE]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--camplace", default="build/release/app/camplace")
    parser.add_argument("--study", default="data/studies/paper.json")
    parser.add_argument("--max-refine", type=int, default=3)
    parser.add_argument("--csv", default="")
    args = parser.parse_args()
    study = json.load(open(args.study))
    seed = str(study.get("scene_seed", 1))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for ex in study["examinations"]:
            params = ex.get("params", [None])
            for p in params:
                group = ex["family"] + ("" if p is None else "-" + str(p))
                scene = os.path.join(tmp, group + ".json")
                cmd = [args.camplace, "generate", ex["family"], "--seed", seed, "--out", scene]
                if p is not None:
                    cmd[3:3] = ["--param", str(p)]
                subprocess.run(cmd, check=True, capture_output=True)
                bounds, tolerance, seconds = [], None, []
                for level in range(args.max_refine + 1):
                    out = os.path.join(tmp, group + "-" + str(level))
                    start = time.time()
                    r = subprocess.run(
                        [args.camplace, "optimize", scene, "--mode", "conservative", "--refine",
                         str(level), "--max-evals", "1", "--threads", "1", "--quiet", "--out",
                         out], capture_output=True, text=True)
                    seconds.append(time.time() - start)
                    if r.returncode != 0:
                        bounds.append(None)
                        continue
                    run = json.load(open(os.path.join(out, "run-1.json")))
                    bounds.append(run["err_lower_bound"])
                    tolerance = run["tolerance"]
                rule = next((level for level, b in enumerate(bounds)
                             if b is not None and tolerance is not None and b < tolerance), None)
                rows.append((group, tolerance, bounds, rule, seconds))
                print(group, tolerance, bounds, rule, file=sys.stderr)
    levels = range(args.max_refine + 1)
    print("| group | tolerance [m²] | " + " | ".join("bound L=%d [m²]" % l for l in levels) +
          " | smallest L with bound < tolerance |")
    print("|---|---|" + "---|" * len(levels) + "---|")
    for group, tolerance, bounds, rule, _ in rows:
        cells = ["refused" if b is None else "%.4f" % b for b in bounds]
        print("| %s | %s | %s | %s |" % (group, "%.4f" % tolerance if tolerance else "-",
                                         " | ".join(cells), "none" if rule is None else rule))
    if args.csv:
        with open(args.csv, "w") as f:
            f.write("group,tolerance," + ",".join("bound_L%d" % l for l in levels) +
                    ",rule," + ",".join("seconds_L%d" % l for l in levels) + "\n")
            for group, tolerance, bounds, rule, seconds in rows:
                f.write("%s,%s,%s,%s,%s\n" % (
                    group, tolerance, ",".join("" if b is None else repr(b) for b in bounds),
                    "" if rule is None else rule, ",".join("%.2f" % s for s in seconds)))


if __name__ == "__main__":
    main()
