#!/usr/bin/env python3
"""Two study folders of the same examinations side by side, by their exact checks: for each
group, the runs, how many reached the success target by their voxel Err and by their exact Err
(`camplace validate`), the false successes (voxel yes, exact no), the runs that over-estimate
some distance (max_overestimate > 0), and the median exact Err; then the totals and the share
of runs that reached the target by their exact Err.

    python3 scripts/compare_studies.py docs/reports/study_paper docs/reports/study_paper_conservative

prints a Markdown table (the groups in the order of the second folder's runs.csv). Each folder
needs runs.csv and validation.csv (a study run with --validate, or `camplace validate DIR`)."""

import argparse
import csv
import os
import statistics
import sys


def read_study(folder):
    """{group: [rows]} from runs.csv joined with validation.csv; the groups in runs.csv order."""
    with open(os.path.join(folder, "runs.csv"), newline="") as f:
        runs = list(csv.DictReader(f))
    with open(os.path.join(folder, "validation.csv"), newline="") as f:
        checks = {row["run"]: row for row in csv.DictReader(f)}
    groups = {}
    for run in runs:
        # A family without a parameter (the domains) has its runs in runs/<family>.
        group = "%s-%s" % (run["family"], run["param"])
        if not os.path.isdir(os.path.join(folder, "runs", group)):
            group = run["family"]
        key = "runs/%s/run-%s.json" % (group, run["seed"])
        check = checks.get(key)
        if check is None or check["error"]:
            sys.exit("%s: %s has no exact check in validation.csv" % (folder, key))
        # runs.csv rounds Err to 6 decimals.
        if abs(float(check["voxel_err"]) - float(run["err_m2"])) > 5.1e-7:
            sys.exit("%s: the exact check of %s is of another run (voxel Err %s, runs.csv %s)"
                     % (folder, key, check["voxel_err"], run["err_m2"]))
        groups.setdefault((run["examination"], run["param"]), []).append(check)
    return groups


def summary(rows):
    if not rows:
        return None
    return {
        "runs": len(rows),
        "voxel": sum(r["reached_voxel"] == "true" for r in rows),
        "exact": sum(r["reached_exact"] == "true" for r in rows),
        "false": sum(r["reached_voxel"] == "true" and r["reached_exact"] != "true" for r in rows),
        "over": sum(float(r["max_overestimate"]) > 0 for r in rows),
        "median": statistics.median(float(r["exact_err"]) for r in rows),
    }


def cells(s):
    if s is None:
        return ["–"] * 5
    return ["%d of %d" % (s["voxel"], s["runs"]), "%d of %d" % (s["exact"], s["runs"]),
            str(s["false"]), str(s["over"]), "%.4f" % s["median"]]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("first", help="study folder (e.g. the center-mode study)")
    parser.add_argument("second", help="study folder of the same examinations")
    args = parser.parse_args()
    first, second = read_study(args.first), read_study(args.second)
    names = [os.path.basename(os.path.normpath(p)) for p in (args.first, args.second)]
    print("| examination | param | " + " | ".join(
        "%s: %s" % (n, c) for n in names
        for c in ("reached (voxel)", "reached (exact)", "false successes", "over-estimates",
                  "median exact Err [m²]")) + " |")
    print("|---|---|" + "---|" * 10)
    totals = {n: [] for n in names}
    for key in list(second) + [k for k in first if k not in second]:
        a, b = summary(first.get(key, [])), summary(second.get(key, []))
        totals[names[0]] += first.get(key, [])
        totals[names[1]] += second.get(key, [])
        print("| %s | %s | " % key + " | ".join(cells(a) + cells(b)) + " |")
    print("| **all** | | " + " | ".join(
        cells(summary(totals[names[0]])) + cells(summary(totals[names[1]]))) + " |")
    print()
    for n in names:
        s = summary(totals[n])
        print("- %s: %d of %d runs (%.1f %%) reached the target by their exact Err; %d false "
              "successes; %d runs over-estimate some distance." % (
                  n, s["exact"], s["runs"], 100.0 * s["exact"] / s["runs"], s["false"], s["over"]))


if __name__ == "__main__":
    main()
