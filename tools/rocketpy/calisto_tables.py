"""Derive flexflight's aerodynamic tables for examples/calisto from RocketPy 1.13.0 itself.

The rocket is calisto.py's (`build()`); nothing is typed in twice. RocketPy's aerodynamics
(rocketpy/rocket/rocket.py, rocketpy/rocket/aero_surface/*):

* the axial force is the drag curve: `R3 = -q S C_D(M)` along the body axis, whatever the
  angle of attack (Flight.u_dot), power-on before burnout and power-off after;
* each aerodynamic surface (nose, fin set, tail) puts a normal force `q S C_Nα,i(M) α_i` at its
  own centre of pressure, `α_i` the total angle of attack of the air velocity AT that surface
  (body velocity plus ω × r), linear in α at any α (Barrowman's slopes; the fins' with the
  NACA 0012 lift slope, the Diederich/Prandtl-Glauert aspect-ratio formula, the fin-body
  interference factor `1 + r/(s + r)` and OpenRocket's n/2 fin-number factor).

flexflight's table model (docs/language.md, "Aerodynamic coefficient tables"):

* body table (fuselage alone = RocketPy's nose + tail, about `reference_point`, on S and d):
  `ca = C_D(M)`; `cn = (C_Nα,nose + C_Nα,tail) α`; `cm = cn (x_cp,body - x_ref)/d` (x forward,
  thesis (5.3.3)); the rate columns reproduce RocketPy's surface-local angle of attack of
  the nose and the tail for a rotation about the reference point, `Δα_i = -q (x_i - x_ref)/V`:
  `cn_q = Σ 2 C_Nα,i (x_ref - x_i)/d`, `cm_q = -Σ 2 C_Nα,i ((x_i - x_ref)/d)²` (per rad of
  `ω d/(2V)`);
* fin table (ONE fin at its own angle of attack α_f, interference included): RocketPy's fin
  set is `n/2 · K · C_Nα,1` (n = 4: two fins in the pitch plane see α_f = ±α, the other two
  α_f = 0, the same total at any roll), so one fin is `cn = K C_Nα,1(M) α_f`; `ca = 0` (all of
  the drag is in the body table); `x_cp_m` is RocketPy's Barrowman `cpz` aft of the root
  leading edge. The fins' own local velocity gives their pitch damping in both programs.

Grid: the drag curve's own Mach points (RocketPy interpolates it linearly, so the tables
give the same C_D), angle of attack 0..180 deg (body) and -180..180 deg (fin) at points where
linear interpolation of a linear function is exact, two altitudes with the same values. Writes examples/calisto/calisto_body.csv and calisto_fins.csv and prints the
surfaces' numbers as JSON.

Usage: python calisto_tables.py [--out DIR]
"""

import argparse
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import calisto  # noqa: E402

from rocketpy.rocket.aero_surface import NoseCone, Tail, TrapezoidalFins  # noqa: E402

# x here = x_RocketPy - NOSE_TIP: 0 at the nose tip, negative aft (the vdl's body frame).
NOSE_TIP = 1.278
REFERENCE_X = -1.39315  # the vdl's aero reference_point (the body key node, README)
BODY_ALPHA = [0, 1, 2, 5, 10, 20, 45, 90, 135, 180]
FIN_ALPHA = [-a for a in reversed(BODY_ALPHA[1:])] + BODY_ALPHA
# Nothing depends on altitude; two rows spanning flexflight's atmosphere (-500 m .. 86 km)
# because a one-value axis is a range of one point to the `stop` policy (README).
ALTITUDES = [-500, 86000]


def read_curve(path):
    return np.loadtxt(path, delimiter=",")


