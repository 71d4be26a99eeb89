"""Reference table: argmin and tie rule, chunk merge, failures, joblib workers, resume after a kill."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
import xarray as xr

from conftest import copy_workflow, snakemake
from uavdamp import criterion, grid, io


def synthetic_grid(values: np.ndarray) -> xr.Dataset:
    shape = values.shape
    spec = grid.GridSpec(freq_y=np.arange(1.0, shape[0] + 1), freq_z=np.arange(1.0, shape[1] + 1),
                         stiffness=np.geomspace(10, 1000, shape[2]), damping=np.geomspace(0.1, 10, shape[3]),
                         amplitude=1e-3, duration=1.0, window=(0.0, 1.0))
    return xr.Dataset({"criterion": (grid.DIMS, values, criterion.CRITERION_ATTRS),
                       "failed": (grid.DIMS, np.isnan(values).astype(np.int8), {"units": "1", "long_name": "f"})},
                      coords=spec.coords())


def test_damping_opt_is_the_argmin_with_documented_ties():
    rng = np.random.default_rng(3)
    values = rng.uniform(1e-4, 1e-3, (3, 2, 2, 5))
    values[0, 0, 0, [1, 3]] = 1e-5  # an exact tie: the smaller damping wins
    values[1, 1, 1, :] = np.nan  # all failed: no optimum
    values[2, 0, 1, 0] = np.nan  # one failed point is ignored
    table = criterion.reference_table(synthetic_grid(values))
    damping = table.damping_opt.values
    c = np.geomspace(0.1, 10, 5)
    for idx in np.ndindex(3, 2, 2):
        row = values[idx]
        if np.all(np.isnan(row)):
            assert np.isnan(damping[idx]) and np.isnan(table.criterion_opt.values[idx])
            continue
        assert damping[idx] == c[np.nanargmin(row)]
        assert table.criterion_opt.values[idx] == np.nanmin(row)
    assert damping[0, 0, 0] == c[1]
    # overall best (K, C) per frequency pair
    best = np.nanmin(values.reshape(3, 2, -1), axis=2)
    np.testing.assert_array_equal(table.criterion_at_stiffness_opt.values[~np.isnan(best)], best[~np.isnan(best)])
    # the flat band contains the optimum
    ok = ~np.isnan(damping)
    assert np.all(table.damping_flat_min.values[ok] <= damping[ok])
    assert np.all(table.damping_flat_max.values[ok] >= damping[ok])


def test_scheduling_gain_is_one_when_the_optimum_does_not_move():
    values = np.ones((3, 3, 2, 4))
    values[..., 0, 2] = 0.5  # K index 0: same best C everywhere
    values[..., 1, :] = 1.0
    values[0, :, 1, 0] = 0.2  # K index 1: the best C depends on f_y
    values[1:, :, 1, 3] = 0.2
    table = criterion.reference_table(synthetic_grid(values))
    assert table.scheduling_gain.values[0] == pytest.approx(1.0)
    assert table.damping_opt_spread.values[0] == pytest.approx(1.0)
    assert table.scheduling_gain.values[1] > 1.5
    assert table.damping_opt_spread.values[1] == pytest.approx(100.0)


def test_criterion_of_a_sine_is_its_rms():
    t = np.linspace(0, 2, 2001)
    disp = xr.DataArray(np.stack([2e-3 * np.sin(2 * np.pi * 5 * t), 1e-3 * np.sin(2 * np.pi * 3 * t)]),
                        dims=("axis", "time"), coords={"axis": ["y", "z"], "time": t})
    expected = np.sqrt(2e-3**2 / 2 + 1e-3**2 / 2)
    assert criterion.camera_criterion(disp, (0.0, 2.0)) == pytest.approx(expected, rel=2e-3)


@pytest.fixture(scope="module")
def tiny(quick_config):
    """A small grid on the quick platform: 2 x 2 x 2 x 3 points of 0.6 s."""
    cfg = dict(quick_config["reference_table"])
    cfg.update(freq_y_hz={"values": [4.0, 8.0]}, freq_z_hz={"values": [5.0, 9.0]},
               stiffness={"values": [10.0, 400.0]}, damping={"values": [1.0, 5.0, 25.0]},
               duration=0.6, window=[0.0, 0.6])
    platform = {k: v for k, v in quick_config["platform"].items() if k != "response"}
    return platform, grid.GridSpec.from_config(cfg)


@pytest.fixture(scope="module")
def single_chunk(tiny):
    platform, spec = tiny
    return grid.run_chunk(platform, spec)


def test_chunks_merge_to_the_single_chunk_run(tiny, single_chunk):
    platform, spec = tiny
    chunks = [grid.run_chunk(platform, spec, n_chunks=3, chunk=i) for i in range(3)]
    assert sorted(np.concatenate([c.point.values for c in chunks]).tolist()) == list(range(spec.size))
    merged = grid.merge_chunks(spec, chunks)
    single = grid.merge_chunks(spec, [single_chunk])
    np.testing.assert_array_equal(merged.criterion.values, single.criterion.values)
    assert np.all(np.isfinite(single.criterion.values)) and single.attrs["n_failed"] == 0
    with pytest.raises(ValueError, match="missing"):
        grid.merge_chunks(spec, chunks[:2])


def test_two_workers_give_identical_numbers(tiny, single_chunk):
    platform, spec = tiny
    parallel = grid.run_chunk(platform, spec, n_jobs=2)
    np.testing.assert_array_equal(parallel.criterion.values, single_chunk.criterion.values)
    np.testing.assert_array_equal(parallel.point.values, single_chunk.point.values)


def test_forced_solver_failure_is_nan_flag_and_count(tiny, single_chunk):
    platform, spec = tiny
    ds = grid.run_chunk(platform, spec, fail=frozenset({5}))
    assert ds.attrs["n_failed"] == 1
    assert np.isnan(ds.criterion.sel(point=5)) and int(ds.failed.sel(point=5)) == 1
    others = ds.point.values != 5
    np.testing.assert_array_equal(ds.criterion.values[others], single_chunk.criterion.values[others])
    assert "point 5" in json.loads(ds.attrs["errors"])[0]
    full = grid.merge_chunks(spec, [ds])
    assert full.attrs["n_failed"] == 1
    table = criterion.reference_table(full)
    assert np.all(np.isfinite(table.damping_opt.values))  # one failed C still leaves the others


def test_bad_grid_config_names_the_key(quick_config):
    cfg = dict(quick_config["reference_table"])
    with pytest.raises(ValueError, match="reference_table.window"):
        grid.GridSpec.from_config({**cfg, "window": [0.0, 1e3]})
    with pytest.raises(ValueError, match="reference_table.damping"):
        grid.GridSpec.from_config({**cfg, "damping": {"values": [3.0, 1.0]}})
    spec = grid.GridSpec.from_config({**cfg, "damping": {"values": [1.0, 1e4]}})
    platform = grid.PlatformParams.from_config(quick_config["platform"])
    with pytest.raises(ValueError, match="damping_min/max"):
        spec.check_damper_bounds(platform)


def test_quick_table_in_pipeline(quick_run):
    table = io.open_dataset(quick_run / "reports/reference_table/table.nc")
    full = io.open_dataset(quick_run / "reports/reference_table/grid.nc")
    crit = full.criterion.values
    expected = full.damping.values[np.nanargmin(crit, axis=3)]
    np.testing.assert_array_equal(table.damping_opt.values, expected)
    assert full.attrs["n_failed"] == 0 and int(full.failed.sum()) == 0
    assert (quick_run / "reports/figures/reference_table.png").stat().st_size > 10_000


def test_resume_after_kill_gives_identical_table(quick_run, tmp_path):
    """Kill Snakemake after the first chunk, rerun: finished chunks kept, table identical."""
    workdir = copy_workflow(tmp_path)
    target = "reports/reference_table/table.nc"
    cmd = [sys.executable, "-m", "snakemake", "-j1", target, "--configfile", "config/quick.yaml"]
    proc = subprocess.Popen(cmd, cwd=workdir, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)
    chunks = workdir / "reports/reference_table/chunks"
    logs = workdir / "reports/logs/reference_table"
    started: list[str] = []  # chunk jobs in the order their logs appeared (-j1: one at a time)
    deadline = time.monotonic() + 600
    try:
        while time.monotonic() < deadline and proc.poll() is None and len(started) < 2:
            for log in sorted(logs.glob("*-of-*.log")) if logs.exists() else []:
                if log.stem not in started:
                    started.append(log.stem)
            time.sleep(0.05)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=60)
    assert len(started) >= 2, "the run ended or timed out before a second chunk started"
    # every chunk started before the last one had finished and been recorded by Snakemake
    kept = {name: (chunks / f"{name}.nc").stat().st_mtime_ns for name in started[:-1]}
    assert not (workdir / target).exists()
    assert snakemake(workdir, "--unlock", "--configfile", "config/quick.yaml").returncode == 0  # the kill left a lock
    result = snakemake(workdir, "-j2", target, "--configfile", "config/quick.yaml", "--rerun-incomplete")
    assert result.returncode == 0, result.stderr[-3000:]
    for name, mtime in kept.items():
        assert (chunks / f"{name}.nc").stat().st_mtime_ns == mtime, f"{name} was recomputed"
    resumed = io.open_dataset(workdir / target)
    reference = io.open_dataset(quick_run / target)
    for name in reference.data_vars:
        np.testing.assert_array_equal(resumed[name].values, reference[name].values, err_msg=name)
