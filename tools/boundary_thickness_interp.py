#!/usr/bin/env python3
"""How well the K1000T's flutter boundary interpolates in fin thickness (docs/performance.md,
Monte Carlo, structural dispersion). Runs the `k1000` flight of examples/hpr_k1000 at three
node thicknesses (1.85, 2.0, 2.15 mm: the range of `k1000_mc`'s truncated normal) and six
between them, each with its own cold flutter boundary, then compares every boundary cell
(flutter speed on the Mach x altitude grid, cells at a grid bound left out) with the
interpolation of the nodes' cells in log t (quadratic through the three, and linear between
the two adjacent), and the minimum flutter margin with its quadratic interpolation in t.
Standard library only; outside `cargo test`; about 20 s CPU a thickness.

    tools/boundary_thickness_interp.py --flexflight target/release/flexflight --out DIR
"""
import argparse, json, math, os, subprocess

NODES = [1.85, 2.0, 2.15]
TESTS = [1.8875, 1.925, 1.9625, 2.0375, 2.075, 2.1125]


def lagrange(ts, ys, x):
    total = 0.0
    for i, (ti, yi) in enumerate(zip(ts, ys)):
        w = 1.0
        for j, tj in enumerate(ts):
            if j != i:
                w *= (x - tj) / (ti - tj)
        total += w * yi
    return total


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexflight", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    runs = {}
    for t in NODES + TESTS:
        d = f"{a.out}/t_{t}"
        if not os.path.exists(f"{d}/summary.json"):
            subprocess.run([a.flexflight, "run", "examples/hpr_k1000/hpr_k1000.vdl", "--scenario", "k1000",
                            "--set", f"fins.thickness={t} mm", "--out", d,
                            "--cache-dir", f"{a.out}/cache"], check=True, capture_output=True)
        fm = json.load(open(f"{d}/summary.json"))["flutter_margin"]
        runs[t] = (fm["boundary"], fm["minimum"]["speed_margin"])
    n = len(runs[2.0][0]["flutter_speeds"])
    valid = [k for k in range(n) if not any(runs[t][0]["upper_bound"][k] or runs[t][0]["lower_bound"][k]
                                             for t in NODES + TESTS)]
    print(f"{len(valid)} of {n} boundary cells inside the grid's speed range at every thickness")
    for t in TESTS:
        b, m = runs[t]
        eq = el = 0.0
        lo, hi = (NODES[0], NODES[1]) if t < NODES[1] else (NODES[1], NODES[2])
        for k in valid:
            ex = b["flutter_speeds"][k]
            q = math.exp(lagrange([math.log(x) for x in NODES],
                                  [math.log(runs[x][0]["flutter_speeds"][k]) for x in NODES], math.log(t)))
            l = math.exp(lagrange([math.log(lo), math.log(hi)],
                                  [math.log(runs[x][0]["flutter_speeds"][k]) for x in (lo, hi)], math.log(t)))
            eq, el = max(eq, abs(q / ex - 1)), max(el, abs(l / ex - 1))
        mq = lagrange(NODES, [runs[x][1] for x in NODES], t)
        print(f"t {t} mm: boundary, largest relative error: quadratic {eq:.1e}, linear {el:.1e}; "
              f"min margin {m:.6f}, interpolated {mq:.6f} ({mq - m:+.1e})")


if __name__ == "__main__":
    main()
