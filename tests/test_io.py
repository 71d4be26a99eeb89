"""NetCDF writing: metadata checks, provenance, CF time, atomic replace."""

from __future__ import annotations

import json
import multiprocessing
import os
import stat
import time

import numpy as np
import pytest
import xarray as xr

from uavdamp import io


def small_dataset() -> xr.Dataset:
    return xr.Dataset(
        {"displacement": (("axis", "time"), np.arange(6.0).reshape(2, 3), {"units": "m", "long_name": "displacement"})},
        coords={
            "axis": ("axis", ["y", "z"], {"units": "1", "long_name": "axis"}),
            "time": ("time", [0.0, 0.1, 0.2], {"units": "s", "long_name": "simulation time"}),
        },
    )


def test_round_trip_with_provenance(tmp_path):
    path = io.write_netcdf(
        small_dataset(), tmp_path / "a.nc", {"step": 0.001, "n": np.int64(3)}, section="demo", command="pytest"
    )
    ds = io.open_dataset(path)
    xr.testing.assert_identical(
        ds.displacement.reset_coords(drop=True), small_dataset().displacement.reset_coords(drop=True)
    )
    np.testing.assert_array_equal(ds.time.values, [0.0, 0.1, 0.2])
    assert ds.time.attrs["units"] == "s"
    assert ds.attrs["Conventions"] == "CF-1.11"
    assert io.read_config_attr(ds, "demo") == {"step": 0.001, "n": 3}
    assert "numpy" in json.loads(ds.attrs["package_versions"])
    assert ds.attrs["command"] == "pytest"
    with xr.open_dataset(path, decode_times=False) as raw:
        assert raw.time.attrs["units"] == io.TIME_UNITS
        assert "_FillValue" not in raw.time.encoding or raw.time.encoding["_FillValue"] is None


def test_missing_metadata_named_and_nothing_written(tmp_path):
    target = tmp_path / "b.nc"
    target.write_text("previous result")
    ds = small_dataset()
    del ds["displacement"].attrs["units"]
    with pytest.raises(ValueError, match=r"displacement \(units\)"):
        io.write_netcdf(ds, target, {}, section="demo")
    assert target.read_text() == "previous result"
    assert list(tmp_path.iterdir()) == [target]


def test_failed_write_leaves_no_partial_file(tmp_path):
    ds = small_dataset()
    ds.attrs["bad"] = {"a dict": "is not a valid netCDF attribute"}
    target = tmp_path / "c.nc"
    with pytest.raises(TypeError, match="Invalid value for attr 'bad'"):
        io.write_netcdf(ds, target, {}, section="demo")
    assert list(tmp_path.iterdir()) == []


def test_outputs_get_umask_permissions(tmp_path):
    old = os.umask(0o022)
    try:
        path = io.write_netcdf(small_dataset(), tmp_path / "p.nc", {}, section="demo")
        text = io.write_text("x", tmp_path / "t.txt")
    finally:
        os.umask(old)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644
    assert stat.S_IMODE(text.stat().st_mode) == 0o644


def _pattern_dataset(kind: str) -> xr.Dataset:
    """Small datasets shaped as a grid chunk, model.nc and comparison.nc, of a known float pattern 1 + k / 7."""
    values = 1.0 + np.arange(24.0) / 7.0
    attrs = {"units": "m", "long_name": "criterion"}
    dims = {
        "chunk": ("window", "point"),
        "model": ("rule", "input"),
        "comparison": ("case", "strategy"),
    }[kind]
    shape = (4, 6)
    coords = {d: (d, np.arange(n), {"units": "1", "long_name": d}) for d, n in zip(dims, shape, strict=True)}
    return xr.Dataset({"criterion_displacement": (dims, values.reshape(shape), attrs)}, coords=coords)


@pytest.mark.parametrize("kind", ["chunk", "model", "comparison"])
def test_a_flipped_byte_in_a_data_variable_is_refused_naming_the_file(tmp_path, kind):
    from conftest import flip_byte_in_data

    ds = _pattern_dataset(kind)
    path = io.write_netcdf(ds, tmp_path / f"{kind}.nc", {}, section="demo")
    xr.testing.assert_equal(io.open_dataset(path).criterion_displacement, ds.criterion_displacement)
    flip_byte_in_data(path, ds.criterion_displacement.values)
    with pytest.raises(io.CorruptOutput, match=f"^{path}: corrupt or truncated") as error:
        io.open_dataset(path)
    assert f"rebuild it: rm {path} && snakemake -j2 all" in str(error.value)
    assert isinstance(error.value, ValueError) and isinstance(error.value, OSError)


