"""Solve examples/calisto's internal point masses from RocketPy's mass model, and check them.

RocketPy (calisto.py) gives the rocket without motor (14.426 kg at x_RP = 0, I = 6.321 /
0.034 kg m^2 about it) and the motor's dry mass (1.815 kg at 0.317 m ahead of the nozzle,
I = 0.125 / 0.002 about it) and grain (centre 0.397 m ahead of the nozzle). flexflight's
motor component puts casing and grain on one cylinder (src/structure/motor.rs: the grain a
solid cylinder, the casing a thin tube, both over `length` from `position`), which in the vdl
is the grain stack: so the grain is RocketPy's (centre exact, pitch inertia 0.0957 vs 0.0969)
and the casing is 0.08 m forward of RocketPy's with a thin tube's inertia. What must agree is
what flies: the burnout vehicle (structure + casing) and the loaded one (+ grain). So the
structure's target is RocketPy's dry vehicle (rocket + motor dry) minus flexflight's casing:
mass 14.426 kg exactly, first and second moments by the parallel-axis theorem.

The structure without internal masses (tube, nose shell, fins) is compiled by flexflight
(a copy of the vdl with no point masses and no motor); three point masses at fixed stations
(payload, avionics/recovery, fin can) close mass, first moment and pitch inertia (a linear
solve; the roll inertia is shared over them as m rho^2, with pitch rho^2/2 each, a disc).
Prints the point_mass blocks; with --check compiles the vdl as it is and prints the
comparison with RocketPy (the numbers in examples/calisto/README.md).

`--case valetudo` does the same for examples/valetudo (valetudo.py's rocket; its motor's
dry mass is 1 g, so the casing compensation is nil).

`--case ndrt2020` does it for examples/ndrt2020 (ndrt2020.py's rocket, nose_to_tail) with two
point masses, which close mass and first moment only: the notebook's pitch inertia, 73.316
kg m^2 about a centre of mass 1.3 m aft of the tip, is more than 18.998 kg can have anywhere
between the tip and the nozzle (3.391 m; at most m a b = 51.6 kg m^2), so the pitch inertia
is what the structure and the two masses give, printed next to the notebook's.

Usage: python calisto_mass.py [--case calisto|valetudo|ndrt2020] [--flexflight BIN] [--check]
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import calisto  # noqa: E402
import ndrt2020  # noqa: E402
import valetudo  # noqa: E402

ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
# Per case: the RocketPy script, the example's folder and vdl, the nose tip in RocketPy's
# frame (metres, in the script's coordinate_system_orientation), the point masses' stations
# (x aft of the nose tip, negative): three close mass, first moment and pitch inertia, two
# mass and first moment only.
CASES = {
    "calisto": (calisto, "calisto", 1.278,
                [("payload", -0.40), ("avionics", -1.30), ("fin_can", -2.20)]),
    "valetudo": (valetudo, "valetudo", valetudo.NOSE_TIP,
                 [("payload", -0.30), ("avionics", -1.10), ("fin_can", -2.00)]),
    "ndrt2020": (ndrt2020, "ndrt2020", 0.0, [("payload", -0.50), ("fin_can", -3.00)]),
}


def select(name):
    global SCRIPT, EX, VDL, NOSE_TIP, STATIONS
    SCRIPT, folder, NOSE_TIP, STATIONS = CASES[name]
    EX = os.path.join(ROOT, "examples", folder)
    VDL = os.path.join(EX, folder + ".vdl")


def to_x(rocket, x_rp):
    """flexflight's x (0 at the nose tip, negative aft) of a position in RocketPy's frame."""
    return rocket._csys * (x_rp - NOSE_TIP)


def vdl_motor():
    """position (aft end x), length, diameter, propellant and total mass of the vdl's motor."""
    text = open(VDL).read()
    blk = re.search(r"motor \w+ \{(.*?)\n  \}", text, re.S).group(1)

    def num(field, unit_scale):
        m = re.search(rf"{field} = \(?(-?[\d.]+)", blk)
        return float(m.group(1)) * unit_scale

    return {
        "x_aft": num("position", 1.0),
        "length": num("length", 1e-3),
        "diameter": num("diameter", 1e-3),
        "propellant": num("propellant_mass", 1.0),
        "total": num("total_mass", 1.0),
    }


def compile_json(ff, text):
    tmp = tempfile.mkdtemp(prefix="calisto_mass_")
    try:
        for f in os.listdir(EX):
            if f.endswith((".eng", ".csv")):
                shutil.copy(os.path.join(EX, f), tmp)
        p = os.path.join(tmp, os.path.basename(VDL))
        open(p, "w").write(text)
        r = subprocess.run(
            [ff, "compile", p, "--format", "json", "--cache-dir", os.path.join(tmp, "cache")],
            capture_output=True, text=True,
        )
        if r.returncode != 0:
            sys.exit(f"flexflight compile failed:\n{r.stdout}\n{r.stderr}")
        return json.loads(r.stdout)
    finally:
        shutil.rmtree(tmp)


def props(j):
    return j["total_mass_kg"], j["centre_of_mass_m"][0], j["inertia_cm_kg_m2"][1][1], j["inertia_cm_kg_m2"][0][0]


