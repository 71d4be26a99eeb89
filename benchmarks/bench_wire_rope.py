"""Benchmark of the wire-rope isolator's compiled steps (`uavdamp.platform.wire_rope_kernel`): a payload stage's
wire-rope runs (the gimbal's 1.5 kg on the default isolator, 5 s on the 0.5 ms grid, yielding), per solver step,
with the machine's load beside the figures.

Usage: python benchmarks/bench_wire_rope.py [--duration 5] [--repeat 3]
Three ways: the five constant dampings of a payload input held (`wire_rope.integrate`: one compiled call), the
same as schedules (`wire_rope.integrate_scheduled`: one compiled step a sample, the schedules read in Python), and
an on-off skyhook on the elements' own velocities at four c_on beside two held C (`integrate_scheduled`, as the
payload stage's laws on the wire rope: the skyhook's Python decisions at every sample included). Times are the best
of --repeat passes (wall clock, one process, after a first call that compiles or loads the machine code).
"""

import argparse
import os
import time

import numpy as np

from uavdamp.damping.laws import Skyhook
from uavdamp.platform import wire_rope
from uavdamp.platform.six_axis import Payload, square_layout
from uavdamp.study.payload_laws import skyhook_schedule

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--duration", type=float, default=5.0, help="s of mount motion")
parser.add_argument("--repeat", type=int, default=3)
args = parser.parse_args()
H = 5e-4
payload = Payload.box(1.5, (0.10, 0.10, 0.08), (0.0, 0.0, 0.06))
isolator = square_layout(payload, 0.05, (250.0, 250.0, 500.0), (1.0,) * 3, kind="wire_rope", semi_active=True)
wire = wire_rope.WireRope()
t = np.arange(0.0, args.duration + H / 2, H)
translation, rotation = np.zeros((3, t.size)), np.zeros((3, t.size))
translation[0], translation[1] = 2e-3 * np.sin(2 * np.pi * 7.07 * t), 1e-3 * np.sin(2 * np.pi * 8.05 * t + 0.3)
rotation[1] = 2e-3 * np.sin(2 * np.pi * 7.07 * t + 1.0)
u = np.vstack([translation, rotation]).T
dampings = [[c] * 4 for c in (1.0, 3.0, 10.0, 30.0, 100.0)]
rates = np.vstack([np.diff(u, axis=0), np.diff(u, axis=0)[-1:]]) / H
laws = [skyhook_schedule(isolator, t, rates, Skyhook(c, 1.0, H)) for c in (3.0, 10.0, 30.0, 100.0)]
held = [np.full((4, t.size), c[0]) for c in dampings]
ways = {
    "held, 5 runs": lambda: wire_rope.integrate(isolator, wire, t, translation, rotation, dampings),
    "stepped, 5 runs": lambda: wire_rope.integrate_scheduled(isolator, wire, t, translation, rotation, held),
    "skyhook x 4 + 2 held": lambda: wire_rope.integrate_scheduled(
        isolator, wire, t, translation, rotation, laws + held[1:3]
    ),
}
print(f"load average (1, 5, 15 min): {os.getloadavg()}")
for name, call in ways.items():
    t0 = time.perf_counter()
    call()
    first = time.perf_counter() - t0
    passes = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        call()
        passes.append(time.perf_counter() - t0)
    best = min(passes)
    steps = t.size - 1
    print(f"{name}: {1e6 * best / steps:.1f} us a step ({best:.3f} s for {steps} steps; first call {first:.2f} s)")
