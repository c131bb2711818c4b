"""The centre of pressure and static margin over Mach of the example rockets, flexflight's
built-in aerodynamics beside RocketPy's Barrowman model of the same geometry (issue 33,
item 4). Outside `cargo test`; RocketPy in its own venv (`setup_venv.sh`).

    tools/rocketpy/.venv/bin/python tools/rocketpy/static_margin_mach.py [--flexflight BIN]

flexflight's centre of pressure is read from a flight: every history row's static margin
is `(x_cg - x_cp) / d` at its own Mach (`aero::static_margin`), so `x_cp = cm_body_x - d sm`;
the rows of the boost (Mach rising) give `x_cp(M)` up to the flight's largest Mach, and it is
interpolated linearly in Mach. RocketPy's is `Rocket.cp_position(M)` of a rocket with the same
nose, body diameter and fins (its other inputs do not enter the centre of pressure). Both
static margins are then taken about one centre of mass, flexflight's at burnout, so the
table compares aerodynamics only. Positions are metres aft of the nose tip.
"""

import argparse
import csv
import os
import subprocess
import sys
import tempfile

from rocketpy import Rocket

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

# name: (vdl, scenario, --set overrides, geometry for RocketPy)
# geometry: diameter d, nose (length, RocketPy kind), fins (n, root, tip, span, sweep length
# of the leading edge, root leading edge aft of the tip)
CASES = {
    "hpr_k1000": ("examples/hpr_k1000/hpr_k1000.vdl", "k1000", [],
                  dict(d=0.098, nose=(0.45, "conical"), fins=(3, 0.25, 0.10, 0.12, 0.15, 1.65))),
    # The 4-fin M1670 rocket of issue 33 with 3.2 mm fins (its vdl: these do not flutter, so
    # the flight reaches its largest Mach; the thickness does not enter the centre of
    # pressure).
    "m1670_4fin": ("examples/m1670_4fin/m1670_4fin.vdl", "flight", ["fins.thickness=3.2 mm"],
                   dict(d=0.102, nose=(0.40, "conical"),
                        fins=(4, 0.203, 0.076, 0.102, 0.102 * 0.80498, 2.197))),
    "valetudo": ("examples/valetudo/valetudo.vdl", "valetudo", [],
                 dict(d=0.0809, nose=(0.274, "tangent"), fins=(3, 0.058, 0.018, 0.077, 0.040, 2.040))),
}
MACHS = [0.1, 0.3, 0.5, 0.7, 0.9, 1.0, 1.1, 1.2, 1.3, 1.5]


def flexflight_cp(binary, vdl, scenario, sets):
    out = tempfile.mkdtemp(prefix="sm_mach_")
    cmd = [binary, "run", os.path.join(ROOT, vdl), "--scenario", scenario, "--no-flutter-margin",
           "--out", out]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, capture_output=True)
    with open(os.path.join(out, "history.csv")) as fh:
        rows = list(csv.DictReader(fh))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexflight", default=os.path.join(ROOT, "target", "release", "flexflight"))
    a = ap.parse_args()
    print("| rocket | Mach | x_cp flexflight (m) | x_cp RocketPy (m) | static margin flexflight (cal) | RocketPy (cal) | diff (cal) |")
    print("|---|---|---|---|---|---|---|")
    for name, (vdl, scenario, sets, g) in CASES.items():
        rows = flexflight_cp(a.flexflight, vdl, scenario, sets)
        d = g["d"]
        # The boost: rows off the rail while the Mach rises, up to the largest Mach.
        pts = []
        best = 0.0
        for r in rows:
            m = float(r["mach"])
            if m > best + 1e-9:
                best = m
                sm = float(r["static_margin"])
                if sm == sm:  # not NaN
                    pts.append((m, float(r["cm_body_x"]) - d * sm))
        x_cg = float(rows[-1]["cm_body_x"])  # burnout (and landing) centre of mass
        n, root, tip, span, sweep, le = g["fins"]
        rp = Rocket(radius=d / 2, mass=1.0, inertia=(1, 1, 0.01), power_off_drag=0.5,
                    power_on_drag=0.5, center_of_mass_without_motor=1.0,
                    coordinate_system_orientation="nose_to_tail")
        rp.add_nose(length=g["nose"][0], kind=g["nose"][1], position=0.0)
        rp.add_trapezoidal_fins(n=n, root_chord=root, tip_chord=tip, span=span, position=le,
                                sweep_length=sweep)
        for mach in MACHS:
            if mach > pts[-1][0] or mach < pts[0][0]:
                continue
            k = next(i for i, p in enumerate(pts) if p[0] >= mach)
            (m0, x0), (m1, x1) = pts[max(k - 1, 0)], pts[k]
            x_ff = x0 if m1 == m0 else x0 + (x1 - x0) * (mach - m0) / (m1 - m0)
            cp_ff = -x_ff
            cp_rp = float(rp.cp_position(mach))
            sm_ff = (cp_ff + x_cg) / d
            sm_rp = (cp_rp + x_cg) / d
            print(f"| {name} | {mach:.1f} | {cp_ff:.4f} | {cp_rp:.4f} | {sm_ff:.2f} | {sm_rp:.2f} | {sm_ff - sm_rp:+.2f} |")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
