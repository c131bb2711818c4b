"""RocketPy's MonteCarlo on the K1000T rocket of examples/hpr_k1000, beside flexflight's
`montecarlo` on the same rocket, the same number of samples and the same machine (issue 35).
Outside `cargo test`; RocketPy in its own venv (`setup_venv.sh`).

    tools/rocketpy/.venv/bin/python tools/rocketpy/k1000_montecarlo.py [--samples N] \
        [--workers W] [--flexflight PATH] [--json FILE] [--keep DIR]

The rocket is the example's as far as RocketPy's rigid model takes it: 98 mm body 1.9 m long
with a 0.45 m conical nose, three trapezoidal fins (root 250 mm, tip 100 mm, span 120 mm,
trailing edge at the aft end), the AeroTech K1000T from the same `.eng` file, a dry mass of
6.42 kg (flexflight's compiled mass without the motor), drag from RocketPy's Calisto curves
(a rocket of this class; flexflight uses its own estimator), a 3 m rail at 85 deg toward the
east, a drogue at apogee (C_D S 0.35 m^2, 1 s lag) and a main at 250 m (4 m^2, 0.5 s lag),
a 5 m/s westerly. The dispersion is the example's `k1000_flight` in RocketPy's terms: rail
inclination N(85, 0.5) deg, heading N(90, 2) deg, the main's C_D S N(4, 0.2) m^2, the
drogue's lag N(1, 0.25) s, the wind scaled by N(1, 0.35) (RocketPy's stochastic wind is a
factor on the profile), the dry mass N(6.42, 0.025) kg. Its flights are rigid, pad to
landing, no flutter margin: the work flexflight does per sample is larger.

Timed: `MonteCarlo.simulate(N, parallel=..., n_workers=W)` (RocketPy's own parallelism), and
`flexflight montecarlo ... --dispersion k1000_flight --samples N --jobs W` as a whole process
with a warm cache. Printed: wall and CPU seconds (the process's own and its reaped
children's: RocketPy's workers, flexflight's process) and samples per second of each, the
ratio, and the load average before and after. `--keep DIR` keeps both tools' outputs (a
fresh DIR each time: flexflight resumes finished samples), so that if RocketPy's workers
hang on a sample the finished ones can be counted from `DIR/k1000.outputs.txt`.
"""

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DATA = os.path.join(HERE, "data")
EXAMPLE = os.path.join(ROOT, "examples", "hpr_k1000")


def cpu_seconds():
    """User + system CPU of this process and of its reaped children (RocketPy's workers,
    flexflight's process and its threads), s."""
    t = 0.0
    for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN):
        r = resource.getrusage(who)
        t += r.ru_utime + r.ru_stime
    return t


def build():
    from rocketpy import Environment, Flight, GenericMotor, Rocket

    env = Environment(latitude=0, longitude=0, elevation=0)
    # 5 m/s from the west (blowing toward +x, east) at every height: RocketPy's stochastic
    # wind is a factor on this profile.
    env.set_atmospheric_model(type="custom_atmosphere", wind_u=5.0, wind_v=0.0)
    motor = GenericMotor.load_from_eng_file(
        os.path.join(EXAMPLE, "AeroTech_K1000T.eng"),
        chamber_radius=0.0375,
        chamber_height=0.396,
        chamber_position=0.198,
        nozzle_radius=0.02,
        dry_mass=2.575 - 1.182,
        center_of_dry_mass_position=0.198,
    )
    # Axis from the tail (0) to the nose tip (1.9 m); centre of mass of the dry rocket
    # about 1.0 m from the tail.
    r = Rocket(
        radius=0.049,
        mass=6.42,
        inertia=(1.9, 1.9, 0.012),
        power_off_drag=os.path.join(DATA, "powerOffDragCurve.csv"),
        power_on_drag=os.path.join(DATA, "powerOnDragCurve.csv"),
        center_of_mass_without_motor=1.0,
        coordinate_system_orientation="tail_to_nose",
    )
    r.add_motor(motor, position=0.0)
    nose = r.add_nose(length=0.45, kind="conical", position=1.9)
    fins = r.add_trapezoidal_fins(n=3, root_chord=0.25, tip_chord=0.10, span=0.12, position=0.25)
    drogue = r.add_parachute("drogue", cd_s=0.35, trigger="apogee", sampling_rate=100, lag=1.0)
    main = r.add_parachute("main", cd_s=4.0, trigger=250, sampling_rate=100, lag=0.5)
    flight = Flight(rocket=r, environment=env, rail_length=3.0, inclination=85, heading=90,
                    terminate_on_apogee=False, max_time=600)
    return env, motor, r, nose, fins, drogue, main, flight


