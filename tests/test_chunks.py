"""Guarded chunks: one writer at a time, and the gather refuses a bad chunk naming it and its rebuild."""

from __future__ import annotations

import json
import multiprocessing
import shutil
import time
from functools import partial

import numpy as np
import pytest
import xarray as xr
from conftest import snakemake

from uavdamp import integrity, io
from uavdamp.reference_table import GridSpec, ReferenceGrid, chunks, grid
from uavdamp.settings import parse, view


def _spawn_holder(hold, path):
    """(process, first event, second event): `hold(path, first, second)` started in a spawned process."""
    ctx = multiprocessing.get_context("spawn")
    first, second = ctx.Event(), ctx.Event()
    holder = ctx.Process(target=hold, args=(str(path), first, second))
    holder.start()
    return holder, first, second


def _hold(path, ready, release):
    with chunks.exclusive(path):
        ready.set()
        release.wait(30)


def test_a_second_writer_stops_at_once_naming_the_file(tmp_path):
    """Another process holds the chunk's lock (a killed run's surviving job): the second writer is refused."""
    target = tmp_path / "chunks" / "2-of-3.nc"
    holder, ready, release = _spawn_holder(_hold, target)
    try:
        assert ready.wait(60)
        with pytest.raises(ValueError, match=rf"2-of-3.nc: another process \(.*~{holder.pid}, host~pid\) has held"):
            with chunks.exclusive(target, wait_s=0.3):
                pass
    finally:
        release.set()
        holder.join(30)
    with chunks.exclusive(target):  # free again once the holder is gone
        pass


POINTS = np.array([3, 4, 7])
MADE_WITH = {"reference_table": {"duration": 1.0}, "camera": {}, "platform": {}}


def _valid_chunk(path) -> None:
    ds = xr.Dataset(
        {
            "criterion_displacement": (("window", "point"), [[1.0, 2.0, 3.0]], {"units": "m", "long_name": "c"}),
            "failed": ("point", np.zeros(3, dtype=np.int8), {"units": "1", "long_name": "failed"}),
        },
        coords={
            "point": ("point", POINTS, {"units": "1", "long_name": "point"}),
            "window": ("window", ["transient"], {"units": "1", "long_name": "window"}),
        },
    )
    io.write_netcdf(ds, path, MADE_WITH, section="reference_table")


def _hold_then_write(path, ready, go):
    with chunks.exclusive(path):
        ready.set()
        go.wait(30)
        time.sleep(0.5)  # the second job is waiting by now
        _valid_chunk(path)


def test_a_job_that_finds_its_chunk_locked_waits_and_keeps_the_holders_finished_chunk(tmp_path):
    """The --unlock race: another run's job holds the chunk's lock; this job waits, finds the chunk the holder
    wrote valid and keeps it (same bytes, same mtime) without computing; it succeeds."""
    target = tmp_path / "chunks" / "1-of-3.nc"
    holder, ready, go = _spawn_holder(_hold_then_write, target)
    try:
        assert ready.wait(60)
        go.set()

        def make():
            raise AssertionError("recomputed a chunk another run had finished")

        finished = partial(chunks.finished_chunk, points=POINTS, config=MADE_WITH)
        assert not target.exists()
        assert io.write_guarded(target, make, finished=finished, wait_s=60) is False
    finally:
        holder.join(30)
    written = (target.read_bytes(), target.stat().st_mtime_ns)
    assert holder.exitcode == 0 and chunks.finished_chunk(target, points=POINTS, config=MADE_WITH)
    assert (target.read_bytes(), target.stat().st_mtime_ns) == written
    assert not list(target.parent.glob(".*.lock.holder"))


def test_a_holders_chunk_of_another_config_is_recomputed_and_a_free_lock_computes(tmp_path):
    target = tmp_path / "2-of-3.nc"
    ctx = multiprocessing.get_context("spawn")
    ready, go = ctx.Event(), ctx.Event()
    holder = ctx.Process(target=_hold_then_write, args=(str(target), ready, go))
    holder.start()
    made = []
    try:
        assert ready.wait(60)
        go.set()
        other = partial(chunks.finished_chunk, points=POINTS, config={**MADE_WITH, "camera": {"x": 1}})
        assert io.write_guarded(target, lambda: made.append("waited"), finished=other, wait_s=60) is True
    finally:
        holder.join(30)
    # nobody holds the lock: computed, even though a finished chunk is there (Snakemake asked for it)
    assert io.write_guarded(target, lambda: made.append("free"), finished=lambda p: True) is True
    assert made == ["waited", "free"]


