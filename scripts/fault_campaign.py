#!/usr/bin/env python3
"""Fault injection against the commands that write results: optimize, study and validate.

Each trial injects one fault, then checks the folder it leaves:
  kill-optimize, kill-study, kill-validate  SIGKILL at a random moment, then the same command
                                            again (it resumes), which must finish (exit 0)
  full-disk      optimize into a tmpfs of a random small size (mount needed: root)
  read-only      optimize into a read-only tmpfs (mount needed: root)
  concurrent-settings  two optimize processes into one folder, center and conservative mode
  concurrent-seeds     two optimize processes into one folder, seeds 1-2 and 2-3
After every trial: every JSON file parses and no file is empty (no truncated file); no run is
lost (every seed of a finished command has its run file) or mixed (the run files of a folder
share their settings); summary.json lists exactly the run files, with their Err and
evaluations; runs.csv has one row per run file; a command that failed said why on an
`error:` line (full disk: the system's reason), and left no temporary file behind (a killed
process may leave its own `*.camplace-tmp<pid>`, counted apart: the rerun does not read them).

    python3 scripts/fault_campaign.py --binary build/release/app/camplace --trials 200

prints one line per trial and a closing count; exit status 1 when any check failed. Faults
that need a mount are skipped (and counted) where mounting is not possible."""

import argparse
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "data", "paper_basic.json")
# Runs of a few hundred milliseconds: the kill lands in the set-up, a run, a write or the
# summary.
OPTIMIZE = ["--resolution", "16x12x12", "--max-evals", "150", "--threads", "1", "--quiet"]
STUDY = {"algorithm": "gaco", "mode": "center", "runs_per_group": 2, "threads": 1,
         "first_seed": 1, "scene_seed": 1, "time_limit_s": 600, "max_evaluations": 40,
         "examinations": [{"name": "cameras", "family": "cameras", "params": [3, 4]}]}


class Trial:
    def __init__(self, kind, work):
        self.kind, self.work, self.problems, self.note = kind, work, [], ""

    def check(self, ok, what):
        if not ok:
            self.problems.append(what)


def run(binary, args, timeout=300):
    return subprocess.run([binary] + args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, timeout=timeout)


def temp_files(folder, pid=None):
    found = []
    for base, _, files in os.walk(folder):
        for name in files:
            if re.search(r"\.camplace-tmp\d+$", name) and (pid is None or name.endswith(".camplace-tmp%d" % pid)):
                found.append(os.path.join(base, name))
    return found


def check_folder(t, folder, expect_seeds=None, killed_pids=()):
    """The checks every trial ends with, on an optimize folder (or each group of a study)."""
    if not os.path.isdir(folder):
        return
    leftovers = [f for f in temp_files(folder)
                 if not any(f.endswith(".camplace-tmp%d" % p) for p in killed_pids)]
    t.check(not leftovers, "temporary files left: %s" % leftovers)
    for base, _, files in os.walk(folder):
        for name in files:
            path = os.path.join(base, name)
            if re.search(r"\.camplace-tmp\d+$", name):
                continue
            # A study run's output-<seed>.txt is its log: empty when its run was found finished.
            if os.path.getsize(path) == 0 and not re.fullmatch(r"output-\d+\.txt", name):
                t.check(False, "empty file %s" % path)
            if name.endswith(".json"):
                try:
                    with open(path) as f:
                        json.load(f)
                except ValueError as e:
                    t.check(False, "%s does not parse: %s" % (path, e))
    runs = {}
    for name in os.listdir(folder):
        m = re.fullmatch(r"run-(\d+)\.json", name)
        if m:
            with open(os.path.join(folder, name)) as f:
                runs[int(m.group(1))] = json.load(f)
    settings = {json.dumps([r["context"]["mode"], r["context"]["resolution"], r["algorithm"],
                            r["context"]["max_evaluations"]]) for r in runs.values()}
    t.check(len(settings) <= 1, "%s mixes settings: %s" % (folder, settings))
    if expect_seeds is not None:
        missing = sorted(set(expect_seeds) - set(runs))
        t.check(not missing, "%s lost the runs of seeds %s" % (folder, missing))
    summary_path = os.path.join(folder, "summary.json")
    if os.path.exists(summary_path) and runs:
        with open(summary_path) as f:
            summary = json.load(f)
        rows = {row["seed"]: row for row in summary.get("per_run", [])}
        # A summary older than the last run file (its writer was killed) is rewritten by the
        # next command; one written after every run file must list them all.
        newest_run = max(os.path.getmtime(os.path.join(folder, "run-%d.json" % s)) for s in runs)
        if os.path.getmtime(summary_path) >= newest_run:
            t.check(set(rows) == set(runs),
                    "%s: summary lists seeds %s, the files %s" % (folder, sorted(rows), sorted(runs)))
        for seed, row in rows.items():
            if seed in runs and os.path.getmtime(summary_path) >= newest_run:
                t.check(row["err"] == runs[seed]["err"] and
                        row["evaluations"] == runs[seed]["evaluations"],
                        "%s: summary row of seed %d differs from its file" % (folder, seed))