def rocketpy_montecarlo(samples, workers, out_dir):
    from rocketpy import MonteCarlo
    from rocketpy.stochastic import (StochasticEnvironment, StochasticFlight,
                                     StochasticGenericMotor, StochasticNoseCone,
                                     StochasticParachute, StochasticRocket,
                                     StochasticTrapezoidalFins)

    env, motor, rocket, nose, fins, drogue, main, flight = build()
    s_env = StochasticEnvironment(environment=env, wind_velocity_x_factor=(1.0, 0.35))
    s_motor = StochasticGenericMotor(generic_motor=motor)
    s_rocket = StochasticRocket(rocket=rocket, mass=(6.42, 0.025))
    s_rocket.add_motor(s_motor, position=0.0)
    s_rocket.add_nose(StochasticNoseCone(nose), position=1.9)
    s_rocket.add_trapezoidal_fins(StochasticTrapezoidalFins(fins), position=0.25)
    s_rocket.add_parachute(StochasticParachute(drogue, lag=(1.0, 0.25)))
    s_rocket.add_parachute(StochasticParachute(main, cd_s=(4.0, 0.2)))
    s_flight = StochasticFlight(flight=flight, inclination=(85, 0.5), heading=(90, 2))
    mc = MonteCarlo(filename=os.path.join(out_dir, "k1000"), environment=s_env,
                    rocket=s_rocket, flight=s_flight)
    t0 = time.perf_counter()
    if workers > 1:
        mc.simulate(number_of_simulations=samples, append=False, parallel=True,
                    n_workers=workers)
    else:
        mc.simulate(number_of_simulations=samples, append=False)
    return time.perf_counter() - t0


def flexflight_montecarlo(exe, samples, workers, out_dir, cache, sets=()):
    cmd = [exe, "montecarlo", os.path.join(EXAMPLE, "hpr_k1000.vdl"), "--dispersion",
           "k1000_flight", "--samples", str(samples), "--jobs", str(workers), "--out", out_dir,
           "--cache-dir", cache]
    for s in sets:
        cmd += ["--set", s]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"flexflight failed ({p.returncode}): {p.stderr}")
    return dt, p.stderr


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=100)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--flexflight", default=os.path.join(ROOT, "target", "release", "flexflight"))
    ap.add_argument("--cache-dir", default=None)
    ap.add_argument("--skip-rocketpy", action="store_true")
    ap.add_argument("--skip-flexflight", action="store_true")
    ap.add_argument("--json", default=None)
    ap.add_argument("--set", action="append", default=[], dest="sets",
                    help="an override passed to flexflight montecarlo (repeatable), e.g. "
                         "run.integrator=exponential")
    ap.add_argument("--keep", default=None,
                    help="a directory for both tools' outputs, kept (default: a temporary one)")
    a = ap.parse_args()
    result = {"samples": a.samples, "workers": a.workers, "load_before": os.getloadavg()}
    with tempfile.TemporaryDirectory() as scratch:
        tmp = a.keep or scratch
        os.makedirs(tmp, exist_ok=True)
        if not a.skip_rocketpy:
            c0 = cpu_seconds()
            t = rocketpy_montecarlo(a.samples, a.workers, tmp)
            result["rocketpy_s"] = t
            result["rocketpy_cpu_s"] = cpu_seconds() - c0
            print(f"RocketPy MonteCarlo: {a.samples} flights, {a.workers} worker(s): {t:.1f} s "
                  f"({result['rocketpy_cpu_s']:.1f} s CPU), {a.samples / t:.2f} samples/s",
                  flush=True)
        if not a.skip_flexflight:
            cache = a.cache_dir or os.path.join(tmp, "cache")
            # A first sample warms the artifact, aerodynamic and flutter-boundary caches.
            flexflight_montecarlo(a.flexflight, 1, 1, os.path.join(tmp, "warm"), cache)
            c0 = cpu_seconds()
            t, err = flexflight_montecarlo(a.flexflight, a.samples, a.workers,
                                           os.path.join(tmp, "ff"), cache, a.sets)
            result["flexflight_s"] = t
            result["flexflight_cpu_s"] = cpu_seconds() - c0
            print(err, end="")
            print(f"flexflight montecarlo: {a.samples} flights, {a.workers} job(s): {t:.1f} s "
                  f"({result['flexflight_cpu_s']:.1f} s CPU), {a.samples / t:.2f} samples/s")
        if "rocketpy_s" in result and "flexflight_s" in result:
            result["ratio"] = result["rocketpy_s"] / result["flexflight_s"]
            print(f"flexflight / RocketPy throughput: {result['ratio']:.2f}x")
        result["load_after"] = os.getloadavg()
        print(f"load average before {result['load_before']}, after {result['load_after']}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(result, f, indent=2)


if __name__ == "__main__":
    main()
