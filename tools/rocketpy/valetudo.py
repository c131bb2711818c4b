"""RocketPy's documented "Valetudo" flight (Projeto Jupiter, 2019), with its measured apogee.

The rocket, motor, drag curves and launch are those of RocketPy's example notebook
docs/examples/valetudo_flight_sim.ipynb (RocketPy-Team/RocketPy, commit d41dd11e; data
files copied into ./data, provenance in data/SOURCE.md). The notebook records what was
recovered of the real flight: apogee 860 m above the ground, drift 350 m east, 25 m north
(the flight recordings were lost). Two changes from the notebook, as for calisto.py: the
International Standard Atmosphere with no wind (the notebook's own run has no wind either:
its reanalysis file is commented out and its surface wind is 0), and no parachute noise.

Prints calisto.py's JSON summary. Usage: python valetudo.py [--until-apogee] [--json OUT]
"""

import os
import sys

from rocketpy import Environment, Rocket, SolidMotor

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from calisto import DATA, fly_and_print  # noqa: E402

# The notebook's `parameters` (nominal values).
ROCKET_MASS = 8.257  # kg, without motor
INERTIA = (3.675, 3.675, 0.007)  # kg m^2 about the centre of mass without motor
RADIUS = 40.45 / 1000
NOZZLE = -1.024  # m, nozzle exit from the centre of mass without motor (tail_to_nose)
NOSE_TIP = 1.134
NOSE_LENGTH = 0.274
FIN_SPAN, FIN_ROOT, FIN_TIP, FIN_POSITION = 0.077, 0.058, 0.018, -0.906
RAIL_LENGTH, INCLINATION, HEADING = 5.7, 84.7, 53
CD_S_DROGUE = 0.349 * 1.3
LAG = 1.0
MEASURED = {"apogee_m_agl": 860.0, "drift_east_m": 350.0, "drift_north_m": 25.0}


def keron():
    """The team's Keron motor: 6 grains, nozzle at the motor's origin, grain centre 0.42 m."""
    return SolidMotor(
        thrust_source=os.path.join(DATA, "keron_thrust_curve.csv"),
        burn_time=5.274,
        dry_mass=0.001,
        dry_inertia=(0, 0, 0),
        center_of_dry_mass_position=0.42,
        grains_center_of_mass_position=0.42,
        grain_number=6,
        grain_separation=6 / 1000,
        grain_density=1707,
        grain_outer_radius=21.4 / 1000,
        grain_initial_inner_radius=9.65 / 1000,
        grain_initial_height=120 / 1000,
        nozzle_radius=21.642 / 1000,
        throat_radius=8 / 1000,
        interpolation_method="linear",
        nozzle_position=0,
        coordinate_system_orientation="nozzle_to_combustion_chamber",
    )


def build():
    env = Environment(latitude=-23.363611, longitude=-48.011389, elevation=668)
    env.set_atmospheric_model(type="standard_atmosphere")
    motor = keron()
    rocket = Rocket(
        radius=RADIUS,
        mass=ROCKET_MASS,
        inertia=INERTIA,
        power_off_drag=os.path.join(DATA, "valetudo_Cd_PowerOff_RASAero.csv"),
        power_on_drag=os.path.join(DATA, "valetudo_Cd_PowerOn_RASAero.csv"),
        center_of_mass_without_motor=0,
    )
    rocket.set_rail_buttons(0.224, -0.93, 30)
    rocket.add_motor(motor=motor, position=NOZZLE)
    rocket.add_nose(length=NOSE_LENGTH, kind="tangent", position=NOSE_TIP)
    rocket.add_trapezoidal_fins(
        3, span=FIN_SPAN, root_chord=FIN_ROOT, tip_chord=FIN_TIP, position=FIN_POSITION
    )
    rocket.add_parachute("Drogue", cd_s=CD_S_DROGUE, trigger="apogee", sampling_rate=105, lag=LAG)
    return env, motor, rocket


def main():
    fly_and_print(build, RAIL_LENGTH, INCLINATION, HEADING)


if __name__ == "__main__":
    main()
