"""Benchmark: the paper's 50 s imbalanced-rotor run (default config), simulated seconds per wall second.

Usage: python benchmarks/bench_helicopter.py [--fast] [--repeats N] [--duration S] [--modes] [--flight]
--fast loads Exudyn's AVX2 module without range checks, as the pipeline does. Target: >= 4 s/s.
--modes times the Campbell diagram and the Floquet analysis of the config instead (wall s).
--flight times, in one process, the vacuum run and the trimmed hover run (trim, release, record) of the same length
and the per-step load update (target: the hover run within 5 x the vacuum run's wall time).
"""

import argparse
import sys
import time
from pathlib import Path

import yaml

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--fast", action="store_true")
parser.add_argument("--repeats", type=int, default=3)
parser.add_argument("--duration", type=float, default=None, help="s, default: the config's")
parser.add_argument("--modes", action="store_true", help="time the Campbell and Floquet analyses")
parser.add_argument("--flight", action="store_true", help="time the trimmed hover run against the vacuum run")
args = parser.parse_args()
if args.fast:
    sys.exudynFast = True

import numpy as np  # noqa: E402

from uavdamp import helicopter  # noqa: E402
from uavdamp.helicopter import floquet  # noqa: E402
from uavdamp.helicopter import modes as rotor_modes  # noqa: E402
from uavdamp.settings import parse  # noqa: E402

cfg = yaml.safe_load((Path(__file__).resolve().parents[1] / "config" / "config.yaml").read_text())["helicopter"]
if args.modes:
    heli = parse(helicopter.HelicopterSection, cfg, "helicopter")
    opts = heli.campbell
    speeds = np.linspace(0.0, opts.max_speed_ratio * heli.main_rotor.omega_rad_s, opts.n_speeds)
    print(f"{'Campbell s':>10} {'Floquet s':>10}  ({len(speeds)} speeds, {opts.floquet_steps} azimuth steps)")
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        rotor_modes.campbell(heli.balanced(), speeds, check_azimuths_rad=opts.check_azimuths_rad)
        t1 = time.perf_counter()
        floquet.floquet_exponents(heli, opts.floquet_steps)
        print(f"{t1 - t0:10.2f} {time.perf_counter() - t1:10.2f}")
    sys.exit(0)
if args.duration:
    cfg["solver"]["duration_s"] = args.duration
heli = parse(helicopter.HelicopterSection, cfg, "helicopter")
if args.flight:
    from uavdamp.helicopter import flight

    options = heli.solver
    print(
        f"{options.duration:g} s record, step {options.step:g} s, {heli.aerodynamics.n_stations} stations, "
        f"inflow {heli.aerodynamics.inflow}, fast module: {args.fast}"
    )
    print(f"{'vacuum s':>9} {'trim s':>7} {'flight s':>9} {'hover s':>8} {'ratio':>6} {'update us':>9}")
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        helicopter.solve(helicopter.build(heli), options)
        t1 = time.perf_counter()
        fh, speed, result = flight.trimmed(heli, "hover")
        t2 = time.perf_counter()
        sim, _ = flight.fly_trimmed(fh, speed, result)
        t3 = time.perf_counter()
        q, q_t = sim.state()
        n = 2000
        t4 = time.perf_counter()
        for _ in range(n):
            sim.loads.update(q, q_t)
        update = (time.perf_counter() - t4) / n
        vacuum, hover = t1 - t0, t3 - t1
        print(f"{vacuum:9.2f} {t2 - t1:7.2f} {t3 - t2:9.2f} {hover:8.2f} {hover / vacuum:6.2f} {1e6 * update:9.1f}")
    sys.exit(0)
options = heli.solver
print(f"{options.duration:g} s simulated, step {options.step:g} s, fast module: {args.fast}")
print(f"{'build s':>8} {'solve wall s':>12} {'solve cpu s':>11} {'sim s / wall s':>14} {'newton it.':>10}")
for _ in range(args.repeats):
    t0 = time.perf_counter()
    model = helicopter.build(heli)
    t1, c1 = time.perf_counter(), time.process_time()
    stats = helicopter.solve(model, options)
    t2, c2 = time.perf_counter(), time.process_time()
    print(
        f"{t1 - t0:8.3f} {t2 - t1:12.2f} {c2 - c1:11.2f} {options.duration / (t2 - t1):14.2f} "
        f"{stats['newton_iterations']:10d}"
    )
