"""RocketPy's documented "Calisto" flight, for side-by-side comparison with flexflight.

The rocket, motor and drag curves are those of RocketPy's "First Simulation" page
(docs/user/first_simulation.rst of RocketPy-Team/RocketPy; data files under data/, MIT
licence, copied into ./data with the M1670 thrust curve taken from ../../shared/motors).
Two changes, both to make the comparison about the same physics and not about inputs:

* the atmosphere is the International Standard Atmosphere (`standard_atmosphere`), with no
  wind, instead of a GFS forecast (flexflight flies the 1976 US Standard Atmosphere, identical
  to the ISA below 32 km);
* no parachute noise.

Prints one JSON object: apogee (m above the pad), time of apogee, speed at burnout, maximum
Mach, out-of-rail speed and time, maximum dynamic pressure and acceleration, the static
margin (Mach 0) and the stability margin (at the flight's Mach) at rail exit, maximum q and
its minimum, the landing point (north and east of the pad) and time, and the wall time of
the flight solve.

Usage: python calisto.py [--until-apogee] [--json OUT]
"""

import argparse
import json
import os
import sys
import time

from rocketpy import Environment, Flight, Rocket, SolidMotor

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "data")
MOTORS = os.path.join(HERE, "..", "..", "..", "shared", "motors")


def motor_file():
    for d in (MOTORS, os.path.join(HERE, "..", "..", "examples", "calisto")):
        p = os.path.join(d, "Cesaroni_M1670.eng")
        if os.path.exists(p):
            return p
    sys.exit("Cesaroni_M1670.eng not found in shared/motors or examples/calisto")


def thrust_points(path):
    """The (time, thrust) points of a RASP .eng file, with one (0, 0) point.

    RocketPy's `.eng` reader prepends (0, 0) itself and documents that the file "must not
    contain the 0 0 point" (`Motor.import_eng`); the shared Cesaroni_M1670.eng has it, and
    the duplicated t = 0 made the thrust NaN at ignition, the total impulse NaN and the
    propellant never burn (RocketPy 1.13.0 flew the loaded 19.197 kg to apogee). Reading the
    points here and handing RocketPy the list avoids that; the curve is the same.
    """
    pts = []
    header = False
    with open(path) as fh:
        for line in fh:
            line = line.split(";", 1)[0].strip()
            if not line:
                continue
            if not header:
                header = True
                continue
            t, f = (float(v) for v in line.split()[:2])
            pts.append((t, f))
    if not pts or pts[0][0] > 0.0:
        pts.insert(0, (0.0, 0.0))
    times = [p[0] for p in pts]
    if any(b <= a for a, b in zip(times, times[1:])):
        sys.exit(f"{path}: thrust curve times are not strictly increasing")
    return pts


def pro75_m1670():
    """The Cesaroni Pro75 M1670 of RocketPy's first-simulation page."""
    return SolidMotor(
        thrust_source=thrust_points(motor_file()),
        dry_mass=1.815,
        dry_inertia=(0.125, 0.125, 0.002),
        nozzle_radius=33 / 1000,
        grain_number=5,
        grain_density=1815,
        grain_outer_radius=33 / 1000,
        grain_initial_inner_radius=15 / 1000,
        grain_initial_height=120 / 1000,
        grain_separation=5 / 1000,
        grains_center_of_mass_position=0.397,
        center_of_dry_mass_position=0.317,
        nozzle_position=0,
        burn_time=3.9,
        throat_radius=11 / 1000,
        coordinate_system_orientation="nozzle_to_combustion_chamber",
    )


