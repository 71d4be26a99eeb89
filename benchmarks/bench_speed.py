"""Benchmark: the three speed figures of the quick start, each in a fresh clone of HEAD, with the machine's load.

Usage: python benchmarks/bench_speed.py [--only study|benchmark|tests] [--repeats N] [--cores N]

study      `snakemake -jN all` from nothing (target: 60 s on 2 cores)
benchmark  `snakemake -jN benchmark` after the study in the same clone (target: 3 min)
tests      the README's test command, `pytest`, with CI=true (target: 6 min)

Each figure is the median wall time of --repeats runs (default 1: the test command takes minutes), printed with the
1-minute load average before and after each run and the number of cores, so that a figure measured on a busy
machine says so. The clone's own `src/` is imported (PYTHONPATH), with this interpreter and its installed
dependencies: commit first, HEAD is what is timed.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
STEPS = {
    "study": lambda cores: [sys.executable, "-m", "snakemake", f"-j{cores}", "all"],
    "benchmark": lambda cores: [sys.executable, "-m", "snakemake", f"-j{cores}", "benchmark"],
    "tests": lambda cores: [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider"],
}


def timed(command: list[str], cwd: Path) -> tuple[float, float, float]:
    """(wall s, load before, load after) of one run; a failed run stops the benchmark naming it."""
    env = dict(os.environ, PYTHONPATH=str(cwd / "src"), CI="true")
    before = os.getloadavg()[0]
    start = time.perf_counter()
    result = subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if result.returncode != 0:
        sys.exit(f"{' '.join(command[2:])} failed in {cwd}:\n{(result.stdout + result.stderr)[-3000:]}")
    return wall, before, os.getloadavg()[0]


def clone(into: Path) -> Path:
    """A fresh clone of this checkout's HEAD."""
    subprocess.run(["git", "clone", "-q", str(ROOT), str(into)], check=True)
    return into


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--only", choices=list(STEPS), action="append", help="default: study and benchmark")
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--cores", type=int, default=2)
    args = parser.parse_args()
    chosen = args.only or ["study", "benchmark"]
    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True).stdout
    print(f"HEAD {head.strip()}, {os.cpu_count()} cores on the machine, -j{args.cores}")
    print(f"{'figure':<10} {'run':>4} {'wall s':>8} {'load before':>12} {'load after':>11}")
    for name in chosen:
        walls = []
        for k in range(args.repeats):
            with tempfile.TemporaryDirectory() as tmp:
                work = clone(Path(tmp) / "uavdamp")
                if name == "benchmark":  # after the study, as the README runs it
                    timed(STEPS["study"](args.cores), work)
                wall, before, after = timed(STEPS[name](args.cores), work)
            walls.append(wall)
            print(f"{name:<10} {k + 1:>4} {wall:>8.1f} {before:>12.2f} {after:>11.2f}")
        print(f"{name:<10} {'median':>4} {statistics.median(walls):>8.1f}")


if __name__ == "__main__":
    main()