def trial_kill_optimize(binary, rng, work, t):
    out = os.path.join(work, "out")
    args = ["optimize", SCENE, "--out", out, "--runs", "3"] + OPTIMIZE
    proc_pid = killed_midway_pid(binary, args, rng, 2.5)
    again = run(binary, args)
    t.check(again.returncode == 0, "rerun failed: %s" % again.stdout[-400:])
    check_folder(t, out, expect_seeds=[1, 2, 3], killed_pids=[proc_pid])


def killed_midway_pid(binary, args, rng, longest):
    proc = subprocess.Popen([binary] + args, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    try:
        proc.wait(timeout=rng.uniform(0.0, longest))
    except subprocess.TimeoutExpired:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    return proc.pid


def trial_kill_study(binary, rng, work, t):
    study = os.path.join(work, "study.json")
    with open(study, "w") as f:
        json.dump(STUDY, f)
    out = os.path.join(work, "out")
    args = ["study", study, "--out", out]
    pid = killed_midway_pid(binary, args, rng, 1.5)
    again = run(binary, args)
    # A run killed while its child optimize wrote: the study names it; the rerun redoes it.
    t.check(again.returncode == 0, "rerun failed: %s" % again.stdout[-400:])
    killed = [pid] + [int(m) for m in re.findall(r"\.camplace-tmp(\d+)", " ".join(temp_files(out)))]
    for group in ("cameras-3", "cameras-4"):
        check_folder(t, os.path.join(out, "runs", group), expect_seeds=[1, 2], killed_pids=killed)
    with open(os.path.join(out, "runs.csv")) as f:
        rows = f.read().strip().split("\n")[1:]
    keys = [tuple(r.split(",")[:4]) for r in rows]
    t.check(len(keys) == 4 and len(set(keys)) == 4, "runs.csv rows: %s" % keys)


def trial_kill_validate(binary, rng, work, t):
    out = os.path.join(work, "out")
    made = run(binary, ["optimize", SCENE, "--out", out, "--runs", "2"] + OPTIMIZE)
    t.check(made.returncode == 0, "optimize failed: %s" % made.stdout[-400:])
    pid = killed_midway_pid(binary, ["validate", out], rng, 4.0)
    again = run(binary, ["validate", out])
    t.check(again.returncode == 0, "validate rerun failed: %s" % again.stdout[-400:])
    check_folder(t, out, expect_seeds=[1, 2], killed_pids=[pid])
    with open(os.path.join(out, "validation.csv")) as f:
        rows = f.read().strip().split("\n")[1:]
    t.check(len(rows) == 2, "validation.csv rows: %d" % len(rows))


def mount_tmpfs(path, size_kb, read_only=False):
    os.makedirs(path, exist_ok=True)
    options = "size=%dk" % size_kb + (",ro" if read_only else "")
    result = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", path],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return result.returncode == 0


def unmount(path):
    subprocess.run(["umount", path], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def trial_full_disk(binary, rng, work, t):
    disk = os.path.join(work, "disk")
    size = rng.choice([8, 16, 24, 32, 48, 64, 96, 128])
    if not mount_tmpfs(disk, size):
        t.note = "skipped (cannot mount a tmpfs here)"
        return "skipped"
    try:
        # Fill it to a random level first.
        fill = rng.randint(0, size * 1024)
        with open(os.path.join(disk, "fill"), "wb") as f:
            try:
                f.write(b"\0" * fill)
            except OSError:
                pass
        out = os.path.join(disk, "out")
        r = run(binary, ["optimize", SCENE, "--out", out, "--runs", "3"] + OPTIMIZE)
        if r.returncode != 0:
            t.check("No space left on device" in r.stdout,
                    "failed without the reason: %s" % r.stdout[-400:])
            t.check(r.stdout.count("error:") == 1, "error lines: %s" % r.stdout[-400:])
            t.note = "%d KB: exit 1 (%s)" % (size, r.stdout.strip().split("\n")[-1][:90])
        else:
            t.note = "%d KB: exit 0" % size
            check_folder(t, out, expect_seeds=[1, 2, 3])
        check_folder(t, out)
    finally:
        unmount(disk)


def trial_read_only(binary, rng, work, t):
    disk = os.path.join(work, "ro")
    if not mount_tmpfs(disk, 64, read_only=True):
        t.note = "skipped (cannot mount a tmpfs here)"
        return "skipped"
    try:
        begin = time.time()
        r = run(binary, ["optimize", SCENE, "--out", os.path.join(disk, "out")] + OPTIMIZE)
        t.check(r.returncode == 1, "exit %d: %s" % (r.returncode, r.stdout[-300:]))
        t.check("Read-only file system" in r.stdout, "no reason: %s" % r.stdout[-300:])
        t.check(time.time() - begin < 5, "found only after the work")
    finally:
        unmount(disk)


def trial_concurrent(binary, rng, work, t, overlapping):
    out = os.path.join(work, "out")
    if overlapping:
        a_args = ["optimize", SCENE, "--out", out, "--seed", "1", "--runs", "2"] + OPTIMIZE
        b_args = ["optimize", SCENE, "--out", out, "--seed", "2", "--runs", "2"] + OPTIMIZE
    else:
        # A's runs are long enough for B's to start, and end, in between.
        slow = [x if x != "150" else "600" for x in OPTIMIZE]
        a_args = ["optimize", SCENE, "--out", out, "--mode", "center", "--runs", "2"] + slow
        b_args = ["optimize", SCENE, "--out", out, "--seed", "5", "--runs", "2"] + OPTIMIZE
    a = subprocess.Popen([binary] + a_args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True)
    time.sleep(rng.uniform(0.0, 1.0))
    b = subprocess.Popen([binary] + b_args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True)
    a_out, _ = a.communicate()
    b_out, _ = b.communicate()
    seeds = []
    for code, text, mine in ((a.returncode, a_out, [1, 2]), (b.returncode, b_out,
                                                              [2, 3] if overlapping else [5, 6])):
        if code == 0:
            seeds += mine
        else:
            t.check("error:" in text, "exit %d without an error line: %s" % (code, text[-300:]))
    if not overlapping:
        t.check(a.returncode == 0 or b.returncode == 0, "both refused")
    t.note = "exit %d and %d" % (a.returncode, b.returncode)
    check_folder(t, out, expect_seeds=seeds)


KINDS = ["kill-optimize", "concurrent-settings", "full-disk", "kill-study", "concurrent-seeds",
         "read-only", "kill-validate"]


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", default=os.path.join(ROOT, "build/release/app/camplace"))
    parser.add_argument("--trials", type=int, default=14)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--kinds", default=",".join(KINDS),
                        help="comma-separated fault kinds, taken in turn")
    args = parser.parse_args()
    rng = random.Random(args.seed)
    kinds = args.kinds.split(",")
    counts = {}
    failed = skipped = 0
    begin = time.time()
    for i in range(args.trials):
        kind = kinds[i % len(kinds)]
        work = tempfile.mkdtemp(prefix="camplace-fault-")
        t = Trial(kind, work)
        try:
            if kind == "kill-optimize":
                outcome = trial_kill_optimize(args.binary, rng, work, t)
            elif kind == "kill-study":
                outcome = trial_kill_study(args.binary, rng, work, t)
            elif kind == "kill-validate":
                outcome = trial_kill_validate(args.binary, rng, work, t)
            elif kind == "full-disk":
                outcome = trial_full_disk(args.binary, rng, work, t)
            elif kind == "read-only":
                outcome = trial_read_only(args.binary, rng, work, t)
            else:
                outcome = trial_concurrent(args.binary, rng, work, t,
                                           kind == "concurrent-seeds")
        except Exception as e:  # a check that could not run is a failed trial
            t.problems.append("%s: %s" % (type(e).__name__, e))
            outcome = None
        if outcome == "skipped":
            skipped += 1
            status = "skipped"
        elif t.problems:
            failed += 1
            status = "FAILED: " + "; ".join(t.problems)
        else:
            counts[kind] = counts.get(kind, 0) + 1
            status = "ok"
        print("trial %d %s: %s%s" % (i + 1, kind, status, " (%s)" % t.note if t.note else ""),
              flush=True)
        if not t.problems:
            shutil.rmtree(work, ignore_errors=True)
        else:
            print("  kept %s" % work)
    passed = sum(counts.values())
    print("fault campaign: %d trials in %.0f s: %d passed (%s), %d failed, %d skipped; "
          "runs lost or mixed and truncated files: %s" %
          (args.trials, time.time() - begin, passed,
           ", ".join("%s %d" % kv for kv in sorted(counts.items())), failed, skipped,
           "none" if failed == 0 else "see the failed trials"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
