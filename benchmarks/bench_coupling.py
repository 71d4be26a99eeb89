"""Benchmark of the force-coupled linear plant (`uavdamp.platform.force_coupling.run`): us per solver step of one run
of the benchmark's platform (config/config.yaml, K = 1000 N/m, 2 ms step, 10 s of two sines) for a law held over
0.5 s (a constant C) and a law decided every step (the clipped skyhook), each with the ideal (viscous), lagged and
MR damper, with the machine's load beside the figures.

Usage: python benchmarks/bench_coupling.py [--repeat 5] [--seconds 10]
Each figure is the best of --repeat runs (wall clock, one process, after a first run that compiles or loads the
machine code); the per-step law's figure includes its Python call every step.
"""

import argparse
import os
import time

import numpy as np
import yaml

from uavdamp.contract import MountMotion
from uavdamp.damping import actuation, laws
from uavdamp.damping.semi_active import Hybrid
from uavdamp.platform import PlatformParams, force_coupling
from uavdamp.platform.linear_plant import LinearPlant
from uavdamp.settings import parse, view

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--repeat", type=int, default=5)
parser.add_argument("--seconds", type=float, default=10.0)
args = parser.parse_args()
with open("config/config.yaml") as f:
    config = yaml.safe_load(f)
params = parse(PlatformParams, view(config["platform"], PlatformParams), "platform")
mr = config["benchmark"]["mr"]
spec = actuation.MRSpec.build(tuple(mr["damping_range_n_s_m"]), mr["max_substep_s"])
h, stiffness = params.time_step, 1000.0
plant = LinearPlant.from_params(params)
t = np.arange(0.0, args.seconds + h / 2, h)
mount = MountMotion.planar(1e-3 * np.sin(2 * np.pi * 7.0 * t), 0.5e-3 * np.sin(2 * np.pi * 11.0 * t))
dampers = {
    "ideal": force_coupling.Viscous,
    "lagged": lambda: actuation.Lag(config["benchmark"]["damper_lag_s"]),
    "mr": lambda: actuation.MRDamper(spec),
}
law_of = {
    "held 0.5 s": lambda: laws.Constant(20.0),
    "every step": lambda: Hybrid(50.0, 1.0, plant.bounds, h, name="skyhook_clipped"),
}
print(f"load average (1, 5, 15 min): {os.getloadavg()}; {t.size - 1} steps of {h * 1e3:g} ms")
for law_name, make_law in law_of.items():
    for damper_name, make_damper in dampers.items():
        force_coupling.run(plant, t, mount, stiffness=stiffness, law=make_law(), damper=make_damper())
        best = np.inf
        for _ in range(args.repeat):
            law, damper = make_law(), make_damper()
            t0 = time.perf_counter()
            force_coupling.run(plant, t, mount, stiffness=stiffness, law=law, damper=damper)
            best = min(best, time.perf_counter() - t0)
        print(f"law {law_name:10s} damper {damper_name:6s}: {1e6 * best / (t.size - 1):6.2f} us a step")
