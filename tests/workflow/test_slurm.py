"""The reference table on a real (throwaway, single-node) SLURM cluster, through profiles/slurm.

Needs root (to install and start Debian's slurmctld/slurmd/munge: tests/slurm/cluster.py) and the
executor plugin from the `test` extra; skipped with the reason otherwise (set UAVDAMP_REQUIRE_SLURM=1
to turn such a skip into a failure). Run alone with `pytest -m slurm -s` to see the wall times.
"""

from __future__ import annotations

import importlib.util
import os
import re
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT, copy_workflow, load_config, load_module, plugin_override, snakemake

from uavdamp import io

pytestmark = [pytest.mark.slurm, pytest.mark.slow]  # a SLURM cluster and Snakemake: out of the inner loop too

TARGET = "reports-quick/reference_table/table.nc"
PROFILE = ROOT / "profiles" / "slurm"
RUN_TIMEOUT_S = 600  # hard kill (SIGKILL) of a hung Snakemake: it has been seen to ignore SIGTERM/SIGINT
CHUNK_THREADS = 1  # CPUs per chunk job on the 2-CPU test node: two chunks run at once
SUBMITTED = re.compile(r"Job (\d+) has been submitted with SLURM jobid (\d+) \(log: (\S+)\)")


def _unavailable(reason: str):
    if os.environ.get("UAVDAMP_REQUIRE_SLURM") == "1":
        pytest.fail(f"SLURM test required but unavailable: {reason}")
    pytest.skip(reason)


@pytest.fixture(scope="session")
def slurm_cluster():
    """A single-node cluster for the session; SLURM_CONF set for Snakemake and its jobs."""
    if importlib.util.find_spec("snakemake_executor_plugin_slurm") is None:
        _unavailable("snakemake-executor-plugin-slurm not installed (pip install -e '.[test]')")
    if os.geteuid() != 0:
        _unavailable("not root: the throwaway SLURM cluster needs root to install and start its daemons")
    cluster_mod = load_module(ROOT / "tests/workflow/slurm/cluster.py", "uavdamp_test_slurm_cluster")
    cluster = cluster_mod.LocalCluster(log=lambda msg: print(f"[slurm cluster] {msg}"))
    t0 = time.monotonic()
    try:
        cluster.start()
    except cluster_mod.ClusterUnavailable as exc:
        _unavailable(f"could not start a local SLURM cluster: {exc}")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("SLURM_CONF", str(cluster.conf))
        try:
            yield cluster
        finally:
            cluster.stop()
            print(
                f"[slurm cluster] up (incl. any apt install) {cluster.started_s:.1f} s; "
                f"start to stop {time.monotonic() - t0:.1f} s"
            )


@pytest.fixture(scope="module")
def n_chunks() -> int:
    return load_config("quick.yaml")["reference_table"]["n_chunks"]


def local_run(request) -> Path:
    """The same target run locally: the session's quick run (one worker per chunk, as on the cluster; that two
    workers give the same numbers is tests/test_reference_table.py's), whose plug-in override sets no
    reference_table key. The numbers the cluster must reproduce bit for bit. Asked for only when the cluster's
    table is there, so that under pytest-xdist the two run side by side."""
    assert "reference_table" not in plugin_override()
    return request.getfixturevalue("quick_run")


def run_on_slurm(workdir: Path, cluster, *extra: str) -> tuple[object, dict[str, tuple[str, str]], float]:
    """`snakemake --profile profiles/slurm TARGET` with the test cluster's overrides.

    Returns the result, {scatteritem or rule: (snakemake jobid, SLURM jobid)} of the submitted
    jobs, and the wall time. The overrides are exactly what a user changes in the profile:
    account and partition, and threads/CPUs/memory that fit the machine (2 chunks of 1 CPU at once).
    """
    args = [
        "--profile",
        str(PROFILE),
        TARGET,
        "--configfile",
        "config/quick.yaml",
        "--default-resources",
        "slurm_account=uavdamp_test",
        f"slurm_partition={cluster.partition}",
        "mem_mb=1000",
        "runtime=30",
        "--set-threads",
        f"reference_table_chunk={CHUNK_THREADS}",
        "--set-resources",
        f"reference_table_chunk:cpus_per_task={CHUNK_THREADS}",
        "reference_table_chunk:mem_mb=1500",
        "reference_table_chunk:runtime=30",
        # no slurmdbd here: poll with squeue (the cluster keeps finished jobs for MinJobAge=300 s)
        "--slurm-status-command",
        "squeue",
        "--slurm-init-seconds-before-status-checks",
        "2",
        "--slurm-keep-successful-logs",
        "--latency-wait",
        "5",
        *extra,
    ]
    t0 = time.monotonic()
    result = snakemake(workdir, *args, timeout=RUN_TIMEOUT_S)
    wall = time.monotonic() - t0
    submitted = {}
    for sm_id, slurm_id, log in SUBMITTED.findall(result.stdout + result.stderr):
        parts = Path(log).relative_to(workdir / ".snakemake" / "slurm_logs").parts  # rule_X/[wildcards/]ID.log
        key = parts[1] if parts[0] == "rule_reference_table_chunk" else parts[0].removeprefix("rule_")
        key = key.removeprefix("scatteritem_")
        submitted[key] = (sm_id, slurm_id)
    return result, submitted, wall


