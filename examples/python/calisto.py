"""RocketPy's Calisto in flexflight and, when RocketPy is installed, in RocketPy: one script,
two trajectories and the flutter margin over the flight.

flexflight flies ``examples/calisto/calisto.vdl`` (RocketPy's documented Calisto with
flexible fins: aerodynamic tables derived from RocketPy itself, see
``examples/calisto/README.md``); RocketPy flies the same rocket as ``tools/rocketpy/calisto.py``
builds it (ISA, no wind), with the power-off drag curve written by flexflight
(``flexflight.write_rocketpy_drag_curve``: the drag curve of flexflight's tables in
RocketPy's CSV format, Mach and C_D). With matplotlib, the altitude against downrange of both
and flexflight's flutter margin (flutter speed over airspeed along the flight) are drawn to
``calisto.png``.

Usage:
    pip install ./python            # from the repository root
    python examples/python/calisto.py [--out DIR] [--no-rocketpy]
"""

import argparse
import math
import os
import sys

import flexflight

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))


def fly_flexflight(out_dir):
    project = flexflight.open(os.path.join(ROOT, "examples", "calisto", "calisto.vdl"))
    run = project.run("calisto", flutter_margin=True, progress=True)
    run.write(os.path.join(out_dir, "flexflight"))
    return run


def column(table, name):
    """A column of a DataFrame or of a dict of arrays, as a list."""
    return [float(x) for x in table[name]]


def fly_rocketpy(drag_csv):
    """RocketPy's Calisto (tools/rocketpy/calisto.py) with flexflight's drag curve; `None`
    without RocketPy."""
    try:
        import rocketpy  # noqa: F401
    except ImportError:
        return None
    sys.path.insert(0, os.path.join(ROOT, "tools", "rocketpy"))
    import calisto as rp_calisto  # tools/rocketpy/calisto.py
    from rocketpy import Flight

    env, _, _ = rp_calisto.build()
    # The same rocket with flexflight's drag curve (power off and on: the tables hold one).
    rocket = rebuild_with_drag(rp_calisto, drag_csv)
    f = Flight(rocket=rocket, environment=env, rail_length=5.2, inclination=85, heading=0,
               terminate_on_apogee=False)
    return env, f


def rebuild_with_drag(rp_calisto, drag_csv):
    """`tools/rocketpy/calisto.py`'s rocket with both drag curves from `drag_csv`."""
    from rocketpy import Rocket

    motor = rp_calisto.pro75_m1670()
    data = rp_calisto.DATA
    calisto = Rocket(
        radius=127 / 2000, mass=14.426, inertia=(6.321, 6.321, 0.034),
        power_off_drag=drag_csv, power_on_drag=drag_csv,
        center_of_mass_without_motor=0, coordinate_system_orientation="tail_to_nose",
    )
    calisto.add_motor(motor, position=-1.255)
    calisto.set_rail_buttons(upper_button_position=0.0818, lower_button_position=-0.6182,
                             angular_position=45)
    calisto.add_nose(length=0.55829, kind="von karman", position=1.278)
    calisto.add_trapezoidal_fins(n=4, root_chord=0.120, tip_chord=0.060, span=0.110,
                                 position=-1.04956, cant_angle=0.5,
                                 airfoil=(os.path.join(data, "NACA0012-radians.txt"), "radians"))
    calisto.add_tail(top_radius=0.0635, bottom_radius=0.0435, length=0.060, position=-1.194656)
    calisto.add_parachute(name="drogue", cd_s=1.0, trigger="apogee", sampling_rate=105, lag=1.5)
    calisto.add_parachute(name="main", cd_s=10.0, trigger=800, sampling_rate=105, lag=1.5)
    return calisto


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="calisto_out", help="output directory")
    ap.add_argument("--no-rocketpy", action="store_true", help="fly flexflight only")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)

    run = fly_flexflight(a.out)
    s = run.summary
    h = run.history
    apogee = s["flight"].get("apogee") or {}
    print(f"flexflight: {s['stop_reason']} at t = {s['t_end']:.2f} s; apogee {apogee}")
    margin = s.get("flutter_margin") or {}
    print(f"flexflight flutter margin, minimum: {margin.get('minimum')}")

    drag_csv = os.path.join(a.out, "flexflight_drag.csv")
    curve = run.drag_curve()
    if curve:
        flexflight.write_rocketpy_drag_curve(curve, drag_csv)
        print(f"drag curve ({len(curve)} Machs) -> {drag_csv}")

    rp = None if a.no_rocketpy or not curve else fly_rocketpy(drag_csv)
    if rp is None:
        print("RocketPy not flown (not installed, or --no-rocketpy)")
    else:
        env, f = rp
        print(f"RocketPy: apogee {f.apogee - env.elevation:.1f} m AGL at t = {f.apogee_time:.2f} s")

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed: no plot")
        return
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.5))
    # flexflight: inertial position, z down; altitude above the pad from the altitude channel.
    # history.csv's columns (docs/outputs.md): inertial position of the nose tip, z down.
    alt = column(h, "altitude")
    site = alt[0]
    north = column(h, "p_inertial_x")
    east = column(h, "p_inertial_y")
    downrange = [math.hypot(n - north[0], e - east[0]) for n, e in zip(north, east)]
    ax1.plot(downrange, [x - site for x in alt], label="flexflight")
    if rp is not None:
        env, f = rp
        ts = [float(x) for x in f.time]
        ax1.plot([math.hypot(float(f.x(x)), float(f.y(x))) for x in ts],
                 [float(f.z(x)) - env.elevation for x in ts], "--", label="RocketPy")
    ax1.set_xlabel("downrange (m)")
    ax1.set_ylabel("altitude above the pad (m)")
    ax1.set_title("Calisto trajectory")
    ax1.legend()
    fm = run.flutter_margin
    if fm is not None:
        # flutter_margin.csv (docs/outputs.md): `speed_margin` = V_F / V at each row `t`.
        t, m = column(fm, "t"), column(fm, "speed_margin")
        ax2.plot(t, m)
        # Near the pad the airspeed is small and the margin huge: scale to the minimum.
        k = min(range(len(m)), key=lambda i: m[i])
        ax2.set_ylim(0.0, max(4.0, 2.0 * m[k]))
        ax2.axhline(1.0, color="k", lw=0.8, label="flutter (1.0)")
        ax2.axhline(1.15, color="k", lw=0.8, ls=":", label="1.15")
        ax2.plot([t[k]], [m[k]], "o", label=f"minimum {m[k]:.2f} at t = {t[k]:.2f} s")
        ax2.legend()
        ax2.set_xlabel("t (s)")
        ax2.set_ylabel("flutter speed / airspeed")
    ax2.set_title("flexflight flutter margin over the flight")
    fig.tight_layout()
    png = os.path.join(a.out, "calisto.png")
    fig.savefig(png, dpi=120)
    print(f"plot -> {png}")


if __name__ == "__main__":
    main()
