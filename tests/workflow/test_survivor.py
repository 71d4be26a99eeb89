"""A job that survived a killed run, held (SIGSTOP) while a rerun of another config finishes, then resumed: the
rerun's result stays, and the file names the run that made it."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import xarray as xr
import yaml
from conftest import copy_workflow, snakemake

TARGET = "reports-quick/platform/modes.nc"
FREQ_C = 7.3  # Hz, the highest of platform.structure.natural_frequencies_hz in the rerun's config (quick: 6.7)


def _job_pid(workdir: Path, timeout_s: float = 300.0) -> int:
    """The pid of this run directory's job script (Snakemake runs it from .snakemake/scripts)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        found = subprocess.run(["pgrep", "-f", f"{workdir}/.snakemake/scripts/"], capture_output=True, text=True)
        pids = [int(p) for p in found.stdout.split()]
        if pids:
            return pids[0]
        time.sleep(0.05)
    raise AssertionError("the job never started")


def _ended(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().split(")")[-1].split()[0] in ("Z", "X")
    except FileNotFoundError:
        return True


@pytest.mark.slow
def test_a_held_job_of_a_killed_run_does_not_replace_the_rerun_result(tmp_path):
    """Seen failing on the previous main: the resumed job of config A wrote platform/modes.nc over the rerun's
    (config C): its first mode read 6.7 Hz (A's) where the rerun's config asks 7.3 Hz."""
    workdir = copy_workflow(tmp_path.resolve() / "run")
    first_mode = {"platform": {"structure": {"natural_frequencies_hz": [FREQ_C, 5.7, 4.5]}}}
    (workdir / "config" / "c.yaml").write_text(yaml.safe_dump(first_mode))
    log = open(tmp_path / "a.log", "w")
    run_a = subprocess.Popen(
        [sys.executable, "-m", "snakemake", "-j1", "--configfile", "config/quick.yaml", "--", TARGET],
        cwd=workdir,
        stdout=log,
        stderr=subprocess.STDOUT,
        start_new_session=True,
    )
    survivor = None
    try:
        survivor = _job_pid(workdir)
        os.kill(survivor, signal.SIGSTOP)  # held before it wrote anything
        os.kill(run_a.pid, signal.SIGKILL)  # the run is killed; its job survives
        run_a.wait(60)
        assert not (workdir / TARGET).exists() and not _ended(survivor)
        assert snakemake(workdir, "--unlock").returncode == 0
        rerun = snakemake(
            workdir, "-j1", "--rerun-incomplete", "--configfile", "config/quick.yaml", "config/c.yaml", "--", TARGET
        )
        assert rerun.returncode == 0, rerun.stderr[-3000:]
        os.kill(survivor, signal.SIGCONT)
        deadline = time.monotonic() + 300
        while not _ended(survivor) and time.monotonic() < deadline:
            time.sleep(0.2)
        assert _ended(survivor)
    finally:
        if survivor is not None and not _ended(survivor):
            os.kill(survivor, signal.SIGKILL)
        log.close()
    with xr.open_dataset(workdir / TARGET, decode_times=False) as ds:
        assert float(ds.natural_frequency.max()) == pytest.approx(FREQ_C, rel=1e-6)  # the rerun's numbers (A: 6.7)
        made = dict(ds.attrs)
    from uavdamp import integrity

    job_log = (workdir / "reports-quick/logs/platform_modes.log").read_text()
    assert f"{TARGET}: not replaced: it holds the result of a later run" in job_log
    digest_a = re.search(r"belongs to an earlier run \(config digest (\w+),", job_log).group(1)
    digest_c = made["config_digest"]
    assert digest_a != digest_c and made["config_digest_rule"] == "platform_modes"
    # a consumer of the killed run's plan (config A) refuses the rerun's file, naming it and the rule that rebuilds it
    with pytest.raises(integrity.StaleInput, match=f"^{workdir / TARGET}: made with config digest {digest_c}") as err:
        integrity.check_inputs({str(workdir / TARGET): [digest_a, "platform_modes"]})
    assert "rule platform_modes rebuilds it" in str(err.value)