def surfaces(rocket):
    """(name, kind, C_Nα(M) callable, x of the centre of pressure in the vdl frame, extra)."""
    out = []
    csys = rocket._csys
    for s, pos in rocket.aerodynamic_surfaces:
        z = pos.z if hasattr(pos, "z") else pos[2]
        x_cp = (z - csys * s.cpz) - NOSE_TIP
        out.append((s, z, x_cp))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(HERE, "..", "..", "examples", "calisto"))
    a = ap.parse_args()
    _env, _motor, rocket = calisto.build()
    d = 2 * rocket.radius
    off = read_curve(os.path.join(calisto.DATA, "powerOffDragCurve.csv"))
    on = read_curve(os.path.join(calisto.DATA, "powerOnDragCurve.csv"))
    same_drag = off.shape == on.shape and bool(np.all(off == on))
    machs = off[:, 0]

    nose_tail = []
    fins = None
    for s, z, x_cp in surfaces(rocket):
        if isinstance(s, TrapezoidalFins):
            fins = (s, z, x_cp)
        elif isinstance(s, (NoseCone, Tail)):
            nose_tail.append((s, z, x_cp))
        else:
            sys.exit(f"unexpected aerodynamic surface {type(s).__name__}")
    if fins is None or fins[0].n != 4:
        sys.exit("the table model below is written for one set of 4 fins")

    # Check that these centres of pressure are RocketPy's: its cp_position from them.
    for m in (0.0, 0.5, 0.8):
        num = sum(s.clalpha(m) * (x + NOSE_TIP) for s, _, x in nose_tail + [fins])
        den = sum(s.clalpha(m) for s, _, _ in nose_tail + [fins])
        if abs(num / den - rocket.cp_position(m)) > 1e-9:
            sys.exit(f"centre of pressure mismatch at M {m}: {num / den} vs {rocket.cp_position(m)}")

    body_rows = []
    fin_rows = []
    for m, cd in zip(machs, off[:, 1]):
        cna = [float(s.clalpha(m)) for s, _, _ in nose_tail]
        xs = [x for _, _, x in nose_tail]
        cna_b = sum(cna)
        x_cp_b = sum(c * x for c, x in zip(cna, xs)) / cna_b
        cn_q = sum(2 * c * (REFERENCE_X - x) / d for c, x in zip(cna, xs))
        cm_q = -sum(2 * c * ((x - REFERENCE_X) / d) ** 2 for c, x in zip(cna, xs))
        for al in BODY_ALPHA:
            cn = cna_b * math.radians(al)
            cm = cn * (x_cp_b - REFERENCE_X) / d
            for h in ALTITUDES:
                body_rows.append((m, al, h, cn, cd, cm, cn_q, cm_q))
        s = fins[0]
        cna_1 = float(s.lift_interference_factor * s.clalpha_single_fin(m))
        for al in FIN_ALPHA:
            for h in ALTITUDES:
                fin_rows.append((m, al, h, cna_1 * math.radians(al), 0.0, float(s.cpz)))

    prov = (
        "# derived from RocketPy 1.13.0 by tools/rocketpy/calisto_tables.py (calisto.py's rocket);"
        " see examples/calisto/README.md\n"
    )
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "calisto_body.csv"), "w") as fh:
        fh.write(prov)
        fh.write(f"# nose + tail: C_D(M) = powerOffDragCurve.csv, reference point x = {REFERENCE_X} m\n")
        fh.write("mach,alpha_deg,altitude_m,cn,ca,cm,cn_q,cm_q\n")
        for m, al, h, cn, ca, cm, q1, q2 in body_rows:
            fh.write(f"{m:.6g},{al},{h},{cn:.12g},{ca:.12g},{cm:.12g},{q1:.12g},{q2:.12g}\n")
    with open(os.path.join(a.out, "calisto_fins.csv"), "w") as fh:
        fh.write(prov)
        fh.write("# one fin: K * C_Nalpha,1(M) * alpha_f, Barrowman cpz\n")
        fh.write("mach,alpha_deg,altitude_m,cn,ca,x_cp_m\n")
        for m, al, h, cn, ca, x in fin_rows:
            fh.write(f"{m:.6g},{al},{h},{cn:.12g},{ca:.12g},{x:.12g}\n")

    info = {
        "reference_area_m2": rocket.area,
        "reference_length_m": d,
        "power_on_equals_power_off": same_drag,
        "surfaces": [
            {"name": s.name, "kind": type(s).__name__, "x_cp_m": x,
             "cn_alpha_M0": float(s.clalpha(0.0)), "cn_alpha_M0.8": float(s.clalpha(0.8))}
            for s, _, x in nose_tail + [fins]
        ],
        "fin_interference_factor": float(fins[0].lift_interference_factor),
        "fin_cpz_m": float(fins[0].cpz),
        "rocket_cp_M0_rocketpy_m": float(rocket.cp_position(0.0)),
        "total_cn_alpha_M0": float(rocket.total_lift_coeff_der(0.0)),
    }
    print(json.dumps(info, indent=2))


if __name__ == "__main__":
    main()
