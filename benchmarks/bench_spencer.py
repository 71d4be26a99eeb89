"""Benchmark of the compiled Spencer MR damper step (`uavdamp.damping.spencer_kernel`): us per solver step of
0.5 ms for the benchmark's platform damper (2 axes) and the payload's four runs side by side (96 dampers), on
strokes past the damper's yield, with the machine's load beside the figures.

Usage: python benchmarks/bench_spencer.py [--steps 4000] [--repeat 5]
Times are the best of --repeat passes over --steps steps (wall clock, one process, after a first call that
compiles or loads the machine code).
"""

import argparse
import os
import time

import numpy as np

from uavdamp.damping.dampers import V_MAX, SpencerMR, SpencerParams

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--steps", type=int, default=4000)
parser.add_argument("--repeat", type=int, default=5)
args = parser.parse_args()
H = 5e-4
params = SpencerParams.for_platform(1.0, 6.0)
print(f"load average (1, 5, 15 min): {os.getloadavg()}")
for n in (2, 96):
    rng = np.random.default_rng(0)
    t = np.arange(args.steps + 1)[:, None] * H
    amp, phase = rng.uniform(5e-5, 2e-3, n), rng.uniform(0, 2 * np.pi, n)
    x, xd = amp * np.sin(44.0 * t + phase), 44.0 * amp * np.cos(44.0 * t + phase)
    volts = np.linspace(0.0, V_MAX, n)
    dampers = SpencerMR(params, n_axes=n)
    t0 = time.perf_counter()
    dampers.step(H, volts, x[0], xd[0], x[1], xd[1])
    first = time.perf_counter() - t0
    best = np.inf
    for _ in range(args.repeat):
        dampers.reset()
        t0 = time.perf_counter()
        for k in range(args.steps):
            dampers.step(H, volts, x[k], xd[k], x[k + 1], xd[k + 1])
        best = min(best, time.perf_counter() - t0)
    print(f"{n:3d} dampers: {1e6 * best / args.steps:7.2f} us a step (first call {first:.3f} s)")
