"""benchmarks/critical_path.py: a run's jobs, span and critical path from Snakemake's metadata."""

from __future__ import annotations

import base64
import json

import pytest
from conftest import QUICK_RUN_ARGS, ROOT, load_module, planned_rules, snakemake_dry

cp = load_module(ROOT / "benchmarks/critical_path.py", "uavdamp_critical_path")


def _record(root, output, rule, inputs, start, end, job: int, split: int = 0, incomplete: bool = False):
    """A metadata record as Snakemake writes it: the output path URL-safe base64, cut into folders of `split`
    characters when given (Snakemake cuts at the file system's name limit)."""
    name = base64.urlsafe_b64encode(output.encode()).decode()
    parts = [name[i : i + split] for i in range(0, len(name), split)] if split else [name]
    path = root.joinpath(*parts)
    path.parent.mkdir(parents=True, exist_ok=True)
    record = {
        "rule": rule,
        "input": inputs,
        "starttime": start,
        "endtime": end,
        "job_hash": job,
        "incomplete": incomplete,
    }
    path.write_text(json.dumps(record))


def test_the_longest_chain_of_a_hand_made_run(tmp_path):
    """A diamond a -> (b, c) -> d and a lone e: by hand, the critical path is a, b, d (2 + 5 + 1 = 8 s; a, c, d
    is 2 + 1 + 1), the jobs' sum 2 + 5 + 1 + 1 + 6 = 15 s; a job with two outputs counts once
    (its records start microseconds apart), a long output name cut into folders is read back, an incomplete
    record and another output folder's are left out."""
    run = tmp_path
    root = run / ".snakemake" / "metadata"
    long_name = "r/" + "x" * 120 + ".nc"
    _record(root, "r/a.nc", "a", ["data/in.csv"], 0.0, 2.0, 1)
    _record(root, "r/a.png", "a", ["data/in.csv"], 0.000_01, 2.0, 1)
    _record(root, "r/b.nc", "b", ["r/a.nc"], 2.5, 7.5, 2)
    _record(root, long_name, "c", ["r/a.png"], 2.0, 3.0, 3, split=40)
    _record(root, "r/d.nc", "d", ["r/b.nc", long_name], 8.0, 9.0, 4)
    _record(root, "r/e.nc", "e", [], 0.0, 6.0, 5)
    _record(root, "other/f.nc", "f", [], 0.0, 50.0, 6)
    _record(root, "r/g.nc", "g", [], 0.0, 1.0, 7, incomplete=True)
    jobs = cp.read_jobs(run, "r")
    assert sorted(j.rule for j in jobs) == ["a", "b", "c", "d", "e"]
    assert next(j for j in jobs if j.rule == "a").outputs == ("r/a.nc", "r/a.png")
    chain = cp.critical_path(jobs)
    assert [j.rule for j in chain] == ["a", "b", "d"]
    assert sum(j.wall for j in chain) == pytest.approx(8.0)
    assert sum(j.wall for j in jobs) == pytest.approx(15.0)


def test_a_folder_without_metadata_is_refused_naming_it(tmp_path):
    with pytest.raises(SystemExit, match=r"\.snakemake/metadata: no Snakemake metadata"):
        cp.read_jobs(tmp_path, "reports")


@pytest.mark.slow
def test_the_quick_runs_critical_path_is_a_chain_of_its_own_jobs(quick_run):
    """On the quick run: the jobs are those of the plan of all targets (Snakemake's own dry run, every job
    forced), each job on the path reads an output of the one before, and the path fits in the run's span (jobs
    of a chain run one after another) while being at least its longest job."""
    jobs = cp.read_jobs(quick_run, "reports-quick")
    plan = planned_rules(snakemake_dry(quick_run, "-n", "--forceall", "all", "benchmark", *QUICK_RUN_ARGS))
    assert {j.rule for j in jobs} == plan - {"all", "benchmark"}
    chain = cp.critical_path(jobs)
    for before, after in zip(chain, chain[1:], strict=False):
        assert set(before.outputs) & set(after.inputs), (before.rule, after.rule)
    span = max(j.end for j in jobs) - min(j.start for j in jobs)
    assert max(j.wall for j in jobs) <= sum(j.wall for j in chain) <= span
