"""Benchmark: the three speed figures of the quick start, each in a fresh clone of HEAD, with the machine's load.

Usage: python benchmarks/bench_speed.py [--only study|benchmark|tests] [--repeats N] [--cores N] [--vs REV]

study      `snakemake -jN all` from nothing (target: 60 s on 2 cores)
benchmark  `snakemake -jN benchmark` after the study in the same clone (target: 3 min)
tests      the README's test command, `pytest`, with CI=true (target: 6 min)

Each figure is the median wall time of --repeats runs (default 1: the test command takes minutes), printed with the
CPU time of the run (user + system, every process it started), the 1-minute load average before and after it and
the number of cores, so that a figure measured on a busy machine says so. The machine's own speed drifts too: on
2026-12-07 the study took 2 min 2 s (224 s of CPU) at 16:17 and 2 min 33 s (292 s of CPU, for the same jobs less
the 3 s a change between saved) at 17:21, both on warm caches. So each run is bracketed by a yardstick, a fixed
one-core workload of small numpy products and Python arithmetic (as the jobs' per-step code) in a fresh interpreter,
and the figure is also printed in yardsticks (wall / the yardstick's mean wall): a reading of the machine's
single-core speed beside the figure (it varied by 20 % between three calls within a minute on 2026-12-07, so it
shows a large drift, not a small one). The clone's own `src/` is imported (PYTHONPATH), with this interpreter and
its installed dependencies: commit first, HEAD is what is timed; its numba kernels compile in the run, as in any
fresh clone.

--vs REV times a second commit beside HEAD, the two in turn (HEAD first in odd repeats, REV first in even ones), each
in its own fresh clone; for the benchmark both clones run their study first, untimed, so that the two timed
benchmarks follow each other. Each pair prints HEAD's wall and CPU over REV's, and the medians of those ratios close
the table: on 2026-12-08 this machine ran the same benchmark in 3 min 15 s and in 4 min 54 s 35 minutes apart, so a
change of a few percent shows only in pairs.
"""

from __future__ import annotations

import argparse
import os
import resource
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


# the yardstick: about 1.5 s on one core of the 2026-12-07 machine (numpy's small products, then Python's arithmetic)
YARDSTICK = """
import numpy as np
a, x, s = np.linspace(0.0, 1.0, 12 * 24).reshape(12, 24), np.ones(24), 0.0
for k in range(400_000):
    s += float((a @ x)[k % 12])
s += sum(i * i % 7 for i in range(4_000_000))
"""


def children_cpu() -> float:
    """User + system CPU s of every finished child process so far (and theirs)."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def yardstick() -> float:
    """Wall s of one run of YARDSTICK in a fresh interpreter, its start-up included."""
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", YARDSTICK], check=True)
    return time.perf_counter() - start


def timed(command: list[str], cwd: Path) -> dict[str, float]:
    """Wall s, CPU s, load before and after of one run, and the yardstick's mean wall s around it; a failed run
    stops the benchmark naming it."""
    env = dict(os.environ, PYTHONPATH=str(cwd / "src"), CI="true")
    first, before, cpu = yardstick(), os.getloadavg()[0], children_cpu()
    start = time.perf_counter()
    result = subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True)
    wall, cpu = time.perf_counter() - start, children_cpu() - cpu
    if result.returncode != 0:
        sys.exit(f"{' '.join(command[2:])} failed in {cwd}:\n{(result.stdout + result.stderr)[-3000:]}")
    after = os.getloadavg()[0]
    return {"wall": wall, "cpu": cpu, "before": before, "after": after, "yardstick": (first + yardstick()) / 2}


def clone(into: Path, rev: str = "HEAD") -> Path:
    """A fresh clone of this checkout at `rev` (default its HEAD)."""
    subprocess.run(["git", "clone", "-q", str(ROOT), str(into)], check=True)
    if rev != "HEAD":
        subprocess.run(["git", "-C", str(into), "checkout", "-q", rev], check=True)
    return into


def prepared(name: str, rev: str, cores: int, into: Path) -> Path:
    """A fresh clone at `rev` ready for step `name`: for the benchmark, its study run first (untimed)."""
    work = clone(into, rev)
    if name == "benchmark":  # after the study, as the README runs it
        timed(STEPS["study"](cores), work)
    return work


def short(rev: str) -> str:
    """The abbreviated commit of `rev` in this checkout (a clear error if it names none)."""
    found = subprocess.run(["git", "rev-parse", "--short", rev], cwd=ROOT, capture_output=True, text=True)
    if found.returncode != 0:
        sys.exit(f"--vs {rev}: not a commit of {ROOT}")
    return found.stdout.strip()


def order(revs: list[str], repeat: int) -> list[str]:
    """The order the commits run in repeat `repeat` (0-based): as given in even repeats, reversed in odd ones, so that
    neither is always first."""
    return list(revs) if repeat % 2 == 0 else list(reversed(revs))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--only", choices=list(STEPS), action="append", help="default: study and benchmark")
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--vs", metavar="REV", help="a commit timed beside HEAD, in turn (module docstring)")
    args = parser.parse_args()
    chosen = args.only or ["study", "benchmark"]
    revs = ["HEAD"] + ([args.vs] if args.vs else [])
    labels = {rev: short(rev) for rev in revs}
    if len(set(labels.values())) < len(revs):
        sys.exit(f"--vs {args.vs}: names HEAD's own commit ({labels['HEAD']}); give another to compare with")
    print(f"{' vs '.join(labels.values())}, {os.cpu_count()} cores on the machine, -j{args.cores}")
    header = ("figure", "commit", "run", "wall s", "cpu s", "yardstick s", "yardsticks", "load before", "load after")
    print("{:<10} {:>8} {:>4} {:>8} {:>8} {:>12} {:>11} {:>12} {:>11}".format(*header))
    for name in chosen:
        runs: dict[str, list[dict]] = {rev: [] for rev in revs}
        for k in range(args.repeats):
            with tempfile.TemporaryDirectory() as tmp:
                works = {rev: prepared(name, rev, args.cores, Path(tmp) / f"uavdamp-{i}") for i, rev in enumerate(revs)}
                for rev in order(revs, k):
                    run = timed(STEPS[name](args.cores), works[rev])
                    runs[rev].append(run)
                    print(
                        f"{name:<10} {labels[rev]:>8} {k + 1:>4} {run['wall']:>8.1f} {run['cpu']:>8.1f} "
                        f"{run['yardstick']:>12.2f} {run['wall'] / run['yardstick']:>11.1f} {run['before']:>12.2f} "
                        f"{run['after']:>11.2f}"
                    )
        for rev in revs:
            walls = [r["wall"] for r in runs[rev]]
            units = [r["wall"] / r["yardstick"] for r in runs[rev]]
            median = f"{statistics.median(walls):>8.1f} {'':>8} {'':>12} {statistics.median(units):>11.1f}"
            print(f"{name:<10} {labels[rev]:>8} {'med':>4} {median}")
        if args.vs:
            pairs = list(zip(runs["HEAD"], runs[args.vs], strict=True))
            wall = statistics.median(a["wall"] / b["wall"] for a, b in pairs)
            cpu = statistics.median(a["cpu"] / b["cpu"] for a, b in pairs)
            print(
                f"{name:<10} {labels['HEAD']} / {labels[args.vs]}: median of {len(pairs)} pair(s), "
                f"wall {wall:.3f}, cpu {cpu:.3f}"
            )


if __name__ == "__main__":
    main()