def test_a_killed_holder_releases_the_lock(tmp_path):
    target = tmp_path / "1-of-3.nc"
    ctx = multiprocessing.get_context("spawn")
    ready, release = ctx.Event(), ctx.Event()
    holder = ctx.Process(target=_hold, args=(str(target), ready, release))
    holder.start()
    assert ready.wait(60)
    holder.kill()  # SIGKILL: no clean-up in the holder
    holder.join(30)
    with chunks.exclusive(target):
        pass


@pytest.fixture(scope="module")
def quick_chunks(quick_run):
    return quick_run / "reports-quick/reference_table/chunks"


def _config(quick_run, path):
    return json.loads(io.open_dataset(path).attrs["config_reference_table"])


def _points(quick_config, name):
    section = quick_config["reference_table"]
    spec = GridSpec.of(parse(ReferenceGrid, view(section, ReferenceGrid), "reference_table"))
    i, n = (int(v) for v in name.removesuffix(".nc").split("-of-"))
    return grid.chunk_points(spec, n, i - 1)


def test_good_chunk_loads(quick_run, quick_chunks, quick_config):
    path = quick_chunks / "1-of-2.nc"
    ds = chunks.load_chunk(path, points=_points(quick_config, path.name), config=_config(quick_run, path))
    assert ds.sizes["point"] == _points(quick_config, path.name).size


@pytest.mark.parametrize("damage", ["truncated", "zero-criterion", "other-config", "other-points"])
def test_bad_chunk_is_named_with_its_rebuild(quick_run, quick_chunks, quick_config, tmp_path, damage):
    source = quick_chunks / "2-of-2.nc"
    path = tmp_path / "2-of-2.nc"
    config, points = _config(quick_run, source), _points(quick_config, source.name)
    if damage == "truncated":
        path.write_bytes(source.read_bytes()[:1000])
        expected = "cannot be read"
    else:
        shutil.copy(source, path)
        if damage == "zero-criterion":
            ds = io.open_dataset(source)
            name = next(v for v in ds.data_vars if v.startswith("criterion"))
            ds[name].values[..., 0] = 0.0
            ds.to_netcdf(path)
            expected = "is not finite and positive"
        elif damage == "other-config":
            config = {**config, "reference_table": {**config["reference_table"], "duration": 9.0}}
            expected = "was made with another config"
        else:
            points = points + 1
            expected = "not this chunk's"
    with pytest.raises(ValueError, match=expected) as error:
        chunks.load_chunk(path, points=points, config=config)
    assert str(path) in str(error.value) and f"rm {path} && snakemake" in str(error.value)


def test_gather_refuses_a_damaged_chunk_in_the_pipeline(quick_run, tmp_path):
    """Through Snakemake: a chunk overwritten with criterion 0 is named by the gather's error."""
    from conftest import copy_workflow

    work = copy_workflow(tmp_path)
    shutil.copytree(quick_run / "reports-quick" / "reference_table", work / "reports-quick" / "reference_table")
    bad = work / "reports-quick/reference_table/chunks/2-of-2.nc"
    ds = io.open_dataset(bad)
    name = next(v for v in ds.data_vars if v.startswith("criterion"))
    ds[name].values[..., 0] = 0.0
    stamp = {k: ds.attrs[k] for k in (integrity.DIGEST_ATTR, integrity.RULE_ATTR, integrity.RUN_ATTR)}
    damaged = ds.drop_attrs(deep=False).assign_attrs(stamp)  # the chunk's job stamp kept: only its numbers are bad
    io.write_netcdf(damaged, bad, json.loads(ds.attrs["config_reference_table"]), section="reference_table")
    (work / "reports-quick/reference_table/grid.nc").unlink()
    result = snakemake(
        work, "-j1", "reports-quick/reference_table/grid.nc", "--configfile", "config/quick.yaml", timeout=600
    )
    log = (work / "reports-quick/logs/reference_table/gather.log").read_text()
    assert result.returncode != 0
    assert "2-of-2.nc" in log and "is not finite and positive" in log, log[-2000:]
    # the run stops at the gather: no grid or table made from the bad chunk
    assert not (work / "reports-quick/reference_table/grid.nc").exists()
