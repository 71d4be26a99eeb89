"""Benchmark: reference-table grid points per second, linear plant (batched) vs Exudyn plant, one core.

Usage: python benchmarks/bench_grid.py [--blocks N] [--exudyn-points N] [--stage]
Both plants on the same points of the default config's grid: the linear plant evaluates N whole
(K, C) blocks (every (f_y, f_z) of each, batched); the Exudyn plant a seeded sample of those points
(its cost per point does not depend on which). Prints points/s of each, the ratio (target >= 100)
and the largest relative criterion difference on the sample.
--stage also times the whole default grid as the pipeline's stage computes it (one chunk, 2 workers),
the gather job's verification (2 workers) and prints the scheduling gain per stiffness.
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np
import yaml

os.environ.setdefault("EXUDYN_MODULE", "fast")  # as the pipeline's jobs (workflow/Snakefile)

from uavdamp.config.load import load  # noqa: E402
from uavdamp.reference_table import GridSpec, chunks, grid, verify  # noqa: E402
from uavdamp.reference_table import criteria as criterion  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--blocks", type=int, default=8, help="(K, C) blocks for the linear plant")
parser.add_argument("--exudyn-points", type=int, default=40, help="points of those blocks for the Exudyn plant")
parser.add_argument("--stage", action="store_true", help="also time the whole default grid and its verification")
args = parser.parse_args()

typed = load(yaml.safe_load((Path(__file__).resolve().parents[1] / "config" / "config.yaml").read_text()))
platform = typed.platform
spec = GridSpec.of(typed.reference_table)
rng = np.random.default_rng(11)
n_blocks = spec.stiffness.size * spec.damping.size
blocks = np.sort(rng.choice(n_blocks, size=min(args.blocks, n_blocks), replace=False))
points = np.concatenate([grid.block_points(spec, b) for b in blocks])
sample = np.sort(rng.choice(points, size=min(args.exudyn_points, points.size), replace=False))
print(f"default grid: {spec.size} points in {n_blocks} (K, C) blocks of {spec.freq_y.size * spec.freq_z.size}")

chunks.evaluate_batch(platform, spec, blocks[:1])  # build and linearise outside the timing
t0 = time.perf_counter()
linear = chunks.evaluate_batch(platform, spec, blocks)
linear_rate = points.size / (time.perf_counter() - t0)
verify.evaluate_points(platform, spec, sample[:1], "exudyn")  # build outside the timing
t0 = time.perf_counter()
exudyn = verify.evaluate_points(platform, spec, sample, "exudyn")
exudyn_rate = sample.size / (time.perf_counter() - t0)
t0 = time.perf_counter()
verify.evaluate_points(platform, spec, sample, "linear")
single_rate = sample.size / (time.perf_counter() - t0)

on_sample = linear["criterion"][[int(np.flatnonzero(linear["indices"] == p)[0]) for p in sample]]
difference = np.abs(on_sample / exudyn - 1).max()
print(f"{'plant':>24} {'points':>7} {'points/s':>10}")
print(f"{'linear, batched':>24} {points.size:7d} {linear_rate:10.0f}")
print(f"{'linear, one point a call':>24} {sample.size:7d} {single_rate:10.0f}")
print(f"{'exudyn':>24} {sample.size:7d} {exudyn_rate:10.1f}")
print(f"ratio linear (batched) / exudyn per point, one core: {linear_rate / exudyn_rate:.0f}x (target >= 100x)")
print(f"largest relative criterion difference on the {sample.size} Exudyn points: {difference:.3%}")

if args.stage:
    t0 = time.perf_counter()
    ds = chunks.run_chunk(platform, spec, n_chunks=1, chunk=0, n_jobs=2)
    stage = time.perf_counter() - t0
    full = chunks.merge_chunks(spec, [ds])
    check = typed.reference_table.verify
    t0 = time.perf_counter()
    checked = verify.verify(platform, spec, full, check, n_jobs=2)
    verify_time = time.perf_counter() - t0
    worst = int(np.argmax(checked.verify_relative_difference.values))
    print(f"whole grid, 2 workers: {stage:.1f} s ({spec.size / stage:.0f} points/s), {ds.attrs['n_failed']} failed")
    print(
        f"verification ({check.n_points} Exudyn points, 2 workers): {verify_time:.1f} s, largest difference "
        f"{float(checked.verify_max_relative_difference):.3%} at point "
        f"{spec.point(int(checked.verify_point.values[worst]))}"
    )
    table = criterion.reference_table(full, typed.reference_table.flat_tolerance)
    table = table.sel(criterion="displacement", window="transient")
    for k, gain, spread in zip(
        spec.stiffness, table.scheduling_gain.values, table.damping_opt_spread.values, strict=True
    ):
        print(
            f"K {k:7.1f} N/m: scheduling gain {gain:.3f}, optimal damping spread {spread:.1f}, "
            f"best constant C {float(table.damping_best_constant.sel(stiffness=k)):.3g} N s/m"
        )