def test_every_variable_with_dimensions_carries_fletcher32(tmp_path):
    import netCDF4

    path = io.write_netcdf(small_dataset(), tmp_path / "f.nc", {}, section="demo")
    with netCDF4.Dataset(path) as raw:
        assert {name: raw[name].filters()["fletcher32"] for name in raw.variables} == {
            "displacement": True,
            "axis": True,
            "time": True,
        }


@pytest.mark.parametrize("keep", [0, 100, 0.5, 0.99])
def test_a_truncated_file_is_refused_naming_the_file(tmp_path, keep):
    path = io.write_netcdf(_pattern_dataset("chunk"), tmp_path / "t.nc", {}, section="demo")
    data = path.read_bytes()
    path.write_bytes(data[: int(keep * len(data)) if isinstance(keep, float) else keep])
    with pytest.raises(io.CorruptOutput, match=f"^{path}: corrupt or truncated.*rebuild it: rm {path}"):
        io.open_dataset(path)


def test_a_missing_file_is_not_called_corrupt(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file"):
        io.open_dataset(tmp_path / "none.nc")


def test_benchmark_outputs_are_rebuilt_by_the_benchmark_target():
    assert io.rebuild_command("reports/benchmark/runs/a.nc").startswith(
        "rm reports/benchmark/runs/a.nc && snakemake -j2 benchmark "
    )
    assert "snakemake -j2 all " in io.rebuild_command("reports/study/comparison.nc")


def _hold_and_write(path, config, ready, go):
    with io.exclusive(path):
        ready.set()
        go.wait(30)
        time.sleep(0.5)  # the second writer is waiting by now
        io.write_netcdf(small_dataset(), path, config, section="benchmark")


@pytest.mark.parametrize("same_config", [True, False])
def test_write_once_waits_for_the_holder_and_keeps_its_output_of_the_same_config(tmp_path, same_config):
    """A benchmark output another run's job is writing: the second job waits, keeps the holder's file if made
    with its config (bytes and mtime unchanged), else writes its own."""
    target = tmp_path / "benchmark" / "runs" / "sweep.nc"
    ctx = multiprocessing.get_context("spawn")
    ready, go = ctx.Event(), ctx.Event()
    holder = ctx.Process(target=_hold_and_write, args=(str(target), {"seed": 1}, ready, go))
    holder.start()
    made = []
    try:
        assert ready.wait(60)
        go.set()
        config = {"seed": 1 if same_config else 2}
        done = io.write_once(target, lambda: made.append(1), config, section="benchmark", wait_s=60)
    finally:
        holder.join(30)
    assert holder.exitcode == 0
    assert done is (not same_config) and made == ([] if same_config else [1])


def test_a_lock_held_too_long_names_its_holder(tmp_path):
    target = tmp_path / "b.nc"
    ctx = multiprocessing.get_context("spawn")
    ready, go = ctx.Event(), ctx.Event()
    holder = ctx.Process(target=_hold_and_write, args=(str(target), {}, ready, go))
    holder.start()
    try:
        assert ready.wait(60)
        with pytest.raises(ValueError, match=rf"b.nc: another process \(.+~{holder.pid}, host~pid\) has held its lock"):
            io.write_once(
                target,
                lambda: None,
                {},
                section="benchmark",
                wait_s=0.3,
            )
    finally:
        go.set()
        holder.join(30)


def test_a_config_section_not_stored_is_named_with_the_file_and_what_is_stored(tmp_path):
    ds = xr.Dataset({"x": ("t", [1.0], {"units": "m", "long_name": "x"})})
    ds["t"] = ("t", [0.0], {"units": "s", "long_name": "t"})
    path = io.write_netcdf(ds, tmp_path / "a.nc", {"study": {"duration_s": 1.0}}, section="study")
    opened = io.open_dataset(path)
    assert io.read_config_attr(opened, "study") == {"study": {"duration_s": 1.0}}
    named = r"a\.nc: no attribute 'config_anfis': config section 'anfis' not stored \(stored: \['study'\]\)"
    with pytest.raises(KeyError, match=named):
        io.read_config_attr(opened, "anfis")


# ------------------------------------------------------------------ which run an output belongs to (uavdamp.integrity)


def _job(monkeypatch, tmp_path, digest, run_started, *, outputs=("study/comparison.nc",), expects=None, rule="study"):
    """An `integrity.Job` of a fake Snakemake job: its digest, its run's start, its outputs under tmp_path."""
    from types import SimpleNamespace

    from uavdamp import integrity

    monkeypatch.setenv(io.STAMP_ENV, "{}")  # restored after the test: Job sets it for this process
    monkeypatch.setenv(io.PROVENANCE_ENV, json.dumps({"run_started": run_started}))
    params = SimpleNamespace(digest=digest, expects=expects or {})
    smk = SimpleNamespace(params=params, rule=rule, output=[str(tmp_path / o) for o in outputs])
    return integrity.Job(smk)


def test_the_plan_digest_is_sha256_of_the_sorted_view_and_the_upstream_digests():
    import hashlib

    from uavdamp import integrity

    text = '{"params": {"a": 1, "b": [2.5, "x"]}, "upstream": ["0f", "1e"]}'  # json.dumps, keys sorted, by hand
    assert (
        integrity.plan_digest({"b": [2.5, "x"], "a": 1}, ["1e", "0f", "1e"])
        == hashlib.sha256(text.encode()).hexdigest()[:16]
    )
    assert integrity.plan_digest({"a": 1}, ["0f"]) != integrity.plan_digest({"a": 1}, ["0e"])  # an upstream edit


def test_a_job_stamps_what_it_writes_and_a_consumer_refuses_a_foreign_digest_naming_file_and_rule(
    monkeypatch, tmp_path
):
    """Seen failing on the previous main: no digest existed; a consumer read any file at its input's path."""
    from uavdamp import integrity

    job = _job(monkeypatch, tmp_path, "aaaa000011112222", "2026-01-01T10:00:00.000000+00:00")
    path = tmp_path / "study/comparison.nc"
    with job.writing():
        io.write_netcdf(small_dataset(), path, {}, section="study")
    attrs = io.open_dataset(path).attrs
    assert (attrs["config_digest"], attrs["config_digest_rule"]) == ("aaaa000011112222", "study")
    assert attrs["run_started"] == "2026-01-01T10:00:00.000000+00:00"
    integrity.check_inputs({str(path): ["aaaa000011112222", "study"]})  # the plan's digest: accepted
    with pytest.raises(integrity.StaleInput) as error:
        integrity.check_inputs({str(path): ["bbbb000011112222", "study"]})
    text = str(error.value)
    assert text.startswith(f"{path}: made with config digest aaaa000011112222")
    assert "expects bbbb000011112222" in text and f"rule study rebuilds it: rm {path} && snakemake" in text
    monkeypatch.setenv(io.STAMP_ENV, "{}")  # an output written without a stamp (an earlier version's)
    io.write_netcdf(small_dataset(), tmp_path / "old.nc", {}, section="study")
    with pytest.raises(integrity.StaleInput, match="old.nc: made with config digest none"):
        integrity.check_inputs({str(tmp_path / "old.nc"): ["bbbb000011112222", "study"]})


@pytest.mark.parametrize("later", [True, False])
def test_an_output_of_a_later_run_is_not_replaced_one_of_an_earlier_run_is(monkeypatch, tmp_path, later):
    """Seen failing on the previous main: any job replaced any output (the study's with an earlier run's)."""
    from uavdamp import integrity

    path = tmp_path / "study/comparison.nc"
    newer = _job(monkeypatch, tmp_path, "c" * 16, "2026-01-01T12:00:00.000000+00:00")
    with newer.writing():
        io.write_netcdf(small_dataset(), path, {}, section="study")
    before = path.read_bytes()
    started = "2026-01-01T11:00:00.000000+00:00" if later else "2026-01-01T13:00:00.000000+00:00"
    other = _job(monkeypatch, tmp_path, "a" * 16, started)
    if later:  # the existing output's run started after this job's: kept, nothing written
        with pytest.raises(integrity.NewerOutput, match=f"^{path}: not replaced: it holds the result of a later run"):
            with other.writing():
                io.write_netcdf(small_dataset() * 2, path, {}, section="study")
        assert path.read_bytes() == before
    else:
        with other.writing():
            io.write_netcdf(small_dataset(), path, {}, section="study")
        assert io.open_dataset(path).attrs["config_digest"] == "a" * 16


def test_a_text_output_carries_its_stamp_beside_it(monkeypatch, tmp_path):
    from uavdamp import integrity

    job = _job(monkeypatch, tmp_path, "d" * 16, "2026-01-01T12:00:00.000000+00:00", outputs=("summary.md",))
    with job.writing():
        io.write_text("# results\n", tmp_path / "summary.md")
    assert integrity.read_stamp(tmp_path / "summary.md")["config_digest"] == "d" * 16
    early = _job(monkeypatch, tmp_path, "e" * 16, "2026-01-01T11:00:00.000000+00:00", outputs=("summary.md",))
    with pytest.raises(integrity.NewerOutput, match="summary.md: not replaced"):
        with early.writing():
            io.write_text("# stale\n", tmp_path / "summary.md")
    assert (tmp_path / "summary.md").read_text() == "# results\n"
