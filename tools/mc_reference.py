#!/usr/bin/env python3
"""The statistics of a Monte Carlo's fast path against a tight-tolerance reference run of the
same samples (issue 35 item 5; docs/montecarlo.md). Standard library only; outside
`cargo test`.

    tools/mc_reference.py FAST_DIR REF_DIR

Both directories are `flexflight montecarlo` outputs of the same dispersion, seed and sample
count (for example the dispersion as written, and the same with `--set run.integrator=dopri5
--set run.rtol=1e-11 --set run.atol=1e-13 --set run.min_step=1e-15s`). The drawn inputs must be
the same bits. For each output: the largest difference between the two runs over the samples,
the difference of the means against the reference's standard error of the mean (s/sqrt n),
of the standard deviations against the standard error of s (s/sqrt(2(n-1)), normal theory),
of the 5/50/95 % percentiles against the sample spread; and the counts behind P(margin <
1.15) and P(flutter).
"""
import csv
import math
import sys

OUTPUTS = [
    ("apogee_m", "apogee [m]"),
    ("max_mach", "max Mach"),
    ("max_q_pa", "max q [Pa]"),
    ("off_rail_speed_m_s", "off-rail speed [m/s]"),
    ("min_static_margin_cal", "min static margin [cal]"),
    ("landing_x_m", "landing x [m]"),
    ("landing_y_m", "landing y [m]"),
    ("flutter_margin_min", "min flutter margin"),
]


def load(d):
    with open(f"{d}/samples.csv") as f:
        r = csv.DictReader(f)
        return r.fieldnames, list(r)


def num(s):
    try:
        x = float(s)
    except ValueError:
        return None
    return x if math.isfinite(x) else None


def percentile(v, p):
    # Hyndman & Fan definition 7, as statistics.json.
    s = sorted(v)
    h = (len(s) - 1) * p
    lo = math.floor(h)
    hi = min(lo + 1, len(s) - 1)
    return s[lo] + (h - lo) * (s[hi] - s[lo])


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    head_f, fast = load(argv[1])
    head_r, ref = load(argv[2])
    if head_f != head_r or len(fast) != len(ref):
        sys.exit("the two runs have other columns or sample counts")
    inputs = head_f[2 : head_f.index("status")]
    for a, b in zip(fast, ref):
        if a["index"] != b["index"] or any(a[c] != b[c] for c in inputs):
            sys.exit(f"sample {a['index']}: other drawn inputs")
    both = [(a, b) for a, b in zip(fast, ref) if a["status"] == "ok" and b["status"] == "ok"]
    print(f"{len(fast)} samples, {len(both)} ok in both runs; "
          f"failed: fast {sum(a['status'] != 'ok' for a in fast)}, "
          f"reference {sum(b['status'] != 'ok' for b in ref)}")
    print("| output | max difference over the samples | mean: difference / its standard error "
          "| std: difference / its standard error | p5, p50, p95: largest difference / std |")
    print("|---|---|---|---|---|")
    worst = 0.0
    for col, label in OUTPUTS:
        pairs = [(num(a[col]), num(b[col])) for a, b in both]
        pairs = [(x, y) for x, y in pairs if x is not None and y is not None]
        n = len(pairs)
        if n < 2:
            continue
        xs = [x for x, _ in pairs]
        ys = [y for _, y in pairs]
        mean_x, mean_y = sum(xs) / n, sum(ys) / n
        sd_x = math.sqrt(sum((x - mean_x) ** 2 for x in xs) / (n - 1))
        sd_y = math.sqrt(sum((y - mean_y) ** 2 for y in ys) / (n - 1))
        dmax = max(abs(x - y) for x, y in pairs)
        se_mean = sd_y / math.sqrt(n)
        se_sd = sd_y / math.sqrt(2 * (n - 1))
        dp = max(abs(percentile(xs, p) - percentile(ys, p)) for p in (0.05, 0.5, 0.95))
        r_mean = abs(mean_x - mean_y) / se_mean if se_mean > 0 else 0.0
        r_sd = abs(sd_x - sd_y) / se_sd if se_sd > 0 else 0.0
        worst = max(worst, r_mean, r_sd)
        print(f"| {label} | {dmax:.2e} | {r_mean:.1e} | {r_sd:.1e} | {dp / sd_y if sd_y > 0 else 0:.1e} |")

    def count(rows, pred):
        return sum(1 for r in rows if pred(r))

    below = lambda r: r["status"] == "ok" and (num(r["flutter_margin_min"]) or math.inf) < 1.15
    flutter = lambda r: r["verdict"] == "flutter"
    print(f"P(margin < 1.15): fast {count(fast, below)}/{len(fast)}, reference {count(ref, below)}/{len(ref)}")
    print(f"P(flutter): fast {count(fast, flutter)}/{len(fast)}, reference {count(ref, flutter)}/{len(ref)}")
    print(f"largest difference of a mean or a standard deviation: {worst:.1e} of its standard error")


if __name__ == "__main__":
    main(sys.argv)
