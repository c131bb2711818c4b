"""RocketPy's rigid 6-DOF flight of a SPHADS-1-sized powered rocket for 10 s from a rail:
the reference for flexflight's speed target (issue "Speed: a flexible flight 20x faster than
RocketPy's rigid one").

SPHADS-1 as compiled by flexflight (vehicles/sphads1.vdl): 17.56 kg with the motor case,
127 mm diameter, 2.75 m long, 450 mm nose, four fins of root chord 324.68 mm, tip chord
122.67 mm, span 127.23 mm; centre of mass 1.5896 m aft of the nose. The motor is the
Cesaroni M1670 of RocketPy's own example, so the flight is powered for 3.9 s of the 10 s.
Drag: RocketPy's Calisto power-off curve (a 127 mm rocket of the same class).

Usage: python speed.py [--runs N]   prints the median wall time of Flight(...) over N runs
(whole flight solve, LSODA, RocketPy defaults), and the min and max.
"""

import argparse
import os
import statistics
import time

from calisto import pro75_m1670
from rocketpy import Environment, Flight, Rocket

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "data")


def build():
    env = Environment(latitude=0, longitude=0, elevation=0)
    env.set_atmospheric_model(type="standard_atmosphere")
    motor = pro75_m1670()
    # Nose tip at +1.5896 m, tail at -1.1604 m about the centre of mass (tail_to_nose axis).
    r = Rocket(
        radius=0.127 / 2,
        mass=17.56 - 1.815,
        inertia=(11.0, 11.0, 0.04),
        power_off_drag=os.path.join(DATA, "powerOffDragCurve.csv"),
        power_on_drag=os.path.join(DATA, "powerOnDragCurve.csv"),
        center_of_mass_without_motor=0,
        coordinate_system_orientation="tail_to_nose",
    )
    r.add_motor(motor, position=-1.1604)
    r.add_nose(length=0.45, kind="ogive", position=1.5896)
    r.add_trapezoidal_fins(
        n=4, root_chord=0.32468, tip_chord=0.12267, span=0.12723, position=-1.1604 + 0.32468
    )
    return env, r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    a = ap.parse_args()
    env, rocket = build()
    times = []
    for _ in range(a.runs):
        t0 = time.perf_counter()
        # With max_time = 10 s and the default (infinite) max_time_step, RocketPy 1.13 returns
        # a 4-point solution with the rocket still on the pad; 0.1 s is the largest step that
        # flies it.
        f = Flight(rocket=rocket, environment=env, rail_length=5.2, inclination=85, heading=0,
                   max_time=10.0, max_time_step=0.1)
        times.append(time.perf_counter() - t0)
    print(
        f"rocketpy 10 s flight: median {statistics.median(times):.3f} s, "
        f"min {min(times):.3f} s, max {max(times):.3f} s over {a.runs} runs; "
        f"t_final {f.t_final:.2f} s, altitude at 10 s {f.z(10.0) - env.elevation:.0f} m, "
        f"{len(f.solution)} solution points"
    )


if __name__ == "__main__":
    main()