def targets():
    _env, motor, rocket = SCRIPT.build()
    m_r = rocket.mass
    x_r = to_x(rocket, rocket.center_of_mass_without_motor)
    i_r, i_r33 = rocket.I_11_without_motor, rocket.I_33_without_motor
    m_d = motor.dry_mass
    x_d = to_x(rocket, rocket.motor_center_of_dry_mass_position)
    m_dry = m_r + m_d
    x_dry = (m_r * x_r + m_d * x_d) / m_dry
    i_dry = i_r + m_r * (x_r - x_dry) ** 2 + motor.dry_I_11 + m_d * (x_d - x_dry) ** 2
    m_p = float(motor.propellant_initial_mass)
    x_p = to_x(rocket, rocket.motor_position
               + motor.grains_center_of_mass_position * rocket._csys * motor._csys)
    m_0 = m_dry + m_p
    x_0 = (m_dry * x_dry + m_p * x_p) / m_0
    i_0 = i_dry + m_dry * (x_dry - x_0) ** 2 + float(motor.propellant_I_11(0)) + m_p * (x_p - x_0) ** 2
    # RocketPy's own I_11(t) is about the centre of DRY mass (rocket.evaluate_inertias):
    i_0_rp_cdm = float(rocket.I_11(0))
    assert abs(i_0 + m_0 * (x_0 - x_dry) ** 2 - i_0_rp_cdm) < 1e-9, "inertia bookkeeping"
    return {
        "rocket": (m_r, x_r, i_r, i_r33),
        "dry": (m_dry, x_dry, i_dry, float(rocket.dry_I_33)),
        "loaded": (m_0, x_0, i_0, float(rocket.I_33(0))),
        "rocketpy_I11_0_about_dry_cm": i_0_rp_cdm,
    }


def casing(mot):
    m = mot["total"] - mot["propellant"]
    x = mot["x_aft"] + mot["length"] / 2
    d, l = mot["diameter"], mot["length"]
    return m, x, m * (d * d / 8 + l * l / 12), m * d * d / 4


def solve(ff):
    t = targets()
    mot = vdl_motor()
    m_dry, x_dry, i_dry, i33_dry = t["dry"]
    m_c, x_c, i_c, i33_c = casing(mot)
    m_s = m_dry - m_c
    x_s = (m_dry * x_dry - m_c * x_c) / m_s
    i_s = i_dry + m_dry * (x_dry - x_s) ** 2 - i_c - m_c * (x_c - x_s) ** 2
    i33_s = i33_dry - i33_c
    text = open(VDL).read()
    text = re.sub(r"\n      point_mass .*?\n      \}\n", "\n", text, flags=re.S)
    text = re.sub(r"\n  motor \w+ \{.*?\n  \}\n", "\n", text, flags=re.S)
    m0, c0, i0, i33_0 = props(compile_json(ff, text))
    # Moments about the nose tip: sum m_k = A, sum m_k x_k = B, sum m_k (x_k^2 + rho^2/2) = C.
    a = m_s - m0
    b = m_s * x_s - m0 * c0
    rho2 = (i33_s - i33_0) / a
    c = (i_s + m_s * x_s**2) - (i0 + m0 * c0**2)
    xs = np.array([x for _, x in STATIONS])
    mat = np.vstack([np.ones(len(xs)), xs, xs**2 + rho2 / 2])[: len(xs)]
    mk = np.linalg.solve(mat, np.array([a, b, c])[: len(xs)])
    out = {"structure_target": [m_s, x_s, i_s, i33_s], "bare_structure": [m0, c0, i0, i33_0],
           "rho2": rho2, "masses": dict(zip([n for n, _ in STATIONS], mk.tolist()))}
    if len(xs) == 2:
        # Mass and first moment closed; the pitch inertia about x_s is what follows.
        c_got = float(np.sum(mk * (xs**2 + rho2 / 2)))
        out["structure_pitch_inertia_reached"] = c_got + i0 + m0 * c0**2 - m_s * x_s**2
    print(json.dumps(out, indent=2))
    if np.any(mk <= 0) or rho2 <= 0:
        sys.exit("no positive solution at these stations")
    for (name, x), m in zip(STATIONS, mk):
        ixx = m * rho2
        print(f"      point_mass {name} {{\n        position = ({x}, 0, 0) m\n        mass = {m:.6f} kg\n"
              f"        inertia = ({ixx:.6f}, {ixx / 2:.6f}, {ixx / 2:.6f}) kg*m^2\n      }}\n")


def check(ff):
    t = targets()
    j = compile_json(ff, open(VDL).read())
    ff_loaded = props(j)
    text = re.sub(r"\n  motor \w+ \{.*?\n  \}\n", "\n", open(VDL).read(), flags=re.S)
    ff_struct = props(compile_json(ff, text))
    mot = vdl_motor()
    m_c, x_c, i_c, i33_c = casing(mot)
    m_s, x_s, i_s, i33_s = ff_struct
    m = m_s + m_c
    x = (m_s * x_s + m_c * x_c) / m
    i = i_s + m_s * (x_s - x) ** 2 + i_c + m_c * (x_c - x) ** 2
    ff_dry = (m, x, i, i33_s + i33_c)
    rows = []
    for label, rp, ff_v in (("dry (burnout)", t["dry"], ff_dry), ("loaded (ignition)", t["loaded"], ff_loaded)):
        rows.append({"state": label, "rocketpy": rp, "flexflight": ff_v})
    print(json.dumps({"rows": rows, "rocketpy_I11_0_about_dry_cm": t["rocketpy_I11_0_about_dry_cm"],
                      "structure_alone": ff_struct}, indent=2))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexflight", default=os.path.join(ROOT, "target", "debug", "flexflight"))
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--case", choices=sorted(CASES), default="calisto")
    a = ap.parse_args()
    select(a.case)
    (check if a.check else solve)(a.flexflight)


if __name__ == "__main__":
    main()
