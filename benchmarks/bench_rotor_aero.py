"""Benchmark: per-call cost of the rotor aerodynamics for one Exudyn step (main 4 x 10 stations, tail 2 x 10).

Usage: python benchmarks/bench_rotor_aero.py [--stations N] [--calls N] [--repeats N]
Target: well under 50 us for the main rotor's velocities + loads, so a 50 s run at a 1 ms step spends
under a few seconds in aerodynamics. Reports the best of the repeats in CPU time (us per call): the shared 2-core
machine is noisy, the minimum is the reproducible figure.
"""

import argparse
import time
from dataclasses import replace

import numpy as np

from uavdamp.helicopter import aerodynamics as rotor_aero
from uavdamp.helicopter import inflow as rotor_inflow

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--stations", type=int, default=10)
parser.add_argument("--calls", type=int, default=2000)
parser.add_argument("--repeats", type=int, default=15)
args = parser.parse_args()

main = replace(rotor_aero.BO105_MAIN, n_stations=args.stations)
tail = replace(rotor_aero.BO105_TAIL, n_stations=args.stations)
omega = 44.4
rng = np.random.default_rng(0)


def step_inputs(blade, n):
    rot = rotor_aero.blade_rotations(0.7, n)
    w = np.array([0.01, -0.02, omega]) + 0.01 * rng.normal(size=(n, 3))
    v0 = np.cross(w, blade.hinge_offset * rot[:, :, 0]) + rng.normal(size=(n, 3))
    air = np.tile([0.0, 0.0, -9.0], (n, blade.n_stations, 1))  # per-station inflow, as Pitt-Peters gives
    return rot, v0, w, air, 0.15 + blade.twist


cases = {
    "main velocities + loads": (main, step_inputs(main, 4)),
    "tail velocities + loads": (tail, step_inputs(tail, 2)),
}


def one_step(blade, inputs):
    rot, v0, w, air, pitch = inputs
    return rotor_aero.blade_loads(blade, *rotor_aero.section_velocities(blade, rot, v0, w, air), pitch)


def best_us(fn, *fn_args):
    best = np.inf
    for _ in range(args.repeats):
        t0 = time.process_time()
        for _ in range(args.calls):
            fn(*fn_args)
        best = min(best, (time.process_time() - t0) / args.calls)
    return 1e6 * best


state = np.array([0.04, 0.001, -0.002])
psi = rotor_inflow.blade_azimuth(0.7, 4)[:, None]
r_over_radius = (main.hinge_offset + main.stations) / main.tip_radius
print(f"{'call':32s} {'us':>8s}  ({args.stations} stations, best of {args.repeats} x {args.calls} calls)")
timings = {name: best_us(one_step, blade, inputs) for name, (blade, inputs) in cases.items()}
timings["pitt_peters_rhs"] = best_us(rotor_inflow.pitt_peters_rhs, state, 0.003, 1e-5, -1e-5, 0.05)
timings["induced_velocity (4 x S)"] = best_us(rotor_inflow.induced_velocity, state, r_over_radius, psi, omega, 5.6)
for name, us in timings.items():
    print(f"{name:32s} {us:8.1f}")
total = sum(timings.values())
print(f"{'one step, all of the above':32s} {total:8.1f}  -> {total * 1e-6 * 50_000:.2f} s per 50 s run at 1 ms")