def build():
    env = Environment(latitude=32.990254, longitude=-106.974998, elevation=1400)
    env.set_atmospheric_model(type="standard_atmosphere")
    motor = pro75_m1670()
    calisto = Rocket(
        radius=127 / 2000,
        mass=14.426,
        inertia=(6.321, 6.321, 0.034),
        power_off_drag=os.path.join(DATA, "powerOffDragCurve.csv"),
        power_on_drag=os.path.join(DATA, "powerOnDragCurve.csv"),
        center_of_mass_without_motor=0,
        coordinate_system_orientation="tail_to_nose",
    )
    calisto.add_motor(motor, position=-1.255)
    calisto.set_rail_buttons(
        upper_button_position=0.0818, lower_button_position=-0.6182, angular_position=45
    )
    calisto.add_nose(length=0.55829, kind="von karman", position=1.278)
    calisto.add_trapezoidal_fins(
        n=4,
        root_chord=0.120,
        tip_chord=0.060,
        span=0.110,
        position=-1.04956,
        cant_angle=0.5,
        airfoil=(os.path.join(DATA, "NACA0012-radians.txt"), "radians"),
    )
    calisto.add_tail(top_radius=0.0635, bottom_radius=0.0435, length=0.060, position=-1.194656)
    calisto.add_parachute(name="drogue", cd_s=1.0, trigger="apogee", sampling_rate=105, lag=1.5)
    calisto.add_parachute(name="main", cd_s=10.0, trigger=800, sampling_rate=105, lag=1.5)
    return env, motor, calisto


def flight_summary(f, env, motor, rocket, wall, until_apogee):
    """The comparison's outputs of a RocketPy `Flight` (shared with valetudo.py)."""
    tb = motor.burn_out_time
    return {
        "apogee_m_agl": float(f.apogee - env.elevation),
        "apogee_time_s": float(f.apogee_time),
        "burnout_time_s": float(tb),
        "burnout_speed_m_s": float(f.speed(tb)),
        "max_mach": float(f.max_mach_number),
        "max_mach_time_s": float(f.max_mach_number_time),
        "out_of_rail_speed_m_s": float(f.out_of_rail_velocity),
        "out_of_rail_time_s": float(f.out_of_rail_time),
        "effective_rail_length_m": float(f.effective_1rl),
        "max_dynamic_pressure_pa": float(f.max_dynamic_pressure),
        "max_dynamic_pressure_time_s": float(f.max_dynamic_pressure_time),
        "max_acceleration_m_s2": float(f.max_acceleration),
        "max_acceleration_time_s": float(f.max_acceleration_time),
        # Rocket.static_margin is at Mach 0; Flight.stability_margin at the flight's Mach.
        "static_margin_at_rail_exit_cal": float(rocket.static_margin(f.out_of_rail_time)),
        "stability_margin_at_rail_exit_cal": float(f.stability_margin(f.out_of_rail_time)),
        "stability_margin_at_max_q_cal": float(f.stability_margin(f.max_dynamic_pressure_time)),
        "min_stability_margin_cal": float(f.min_stability_margin),
        "min_stability_margin_time_s": float(f.min_stability_margin_time),
        "apogee_north_m": float(f.apogee_y),
        "apogee_east_m": float(f.apogee_x),
        "final_time_s": float(f.t_final),
        "landing": None
        if until_apogee
        else {
            "t": float(f.t_final),
            "north_m": float(f.y_impact),
            "east_m": float(f.x_impact),
            "vertical_speed_m_s": float(f.impact_velocity),
            "speed_m_s": float(f.speed(f.t_final)),
        },
        "solve_wall_s": wall,
    }


def fly_and_print(build_fn, rail_length, inclination, heading):
    """Parses `--until-apogee` and `--json`, flies `build_fn()`'s rocket, prints the summary."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--until-apogee", action="store_true")
    ap.add_argument("--json")
    a = ap.parse_args()
    env, motor, rocket = build_fn()
    t0 = time.perf_counter()
    f = Flight(
        rocket=rocket,
        environment=env,
        rail_length=rail_length,
        inclination=inclination,
        heading=heading,
        terminate_on_apogee=a.until_apogee,
    )
    wall = time.perf_counter() - t0
    text = json.dumps(flight_summary(f, env, motor, rocket, wall, a.until_apogee), indent=2)
    if a.json:
        with open(a.json, "w") as fh:
            fh.write(text + "\n")
    print(text)


def main():
    fly_and_print(build, rail_length=5.2, inclination=85, heading=0)


if __name__ == "__main__":
    main()
