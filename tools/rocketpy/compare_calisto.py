#!/usr/bin/env python3
"""Calisto side by side: RocketPy 1.13.0 (calisto.py) against flexflight (examples/calisto).

Sets up tools/rocketpy/.venv if it is missing (setup_venv.sh), runs RocketPy's flight, runs
`flexflight run examples/calisto/calisto.vdl --scenario calisto` with RocketPy's aerodynamics
as tables (calisto_tables.py) and, for a second column, the same flight with flexflight's
built-in estimator (a copy of the vdl with `aero { source = builtin }`), and prints a side-by-side table (the
Markdown of docs/validation.md, "Calisto against RocketPy", with --markdown).

Only the standard library is needed here; RocketPy runs in the venv. The flexflight binary is
$FLEXFLIGHT, else target/release/flexflight, else target/debug/flexflight (build it first).

Usage: python3 tools/rocketpy/compare_calisto.py [--markdown] [--keep DIR]
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
VDL = os.path.join(ROOT, "examples", "calisto", "calisto.vdl")


def flexflight_bin():
    env = os.environ.get("FLEXFLIGHT")
    if env:
        return env
    tgt = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    for prof in ("release", "debug"):
        p = os.path.join(tgt, prof, "flexflight")
        if os.path.exists(p):
            return p
    sys.exit("no flexflight binary: `cargo build --release` (or set FLEXFLIGHT)")


def rocketpy(work):
    py = subprocess.run(
        ["bash", os.path.join(HERE, "setup_venv.sh")], check=True, capture_output=True, text=True
    ).stdout.strip().splitlines()[-1]
    out = os.path.join(work, "rocketpy.json")
    subprocess.run([py, os.path.join(HERE, "calisto.py"), "--json", out], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return json.load(open(out))


BUILTIN_AERO = """  aero {
    source = builtin
    reference_length = 127 mm
    reference_point = (-1.39315, 0, 0) m
  }
