"""Benchmark: reference-table grid points per second with 1 and 2 joblib workers (default config).

Usage: python benchmarks/bench_grid.py [--points N]
Reports points/s, the parallel efficiency (rate with 2 workers / 2 x rate with 1) and the time
outside the solver (building, Python, joblib, I/O) as a fraction of the solver's time.
Targets (issue): efficiency >= 85 %, outside-solver time <= 10 %.
"""

import argparse
import os
import time
from pathlib import Path

import yaml

os.environ.setdefault("EXUDYN_MODULE", "fast")  # as the pipeline's chunk jobs

from uavdamp import grid  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--points", type=int, default=160, help="grid points per measurement")
args = parser.parse_args()

cfg = yaml.safe_load((Path(__file__).resolve().parents[1] / "config" / "config.yaml").read_text())
platform = {k: v for k, v in cfg["platform"].items() if k != "response"}
spec = grid.GridSpec.from_config(cfg["reference_table"])
n_chunks = max(1, spec.size // args.points)  # one strided chunk of about --points points

print(f"{spec.size} grid points, measuring chunk 1 of {n_chunks} ({len(grid.chunk_points(spec.size, n_chunks, 0))} points)")
print(f"{'workers':>7} {'wall s':>8} {'points/s':>9} {'solver s':>9} {'outside solver':>15}")
rates = {}
for n_jobs in (1, 2):
    t0 = time.perf_counter()
    ds = grid.run_chunk(platform, spec, n_chunks=n_chunks, chunk=0, n_jobs=n_jobs)
    wall = time.perf_counter() - t0
    rates[n_jobs] = ds.sizes["point"] / wall
    outside = (n_jobs * wall - ds.attrs["solver_time_s"]) / ds.attrs["solver_time_s"]
    print(f"{n_jobs:7d} {wall:8.2f} {rates[n_jobs]:9.2f} {ds.attrs['solver_time_s']:9.2f} {outside:14.1%}")
print(f"parallel efficiency with 2 workers: {rates[2] / (2 * rates[1]):.1%}")
