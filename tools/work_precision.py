#!/usr/bin/env python3
"""Work-precision of the integrators on one flight (docs/performance.md, "Work-precision"):
each variant's error against a tight reference, per output a user reads, with its steps
and whole-process CPU time. Standard library only; outside `cargo test`.

    tools/work_precision.py --flexflight target/release/flexflight --case k1000 --out DIR
    tools/work_precision.py --flexflight target/release/flexflight --case thesis --out DIR

Summary outputs (summary.json): absolute differences (apogee and landing in m, max q in Pa,
off-rail speed in m/s, margins in calibres and V_F/V). History groups (history.csv): the
largest difference over the rows divided by the group's range over the reference (rows of
the ascent only for k1000: under the canopies the vehicle is a point mass; rows within 15 ms
of an event or a gust's switch skipped, where the forcing jumps). Runs are kept in DIR and
not redone.
"""
import argparse, csv, json, math, os, resource, subprocess, sys

CASES = {
    "k1000": ("examples/hpr_k1000/hpr_k1000.vdl", "k1000", [],
              [("dopri5", "1e-7", "1e-9"), ("dopri5", "1e-8", "1e-10"),
               ("exponential", "1e-7", "1e-9"), ("exponential", "1e-8", "1e-10"),
               ("exponential", "1e-8", "1e-11"), ("exponential", "1e-9", "1e-11"),
               ("exponential", "1e-9", "2e-12"), ("exponential", "1e-9", "1e-12")]),
    "thesis": ("examples/thesis/section_6_5.vdl", "subsonic_t06", ["fins.thickness=1.0 mm"],
               [("dopri5", "1e-6", "1e-9"), ("dopri5", "1e-7", "1e-10"),
                ("exponential", "1e-6", "1e-9"), ("exponential", "1e-7", "1e-10"),
                ("exponential", "1e-8", "1e-11"), ("exponential", "1e-9", "1e-12")]),
}
REFERENCE = [("dop853", "1e-12", "1e-14"), ("dopri5", "1e-11", "1e-13")]
GROUPS = [
    ("position", lambda c: c.startswith("p_inertial")),
    ("velocity", lambda c: c.startswith("v_body")),
    ("angular rate", lambda c: c.startswith("omega_body")),
    ("attitude", lambda c: c in ("q0", "q1", "q2", "q3")),
    ("eta", lambda c: c.startswith("eta_") and not c.startswith("eta_dot")),
    ("eta_dot", lambda c: c.startswith("eta_dot")),
    ("fin root stress", lambda c: c.endswith("root_stress")),
]


def fly(ff, vdl, scenario, out, sets):
    if os.path.exists(f"{out}/summary.json") and os.path.exists(f"{out}/cpu"):
        return float(open(f"{out}/cpu").read())
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    args = [ff, "run", vdl, "--scenario", scenario, "--out", out]
    for s in sets:
        args += ["--set", s]
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"{out}: {p.stderr}")
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime
    open(f"{out}/cpu", "w").write(str(cpu))
    return cpu


def outputs(d):
    s = json.load(open(f"{d}/summary.json"))
    f = s["flight"]
    o = {}
    if f["apogee"]:
        o["apogee"] = f["apogee"]["altitude"]
    if f["landing"]:
        o["landing"] = f["landing"]["position"][:2]
    o["max Mach"] = f["max_mach"]["value"]
    o["max q"] = f["max_dynamic_pressure"]["value"]
    if f["off_rail_speed"] is not None:
        o["off-rail speed"] = f["off_rail_speed"]
    o["min static margin"] = f["static_margin_calibres"]["min"]["value"]
    fm = s.get("flutter_margin")
    if fm and fm.get("computed") and fm.get("minimum"):
        o["min flutter margin"] = fm["minimum"]["speed_margin"]
    return o, s["accepted_steps"]


def history(d):
    with open(f"{d}/history.csv") as fh:
        r = csv.reader(fh)
        head = next(r)
        return head, [[float(x) for x in row] for row in r]


def errors(ref, run, t_max, skip):
    (head, a), (h2, b) = ref, run
    assert head == h2
    n = min(len(a), len(b))
    rows = [k for k in range(n) if a[k][0] <= t_max and abs(a[k][0] - b[k][0]) < 1e-9
            and all(abs(a[k][0] - t) > 0.015 for t in skip)]
    out = {}
    for name, pick in GROUPS:
        cols = [i for i, c in enumerate(head) if pick(c)]
        if not cols:
            continue
        rng = max(max(a[k][i] for k in rows) - min(a[k][i] for k in rows) for i in cols)
        worst = max(abs(a[k][i] - b[k][i]) for k in rows for i in cols
                    if math.isfinite(a[k][i]) and math.isfinite(b[k][i]))
        out[name] = worst / rng
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexflight", required=True)
    ap.add_argument("--case", choices=CASES, required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--variant", action="append", metavar="INTEGRATOR,RTOL,ATOL[,SET...]",
                    help="instead of the case's list; each further SET (e.g. run.atol=...) is passed as --set")
    a = ap.parse_args()
    vdl, scenario, base, variants = CASES[a.case]
    if a.variant:
        variants = [tuple(v.split(",")) for v in a.variant]
    os.makedirs(a.out, exist_ok=True)
    d = lambda name: f"{a.out}/" + name.replace(", ", "_").replace(" ", "_")
    def sets(it, rt, at, ab, tight):  # ab: further --set values
        s = base + [f"run.integrator={it}", f"run.rtol={rt}", f"run.atol={at}"]
        s += list(ab)
        return s + ["run.min_step=1e-15 s"] if tight else s
    names, cpu = [], {}
    for tight, group in ((True, REFERENCE), (False, variants)):
        for it, rt, at, *ab in group:
            name = f"{it} {rt}, {at}" + "".join(f", {x}" for x in ab)
            cpu[name] = fly(a.flexflight, vdl, scenario, d(name), sets(it, rt, at, ab, tight))
            names.append(name)
    ref = names[0]
    ro, _ = outputs(d(ref))
    f = json.load(open(f"{d(ref)}/summary.json"))["flight"]
    if f["apogee"]:
        t_max, skip = f["apogee"]["t"] - 0.5, [f["rail_exit"]["t"], f["burnout"]["t"]]
    else:
        t_max, skip = float("inf"), [1.0, 1.1, 5.0, 5.1]
    rh = history(d(ref))
    cols = names[1:]
    table = {}
    for name in cols:
        o, steps = outputs(d(name))
        e = {"steps": steps, "CPU s (whole process)": cpu[name]}
        for k, v in ro.items():
            e[k] = max(abs(x - y) for x, y in zip(o[k], v)) if k == "landing" else abs(o[k] - v)
        e.update(errors(rh, history(d(name)), t_max, skip))
        table[name] = e
    print(f"reference: {ref}\n")
    print("| output | " + " | ".join(cols) + " |")
    print("|---|" + "---|" * len(cols))
    for k in table[cols[0]]:
        cell = lambda v: str(v) if isinstance(v, int) else (f"{v:.2f}" if k.startswith("CPU") else f"{v:.1e}")
        print(f"| {k} | " + " | ".join(cell(table[c][k]) for c in cols) + " |")


if __name__ == "__main__":
    main()