"""


def vdl_variant(work, name, builtin):
    """The vdl as it is, or a copy (with its motor and tables) whose aero block is the
    built-in estimator's (a vehicle's `aero.source` cannot be overridden while it names
    tables)."""
    if not builtin:
        return VDL
    d = os.path.join(work, name + "_vdl")
    os.makedirs(d, exist_ok=True)
    src = os.path.dirname(VDL)
    for f in os.listdir(src):
        if f.endswith((".eng", ".csv")):
            shutil.copy(os.path.join(src, f), d)
    text = open(VDL).read()
    text, n = re.subn(r"  aero \{\n.*?\n  \}\n", BUILTIN_AERO, text, count=1, flags=re.S)
    if n != 1:
        sys.exit("no aero block found in the vdl")
    p = os.path.join(d, "calisto.vdl")
    open(p, "w").write(text)
    return p


def flexflight(work, name, sets=(), builtin=False):
    out = os.path.join(work, name)
    cmd = [flexflight_bin(), "run", vdl_variant(work, name, builtin), "--scenario", "calisto",
           "--out", out, "--cache-dir", os.path.join(work, "cache")]
    for s in sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"flexflight run ({name}) failed:\n{r.stdout}\n{r.stderr}")
    s = json.load(open(os.path.join(out, "summary.json")))
    if s["stop_reason"] != "ground":
        sys.exit(f"flexflight run ({name}) did not reach the ground: {s['stop_detail']}")
    return s


def ff_values(s):
    f = s["flight"]
    sm = f["static_margin_calibres"]
    land = f.get("landing") or {}
    return {
        "apogee": f["apogee"]["height"],
        "apogee_t": f["apogee"]["t"],
        "burnout_t": f["burnout"]["t"],
        "burnout_v": f["burnout"]["speed"],
        "max_mach": f["max_mach"]["value"],
        "max_mach_t": f["max_mach"]["t"],
        "rail_v": f["off_rail_speed"],
        "rail_t": f["rail_exit"]["t"],
        "max_q": f["max_dynamic_pressure"]["value"] / 1000,
        "max_q_t": f["max_dynamic_pressure"]["t"],
        "max_acc": f["max_acceleration"]["value"],
        "sm_rail": sm["at_rail_exit"],
        "sm_max_q": sm["at_max_q"],
        "sm_min": (sm.get("min") or {}).get("value"),
        "land_t": land.get("t"),
        "land_n": (land.get("position") or [None, None])[0],
        "land_e": (land.get("position") or [None, None])[1],
        "land_v": land.get("speed"),
        "m0": s["mass"]["initial_kg"],
        "m1": s["mass"]["final_kg"],
    }


def rp_values(r):
    land = r.get("landing") or {}
    return {
        "apogee": r["apogee_m_agl"],
        "apogee_t": r["apogee_time_s"],
        "burnout_t": r["burnout_time_s"],
        "burnout_v": r["burnout_speed_m_s"],
        "max_mach": r["max_mach"],
        "max_mach_t": r["max_mach_time_s"],
        "rail_v": r["out_of_rail_speed_m_s"],
        "rail_t": r["out_of_rail_time_s"],
        "max_q": r["max_dynamic_pressure_pa"] / 1000,
        "max_q_t": r["max_dynamic_pressure_time_s"],
        "max_acc": r["max_acceleration_m_s2"],
        "sm_rail": r["stability_margin_at_rail_exit_cal"],
        "sm_max_q": r["stability_margin_at_max_q_cal"],
        "sm_min": r["min_stability_margin_cal"],
        "land_t": land.get("t"),
        "land_n": land.get("north_m"),
        "land_e": land.get("east_m"),
        "land_v": land.get("speed_m_s"),
        "m0": None,
        "m1": None,
        "rail_eff": r["effective_rail_length_m"],
    }


ROWS = [
    ("apogee", "apogee AGL (m)", "{:.1f}"),
    ("apogee_t", "time of apogee (s)", "{:.2f}"),
    ("burnout_v", "burnout speed (m/s)", "{:.1f}"),
    ("burnout_t", "burnout time (s)", "{:.3f}"),
    ("max_mach", "max Mach", "{:.4f}"),
    ("max_mach_t", "time of max Mach (s)", "{:.2f}"),
    ("rail_v", "off-rail speed (m/s)", "{:.2f}"),
    ("rail_t", "off-rail time (s)", "{:.3f}"),
    ("max_q", "max dynamic pressure (kPa)", "{:.2f}"),
    ("max_q_t", "time of max q (s)", "{:.2f}"),
    ("max_acc", "max acceleration (m/s^2)", "{:.1f}"),
    ("sm_rail", "static margin off the rail (cal)", "{:.3f}"),
    ("sm_max_q", "static margin at max q (cal)", "{:.3f}"),
    ("sm_min", "min static margin, rail exit to apogee (cal)", "{:.3f}"),
    ("land_t", "landing time (s)", "{:.1f}"),
    ("land_n", "landing north of the pad (m)", "{:.1f}"),
    ("land_e", "landing east of the pad (m)", "{:.1f}"),
    ("land_v", "landing speed (m/s)", "{:.2f}"),
]


def cell(fmt, v):
    return "-" if v is None else fmt.format(v)


def diff(a, b):
    if a is None or b is None or b == 0:
        return "-"
    return f"{100 * (a - b) / abs(b):+.2f} %"


def table(rp, ft, fb, markdown):
    head = ["", "RocketPy 1.13.0", "flexflight (RocketPy's tables)", "diff", "flexflight (builtin)", "diff"]
    lines = []
    for key, label, fmt in ROWS:
        lines.append([label, cell(fmt, rp[key]), cell(fmt, ft[key]), diff(ft[key], rp[key]),
                      cell(fmt, fb[key]), diff(fb[key], rp[key])])
    if markdown:
        out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        out += ["| " + " | ".join(r) + " |" for r in lines]
        return "\n".join(out)
    w = [max(len(r[i]) for r in lines + [head]) for i in range(len(head))]
    fmt_row = lambda r: "  ".join(c.ljust(w[i]) if i == 0 else c.rjust(w[i]) for i, c in enumerate(r))
    return "\n".join([fmt_row(head)] + [fmt_row(r) for r in lines])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--keep", help="keep the run directories here")
    a = ap.parse_args()
    work = a.keep or tempfile.mkdtemp(prefix="calisto_compare_")
    os.makedirs(work, exist_ok=True)
    try:
        rp = rp_values(rocketpy(work))
        ft = ff_values(flexflight(work, "tables"))
        fb = ff_values(flexflight(work, "builtin", builtin=True))
        # RocketPy's rail: the vehicle is free when its upper rail button leaves the rail,
        # after `rail_length - |nozzle - upper button|` (Flight.effective_1rl); flexflight's
        # after the whole rail_length. The same flight on RocketPy's effective length:
        fr = ff_values(flexflight(work, "rail", [f"launch.rail_length={rp['rail_eff']} m"]))
        print(table(rp, ft, fb, a.markdown))
        print()
        print(f"flexflight mass: {ft['m0']:.4f} kg at ignition, {ft['m1']:.4f} kg at the end")
        print(
            f"with rail_length = {rp['rail_eff']:.4f} m (RocketPy's effective rail): off-rail "
            f"{fr['rail_v']:.2f} m/s at {fr['rail_t']:.3f} s ({diff(fr['rail_v'], rp['rail_v'])}, "
            f"{diff(fr['rail_t'], rp['rail_t'])}), apogee {fr['apogee']:.1f} m "
            f"({diff(fr['apogee'], rp['apogee'])}) at {fr['apogee_t']:.2f} s"
        )
    finally:
        if not a.keep:
            shutil.rmtree(work)


if __name__ == "__main__":
    main()
