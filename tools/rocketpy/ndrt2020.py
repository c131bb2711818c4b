"""RocketPy's documented Notre Dame Rocket Team 2020 flight, with its measured apogee.

The rocket, motor and launch are those of RocketPy's example notebook
docs/examples/ndrt_2020_flight_sim.ipynb (RocketPy-Team/RocketPy, commit d41dd11e): its
nominal `parameters`, nose_to_tail as there. The motor curve is the notebook's
Cesaroni_4895L1395-P.eng, copied with its provenance into examples/ndrt2020. The notebook
records the measured flight (23 February 2020, Three Oaks, MI, 206 m): apogee 4,320 ft =
1316.736 m above the ground, static margin 2.875 cal, drift 2275 ft. Its drag is a constant
C_D of 0.44, power on and off.

One change from the notebook, as for valetudo.py: the International Standard Atmosphere with
no wind instead of the ERA5 reanalysis of the launch day (the notebook's own run), so that
both programs fly the same air; and no parachute noise. `--era5 FILE` flies the notebook's
reanalysis instead (its data/weather/ndrt_2020_weather_data_ERA5.nc, read from wherever it
is; not copied here). `--pitch-inertia I` replaces the notebook's 73.316 kg m^2 (which no
mass distribution inside this rocket can have, examples/ndrt2020/README.md) by I.

Prints calisto.py's JSON summary.
Usage: python ndrt2020.py [--era5 FILE] [--pitch-inertia I] [--until-apogee] [--json OUT]
"""

import argparse
import math
import os
import sys

from rocketpy import Environment, Rocket, SolidMotor

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from calisto import fly_and_print  # noqa: E402

EXAMPLE = os.path.join(HERE, "..", "..", "examples", "ndrt2020")

# The notebook's `parameters` (nominal values), nose_to_tail: positions in m aft of the nose
# tip.
ROCKET_MASS = 18.998  # kg, without motor
CENTER_OF_MASS = 1.3
INERTIA = (73.316, 73.316, 0.15982)  # kg m^2 about the centre of mass without motor
RADIUS = 0.1015
MOTOR_POSITION = 3.391  # the motor's origin, its nozzle exit
MOTOR_DRY_MASS = 1.848
GRAINS_CENTER = -0.35  # combustion_chamber_to_nozzle: 0.35 m ahead of the nozzle
NOSE_LENGTH = 0.610
FIN_SPAN, FIN_ROOT, FIN_TIP, FIN_SWEEP, FIN_POSITION = 0.165, 0.152, 0.0762, 13, 3.050
TAIL_TOP, TAIL_BOTTOM, TAIL_LENGTH, TAIL_POSITION = 0.1015, 0.0775, 0.127, 1.2
DRAG_COEFFICIENT = 0.44
RAIL_LENGTH, INCLINATION, HEADING = 3.353, 90, 181
CD_S_DROGUE = 1.5 * math.pi * (24 * 25.4 / 1000) ** 2 / 4
CD_S_MAIN = 2.2 * math.pi * (120 * 25.4 / 1000) ** 2 / 4
MAIN_ALTITUDE = 167.64  # m above the ground (550 ft)
LAG = 1.0
MEASURED = {"apogee_m_agl": 1316.736, "static_margin_cal": 2.875, "drift_m": 2275 * 0.3048}

OPTIONS = argparse.Namespace(era5=None, pitch_inertia=None)


def l1395():
    """The notebook's Cesaroni L1395: 5 grains, nozzle at the motor's origin."""
    return SolidMotor(
        thrust_source=os.path.join(EXAMPLE, "Cesaroni_4895L1395-P.eng"),
        burn_time=3.433,
        dry_mass=MOTOR_DRY_MASS,
        dry_inertia=(0, 0, 0),
        center_of_dry_mass_position=GRAINS_CENTER,
        grains_center_of_mass_position=GRAINS_CENTER,
        grain_number=5,
        grain_separation=0.003,
        grain_density=1519.708,
        grain_outer_radius=0.033,
        grain_initial_inner_radius=0.015,
        grain_initial_height=0.12,
        nozzle_radius=0.02475,
        throat_radius=0.01075,
        interpolation_method="linear",
        nozzle_position=0,
        coordinate_system_orientation="combustion_chamber_to_nozzle",
    )


def build():
    env = Environment(
        gravity=9.81, latitude=41.775447, longitude=-86.572467, date=(2020, 2, 23, 16), elevation=206
    )
    if OPTIONS.era5:
        env.set_atmospheric_model(type="Reanalysis", file=OPTIONS.era5, dictionary="ECMWF")
    else:
        env.set_atmospheric_model(type="standard_atmosphere")
    motor = l1395()
    i = INERTIA if OPTIONS.pitch_inertia is None else (OPTIONS.pitch_inertia,) * 2 + INERTIA[2:]
    rocket = Rocket(
        radius=RADIUS,
        mass=ROCKET_MASS,
        inertia=i,
        power_off_drag=DRAG_COEFFICIENT,
        power_on_drag=DRAG_COEFFICIENT,
        center_of_mass_without_motor=CENTER_OF_MASS,
        coordinate_system_orientation="nose_to_tail",
    )
    rocket.set_rail_buttons(1.5, 2, 45)
    rocket.add_motor(motor=motor, position=MOTOR_POSITION)
    rocket.add_nose(length=NOSE_LENGTH, kind="tangent", position=0)
    rocket.add_trapezoidal_fins(
        4,
        span=FIN_SPAN,
        root_chord=FIN_ROOT,
        tip_chord=FIN_TIP,
        position=FIN_POSITION,
        sweep_angle=FIN_SWEEP,
        radius=TAIL_BOTTOM,
    )
    rocket.add_tail(
        top_radius=TAIL_TOP, bottom_radius=TAIL_BOTTOM, length=TAIL_LENGTH, position=TAIL_POSITION
    )
    rocket.add_parachute("Drogue", cd_s=CD_S_DROGUE, trigger="apogee", sampling_rate=105, lag=LAG)
    rocket.add_parachute("Main", cd_s=CD_S_MAIN, trigger=MAIN_ALTITUDE, sampling_rate=105, lag=LAG)
    return env, motor, rocket


def main():
    ap = argparse.ArgumentParser(add_help=False)
    ap.add_argument("--era5")
    ap.add_argument("--pitch-inertia", type=float)
    known, rest = ap.parse_known_args()
    OPTIONS.era5, OPTIONS.pitch_inertia = known.era5, known.pitch_inertia
    sys.argv = sys.argv[:1] + rest
    fly_and_print(build, RAIL_LENGTH, INCLINATION, HEADING)


if __name__ == "__main__":
    main()
