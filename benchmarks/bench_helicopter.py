"""Benchmark: the paper's 50 s imbalanced-rotor run (default config), simulated seconds per wall second.

Usage: python benchmarks/bench_helicopter.py [--fast] [--repeats N] [--duration S]
--fast loads Exudyn's AVX2 module without range checks, as the pipeline does. Target: >= 4 s/s.
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
args = parser.parse_args()
if args.fast:
    sys.exudynFast = True

from uavdamp import helicopter  # noqa: E402

cfg = yaml.safe_load((Path(__file__).resolve().parents[1] / "config" / "config.yaml").read_text())["helicopter"]
if args.duration:
    cfg["solver"]["duration"] = args.duration
heli = helicopter.Helicopter.from_config(cfg)
options = helicopter.SolverOptions.from_config(cfg["solver"])
print(f"{options.duration:g} s simulated, step {options.step:g} s, fast module: {args.fast}")
print(f"{'build s':>8} {'solve wall s':>12} {'solve cpu s':>11} {'sim s / wall s':>14} {'newton it.':>10}")
for _ in range(args.repeats):
    t0 = time.perf_counter()
    model = helicopter.build(heli)
    t1, c1 = time.perf_counter(), time.process_time()
    stats = helicopter.solve(model, options)
    t2, c2 = time.perf_counter(), time.process_time()
    print(f"{t1 - t0:8.3f} {t2 - t1:12.2f} {c2 - c1:11.2f} {options.duration / (t2 - t1):14.2f} "
          f"{stats['newton_iterations']:10d}")