def _items(n: int) -> list[str]:
    return [f"{i}-of-{n}" for i in range(1, n + 1)]


def _assert_same_numbers(workdir: Path, reference: Path) -> None:
    for name in ("grid.nc", "table.nc"):
        got = io.open_dataset(workdir / "reports-quick/reference_table" / name)
        want = io.open_dataset(reference / "reports-quick/reference_table" / name)
        assert set(got.data_vars) == set(want.data_vars), name
        for var in want.data_vars:
            np.testing.assert_array_equal(got[var].values, want[var].values, err_msg=f"{name}:{var}")
        for coord in want.coords:
            np.testing.assert_array_equal(got[coord].values, want[coord].values, err_msg=f"{name}:{coord}")


def _assert_ran_as_slurm_job(cluster, workdir: Path, item: str, slurm_id: str, state: str) -> None:
    """The chunk's own log names the SLURM job; SLURM's records agree (rule, wildcards, state, CPUs)."""
    log = (workdir / f"reports-quick/logs/reference_table/{item}.log").read_text()
    if state == "COMPLETED":  # a chunk forced to fail raises before it logs its job id
        assert re.search(rf"SLURM job {slurm_id}\b", log), log[-2000:]
        assert f" {CHUNK_THREADS} workers" in log, "the chunk's joblib must use the job's threads"
    record = cluster.job_record(slurm_id)  # scontrol show job: kept for MinJobAge after the end
    assert record.get("JobState") == state, record
    assert record.get("Comment") == f"rule_reference_table_chunk_wildcards_{item}", record
    assert record.get("NumCPUs") == str(CHUNK_THREADS) and record.get("WorkDir") == str(workdir), record
    completion = cluster.completed_jobs()[slurm_id]  # jobcomp/filetxt: SLURM's completion log
    assert completion["JobState"] == state and completion["NodeList"] == "localhost", completion


def test_failed_chunk_is_reported_and_rerun_resumes(slurm_cluster, n_chunks, tmp_path, monkeypatch, request):
    """The reference table through the SLURM profile, one chunk failing on purpose: the failure is reported and the
    other chunks finish as SLURM jobs; the rerun submits only the failed chunk and the gather, keeps the finished
    chunks, and the table equals the local run's bit for bit. Every chunk and the gather ran as a SLURM job (the
    clean run's checks, which this covers: one cluster run fewer)."""
    items = _items(n_chunks)
    bad = items[1]
    workdir = copy_workflow(tmp_path)
    chunks = workdir / "reports-quick/reference_table/chunks"

    # the chunk's job raises (tests/slurm/fail_chunk/sitecustomize.py, loaded by every job's Python)
    monkeypatch.setenv(
        "PYTHONPATH",
        os.pathsep.join(filter(None, [str(ROOT / "tests/workflow/slurm/fail_chunk"), os.environ.get("PYTHONPATH")])),
    )
    monkeypatch.setenv("UAVDAMP_TEST_FAIL_CHUNK", bad)
    result, first, wall = run_on_slurm(workdir, slurm_cluster)
    submitted = first
    print(f"[slurm] run with chunk {bad} failing: {wall:.1f} s")
    output = result.stdout + result.stderr
    assert result.returncode != 0, output[-6000:]
    assert "Error in rule reference_table_chunk" in output, output[-6000:]
    assert f"SLURM-job '{submitted[bad][1]}' failed" in output, output[-6000:]
    assert "failed on purpose" in (workdir / f"reports-quick/logs/reference_table/{bad}.log").read_text()
    _assert_ran_as_slurm_job(slurm_cluster, workdir, bad, submitted[bad][1], "FAILED")
    good = [item for item in items if item != bad]
    for item in good:  # keep-going (profile): the other chunks finished
        _assert_ran_as_slurm_job(slurm_cluster, workdir, item, submitted[item][1], "COMPLETED")
    assert sorted(p.stem for p in chunks.glob("*.nc")) == sorted(good)
    assert not (workdir / TARGET).exists()
    kept = {item: (chunks / f"{item}.nc").stat().st_mtime_ns for item in good}

    monkeypatch.delenv("UAVDAMP_TEST_FAIL_CHUNK")
    result, submitted, wall = run_on_slurm(workdir, slurm_cluster)
    print(f"[slurm] rerun (resume): {wall:.1f} s")
    output = result.stdout + result.stderr
    assert result.returncode == 0, output[-6000:]
    assert set(submitted) == {bad, "reference_table"}, f"only the failed chunk and the gather rerun: {submitted}"
    assert set(first) | set(submitted) == {*items, "reference_table"}, (first, submitted)
    _assert_ran_as_slurm_job(slurm_cluster, workdir, bad, submitted[bad][1], "COMPLETED")
    for item, mtime in kept.items():
        assert (chunks / f"{item}.nc").stat().st_mtime_ns == mtime, f"finished chunk {item} was recomputed"
    _assert_same_numbers(workdir, local_run(request))
