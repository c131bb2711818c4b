#!/usr/bin/env python3
"""RocketPy's rigid 10 s flight and flexflight's flexible flights, timed side by side as whole
processes on this machine (issue "Speed: a flexible flight 20x faster than RocketPy's rigid
one"). Standard library only; RocketPy runs in the venv of `setup_venv.sh` (created on first
use), flexflight from the release build (built on first use). Outside `cargo test`.

    python3 tools/rocketpy/side_by_side.py [--rounds N] [--no-build] [--json FILE]

Every case is run once to warm the artifact and aerodynamic caches, then N rounds (default 5)
of all cases one after the other, the order rotated each round so that no case always follows
the same one. Each flexflight run writes into a fresh temporary directory, removed after.
Printed per case: the whole-process wall time (median, min, max over the rounds) and the time
the program itself reports for its solve (RocketPy: the `Flight(...)` call, `speed.py`;
flexflight: the run proper, integration and output rows, from its summary line), and the
ratios of RocketPy's figures to the case's (> 1: flexflight faster).

The cases: the thesis scenario of the issue (`subsonic_t06`, 1.0 mm fins, 10 s, key-node fins
as the file has them) with the default DOPRI5 and with `run.integrator=exponential`, each
with the scenario's 1 ms rows and with 10 ms rows (RocketPy's solution has 270 points), and
the main job (the K1000T launch, pad to landing, with its flutter margin), with its DOPRI5
and with the exponential integrator.
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
THESIS = "examples/thesis/section_6_5.vdl"
T06 = [THESIS, "--scenario", "subsonic_t06", "--set", "fins.thickness=1mm"]
EXP = ["--set", "run.integrator=exponential"]
ROWS10 = ["--set", "run.output_interval=10ms"]
CASES = [
    ("subsonic_t06 1.0 mm, DOPRI5, 1 ms rows", T06),
    ("subsonic_t06 1.0 mm, DOPRI5, 10 ms rows", T06 + ROWS10),
    ("subsonic_t06 1.0 mm, exponential, 1 ms rows", T06 + EXP),
    ("subsonic_t06 1.0 mm, exponential, 10 ms rows", T06 + EXP + ROWS10),
    ("k1000 launch to landing + flutter margin (main job)",
     ["examples/hpr_k1000/hpr_k1000.vdl", "--scenario", "k1000"]),
    ("k1000 launch to landing + flutter margin, exponential",
     ["examples/hpr_k1000/hpr_k1000.vdl", "--scenario", "k1000"] + EXP),
]
ROCKETPY = "RocketPy 1.13 rigid 10 s flight (speed.py --runs 1)"
# flexflight's last status line: "...: <stop> at t = T s (R rows, S steps, X s) -> out".
RUN_LINE = re.compile(r"\((\d+) rows, (\d+) steps, ([0-9.]+) s\)")
ROCKETPY_LINE = re.compile(r"median ([0-9.]+) s")


def flexflight_binary():
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    return os.path.join(target, "release", "flexflight")


def timed(cmd, cwd):
    t0 = time.perf_counter()
    p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stderr}")
    return wall, p.stdout + p.stderr


def run_flexflight(binary, args):
    out = tempfile.mkdtemp(prefix="ff-side-by-side-")
    try:
        # `run` refuses a non-empty output directory: give it a fresh one inside.
        wall, text = timed([binary, "run", *args, "--out", os.path.join(out, "o")], ROOT)
    finally:
        shutil.rmtree(out, ignore_errors=True)
    m = RUN_LINE.search(text)
    if not m:
        sys.exit(f"no run summary in flexflight's output:\n{text}")
    return wall, float(m.group(3)), f"{m.group(1)} rows, {m.group(2)} steps"


def run_rocketpy(python):
    wall, text = timed([python, os.path.join(HERE, "speed.py"), "--runs", "1"], HERE)
    m = ROCKETPY_LINE.search(text)
    if not m:
        sys.exit(f"no timing in speed.py's output:\n{text}")
    return wall, float(m.group(1)), "270 solution points"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--no-build", action="store_true", help="use the existing release binary")
    ap.add_argument("--json", help="also write the figures to this file")
    a = ap.parse_args()
    if a.rounds < 1:
        sys.exit("--rounds must be at least 1")
    python = subprocess.run(
        [os.path.join(HERE, "setup_venv.sh")], capture_output=True, text=True, check=True
    ).stdout.strip().splitlines()[-1]
    if not a.no_build:
        subprocess.run(["cargo", "build", "--release", "--locked", "--quiet"], cwd=ROOT, check=True)
    binary = flexflight_binary()
    jobs = [(ROCKETPY, lambda: run_rocketpy(python))] + [
        (name, (lambda args=args: run_flexflight(binary, args))) for name, args in CASES
    ]
    for _, job in jobs:  # warm the caches (and the file system)
        job()
    samples = {name: [] for name, _ in jobs}
    notes = {}
    for r in range(a.rounds):
        order = jobs[r % len(jobs):] + jobs[: r % len(jobs)]
        for name, job in order:
            wall, solve, note = job()
            samples[name].append((wall, solve))
            notes[name] = note
    rows = []
    for name, _ in jobs:
        walls = [s[0] for s in samples[name]]
        solves = [s[1] for s in samples[name]]
        rows.append({
            "case": name,
            "work": notes[name],
            "wall_median_s": statistics.median(walls),
            "wall_min_s": min(walls),
            "wall_max_s": max(walls),
            "solve_median_s": statistics.median(solves),
        })
    ref = rows[0]
    print(f"{a.rounds} rounds, whole process (wall) and the program's own solve time, medians\n")
    print("| case | work | whole process (min-max) | solve | RocketPy / case, whole | RocketPy / case, solve |")
    print("|---|---|---|---|---|---|")
    for row in rows:
        row["ratio_whole"] = ref["wall_median_s"] / row["wall_median_s"]
        row["ratio_solve"] = ref["solve_median_s"] / row["solve_median_s"]
        print(
            f"| {row['case']} | {row['work']} | {row['wall_median_s']:.3f} s "
            f"({row['wall_min_s']:.3f}-{row['wall_max_s']:.3f}) | {row['solve_median_s']:.3f} s "
            f"| {row['ratio_whole']:.2f} | {row['ratio_solve']:.2f} |"
        )
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"rounds": a.rounds, "cases": rows}, f, indent=2)


if __name__ == "__main__":
    main()
