#!/usr/bin/env python3
"""Per channel group, the largest difference of each run's history.csv from a reference
run's, divided by the group's range over the reference flight (the measure of
docs/performance.md). Standard library only; outside `cargo test`.

    tools/history_error.py REF_DIR RUN_DIR [RUN_DIR ...]

The runs must have the same output rows (same scenario, stop and output interval); rows
where either value is not finite are skipped.
"""
import csv
import math
import sys

GROUPS = [
    ("position", lambda c: c.startswith("p_inertial")),
    ("velocity", lambda c: c.startswith("v_body")),
    ("angular rate", lambda c: c.startswith("omega_body")),
    ("attitude", lambda c: c in ("q0", "q1", "q2", "q3")),
    ("alpha, beta", lambda c: c in ("alpha", "beta")),
    ("eta", lambda c: c.startswith("eta_") and not c.startswith("eta_dot")),
    ("eta_dot", lambda c: c.startswith("eta_dot")),
    ("fin alpha", lambda c: c.startswith("fin") and c.endswith("_alpha")),
    ("fin root stress", lambda c: c.endswith("root_stress")),
    ("energies", lambda c: c in ("energy_kinetic", "energy_strain", "energy_gravitational", "energy_total")),
    ("max deformation", lambda c: c == "max_deformation"),
    ("acceleration", lambda c: c == "acceleration"),
    ("mach", lambda c: c == "mach"),
]


def load(d):
    with open(f"{d}/history.csv") as f:
        r = csv.reader(f)
        head = next(r)
        return head, [[float(x) for x in row] for row in r]


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    head, ref = load(argv[1])
    runs = []
    for d in argv[2:]:
        h, rows = load(d)
        if h != head or len(rows) != len(ref):
            sys.exit(f"{d}: other columns or rows than {argv[1]}")
        runs.append(rows)
    print("| group | " + " | ".join(argv[2:]) + " |")
    print("|---|" + "---|" * len(runs))
    for name, pick in GROUPS:
        cols = [i for i, c in enumerate(head) if pick(c)]
        if not cols:
            continue
        rng = 0.0
        for i in cols:
            vals = [r[i] for r in ref if math.isfinite(r[i])]
            if vals:
                rng = max(rng, max(vals) - min(vals))
        cells = []
        for rows in runs:
            err = 0.0
            for i in cols:
                for a, b in zip(ref, rows):
                    if math.isfinite(a[i]) and math.isfinite(b[i]):
                        err = max(err, abs(a[i] - b[i]))
            cells.append(f"{err / rng:.2g}" if rng > 0 else "n/a")
        print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main(sys.argv)
