"""Benchmark of the platform model: build vs solve time of a 5 s mono-frequency run, Newton iterations.

Usage: PYTHONPATH=src python benchmarks/bench_platform.py [--config config/config.yaml] [--repeat 5]
Times are the best of --repeat runs (wall clock, one process); Newton iterations are counts.
"""

import argparse
import statistics
import time

import yaml

from uavdamp.damping.laws import Constant, Schedule
from uavdamp.platform import ExudynPlant, PlatformParams
from uavdamp.settings import parse, view
from uavdamp.sources.excitation import sine_input

DURATION = 5.0  # s, run length
FREQ_Y_HZ, FREQ_Z_HZ = 7.0, 8.0  # near the paper's fuselage Y (44.04 rad/s) and Z (50.58 rad/s) peaks
AMPLITUDE = 1.3e-3  # m (paper)
DAMPING = 2.0  # N s m-1, isolator damping of the timed runs


def _timed(sim: ExudynPlant) -> list[float]:
    """Accumulate the time spent in the simulator's per-step Python into the returned one-element list."""
    spent = [0.0]
    prepare = sim._prepare_step

    def timed(mbs, t):
        t0 = time.perf_counter()
        result = prepare(mbs, t)
        spent[0] += time.perf_counter() - t0
        return result

    sim._prepare_step = timed
    return spent


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--config", default="config/config.yaml")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    with open(args.config) as f:
        params = parse(PlatformParams, view(yaml.safe_load(f)["platform"], PlatformParams), "platform")
    h = params.time_step
    t, y, z = sine_input(FREQ_Y_HZ, FREQ_Z_HZ, AMPLITUDE, DURATION, h)
    print(f"{DURATION:g} s run at {FREQ_Y_HZ:g} Hz (y), {FREQ_Z_HZ:g} Hz (z); time step {h:g} s ({t.size - 1} steps)")
    print("solve = Exudyn's SolveSystem, of which pre-step = the per-step Python (input, damping, servo I term);")
    print("other = the rest of run() (argument checks, resampling, dataset)")
    print(f"{'variant':<20}{'build s':>9}{'solve s':>9}{'pre-step s':>12}{'other s':>9}{'Newton it.':>12}")
    for mount, body in (("isolated", "full"), ("rigid", "full"), ("isolated", "lumped")):
        builds, solves, totals, pre = [], [], [], []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            sim = ExudynPlant(params, mount=mount, body=body)
            builds.append(time.perf_counter() - t0)
            pre_step = _timed(sim)
            t0 = time.perf_counter()
            sim.run(t, y, z, stiffness=params.isolator_stiffness, law=Constant(DAMPING))
            totals.append(time.perf_counter() - t0)
            solves.append(sim.solve_time)
            pre.append(pre_step[0])
        rest = [total - solve for total, solve in zip(totals, solves, strict=True)]
        print(
            f"{mount + ', ' + body:<20}{min(builds):>9.4f}{min(solves):>9.3f}{min(pre):>12.3f}"
            f"{statistics.median(rest):>9.4f}{sim.newton_iterations:>12d}"
        )

    print("\nNewton iterations, isolated platform, K = 10 N/m (Jacobian updates in brackets)")
    schedule = [2.0, 20.0] * int(DURATION / params.update_period / 2 + 1)
    for body in ("full", "lumped"):
        sim = ExudynPlant(params, body=body)
        counts = {}
        for label, law in (
            ("constant C = 2", Constant(2.0)),
            ("constant C = 20", Constant(20.0)),
            (f"switched 2/20 every {params.update_period:g} s", Schedule(schedule)),
        ):
            sim.run(t, y, z, stiffness=10.0, law=law)
            counts[label] = (sim.newton_iterations, sim.jacobian_updates)
        line = "; ".join(f"{k}: {n} ({j})" for k, (n, j) in counts.items())
        print(f"  {body}: {line}")


if __name__ == "__main__":
    main()
