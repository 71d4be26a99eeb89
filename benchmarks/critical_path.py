"""Benchmark: where a finished run's time went, from Snakemake's own records of it.

Usage: python benchmarks/critical_path.py [RUN_DIR] [--output-dir reports] [--top N]

Reads RUN_DIR/.snakemake/metadata (one record per output file: the rule, the inputs, the job's start and end) for
the jobs whose outputs lie under --output-dir, and prints the run's span (first start to last end), the sum of the
jobs' wall times, the critical path (the longest chain of jobs each of which needs an output of the one before, by
wall time) with each job on it, the lower bound on the span with C cores, max(critical path, sum / C), and the
--top longest jobs. Wall times are as the run measured them, so with other work on the cores they are longer.
"""

from __future__ import annotations

import argparse
import base64
import json
from dataclasses import dataclass
from graphlib import TopologicalSorter
from pathlib import Path


@dataclass(frozen=True)
class Job:
    """One finished job: its rule, outputs and inputs (paths relative to the run folder) and wall time, s."""

    rule: str
    outputs: tuple[str, ...]
    inputs: tuple[str, ...]
    start: float
    end: float

    @property
    def wall(self) -> float:
        return self.end - self.start


def _decoded(relative: Path) -> str:
    """The output path a metadata file records (its name is the path, URL-safe base64, split at the name limit)."""
    name = "".join(relative.parts)
    return base64.urlsafe_b64decode(name + "=" * (-len(name) % 4)).decode()


def read_jobs(run_dir: Path, output_dir: str) -> list[Job]:
    """The run's finished jobs with an output under output_dir, from .snakemake/metadata (grouped by job hash)."""
    root = run_dir / ".snakemake" / "metadata"
    if not root.is_dir():
        raise SystemExit(f"{root}: no Snakemake metadata (run the workflow in {run_dir} first)")
    records: dict[tuple, dict] = {}
    for path in (p for p in root.rglob("*") if p.is_file()):
        output = _decoded(path.relative_to(root))
        if not output.startswith(output_dir.rstrip("/") + "/"):
            continue
        record = json.loads(path.read_text())
        if record.get("incomplete") or record.get("starttime") is None or record.get("endtime") is None:
            continue
        key = (record["rule"], record["job_hash"], record["endtime"])  # a job's outputs: one end, starts apart by µs
        entry = records.setdefault(key, {"inputs": tuple(record["input"]), "start": record["starttime"], "outputs": []})
        entry["start"] = min(entry["start"], record["starttime"])
        entry["outputs"].append(output)
    jobs = [Job(key[0], tuple(sorted(e["outputs"])), e["inputs"], e["start"], key[2]) for key, e in records.items()]
    if not jobs:
        raise SystemExit(f"{root}: no finished job with an output under {output_dir}/")
    return jobs


def critical_path(jobs: list[Job]) -> list[Job]:
    """The chain of jobs, first to last, whose wall times add up to the most, each needing an output of the one
    before (inputs made by no job of the list, such as data files, start a chain)."""
    made_by = {output: job for job in jobs for output in job.outputs}
    needs = {job: {made_by[i] for i in job.inputs if i in made_by} for job in jobs}
    finish: dict[Job, float] = {}
    before: dict[Job, Job | None] = {}
    for job in TopologicalSorter(needs).static_order():
        previous = max(needs[job], key=lambda j: finish[j], default=None)
        before[job] = previous
        finish[job] = job.wall + (finish[previous] if previous is not None else 0.0)
    chain = [max(finish, key=finish.get)]
    while before[chain[-1]] is not None:
        chain.append(before[chain[-1]])
    return chain[::-1]


def _label(job: Job) -> str:
    """The rule and its first NetCDF output (else its first output), with the number of the others."""
    first = next((o for o in job.outputs if o.endswith(".nc")), job.outputs[0])
    more = f" (+{len(job.outputs) - 1})" if len(job.outputs) > 1 else ""
    return f"{job.rule:<28} {first}{more}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run_dir", nargs="?", default=".", type=Path)
    parser.add_argument("--output-dir", default="reports")
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--top", type=int, default=10)
    args = parser.parse_args()
    jobs = read_jobs(args.run_dir, args.output_dir)
    span = max(j.end for j in jobs) - min(j.start for j in jobs)
    total = sum(j.wall for j in jobs)
    chain = critical_path(jobs)
    length = sum(j.wall for j in chain)
    print(f"{len(jobs)} jobs under {args.output_dir}/: span {span:.1f} s, job wall times add up to {total:.1f} s")
    print(f"critical path {length:.1f} s over {len(chain)} jobs; on {args.cores} cores the span is at least")
    print(f"max(critical path, sum / {args.cores}) = {max(length, total / args.cores):.1f} s")
    print("\ncritical path (wall s; s from the end of the job before to this one's start; rule, output):")
    for previous, job in zip([None, *chain[:-1]], chain, strict=True):
        gap = f"{job.start - previous.end:7.1f}" if previous is not None else " " * 7
        print(f"  {job.wall:7.1f} {gap}  {_label(job)}")
    print(f"\nthe {args.top} longest jobs (wall s, rule, output):")
    for job in sorted(jobs, key=lambda j: j.wall, reverse=True)[: args.top]:
        print(f"  {job.wall:7.1f}  {_label(job)}")


if __name__ == "__main__":
    main()
