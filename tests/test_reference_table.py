"""Reference table: argmin and tie rule, per criterion and window, chunk merge, plants, failures, verification,
workers, resume."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest
import xarray as xr
from conftest import camera_of, platform_from, synthetic_grid

from uavdamp import io
from uavdamp.contract import SolverFailed
from uavdamp.reference_table import GridSpec, ReferenceGrid, ReferenceTableSection, VerifyOptions, chunks, grid, verify
from uavdamp.reference_table import criteria as criterion
from uavdamp.settings import parse, view


def one_table(values: np.ndarray) -> xr.Dataset:
    """The table of one criterion (displacement, transient) over (f_y, f_z, K, C) `values`."""
    return criterion.select_table(criterion.reference_table(synthetic_grid(values)), "displacement", "transient")


def test_damping_opt_is_the_argmin_with_documented_ties():
    rng = np.random.default_rng(3)
    values = rng.uniform(1e-4, 1e-3, (3, 2, 2, 5))
    values[0, 0, 0, [1, 3]] = 1e-5  # an exact tie: the smaller damping wins
    values[1, 1, 1, :] = np.nan  # all failed: no optimum
    values[2, 0, 1, 0] = np.nan  # one failed point is ignored
    table = one_table(values)
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
    table = one_table(values)
    assert table.scheduling_gain.values[0] == pytest.approx(1.0)
    assert table.damping_opt_spread.values[0] == pytest.approx(1.0)
    assert table.scheduling_gain.values[1] == pytest.approx(7 / 3, rel=1e-14)  # worked in test_mutants_criterion.py
    assert table.damping_opt_spread.values[1] == pytest.approx(100.0)


def test_table_per_criterion_and_window_is_each_slices_own_optimum():
    """Three criteria x two windows in one table: each slice's damping_opt, criterion_opt (in its criterion's
    units) and scheduling gain are those of that slice alone (argmin over C, by numpy)."""
    rng = np.random.default_rng(12)
    values = rng.uniform(0.1, 1.0, (3, 2, 3, 2, 2, 5))
    table = criterion.reference_table(synthetic_grid(values, windows=("transient", "steady")))
    c = np.geomspace(0.1, 10, 5)
    assert list(table.criterion.values) == list(criterion.CRITERIA) and list(table.window.values) == [
        "transient",
        "steady",
    ]
    for i, name in enumerate(criterion.CRITERIA):
        assert table[f"criterion_opt_{name}"].attrs["units"] == criterion.CRITERIA[name]["units"]
        for w, window in enumerate(("transient", "steady")):
            part = table.sel(criterion=name, window=window)
            np.testing.assert_array_equal(part.damping_opt.values, c[np.argmin(values[i, w], axis=-1)])
            np.testing.assert_array_equal(
                table[f"criterion_opt_{name}"].sel(window=window).values, values[i, w].min(axis=-1)
            )
            best_constant = np.argmin(values[i, w].mean(axis=(0, 1)), axis=-1)  # per K
            const = np.take_along_axis(values[i, w], best_constant[None, None, :, None], axis=-1)[..., 0]
            np.testing.assert_allclose(
                part.scheduling_gain.values, (const / values[i, w].min(axis=-1)).mean(axis=(0, 1)), rtol=1e-12
            )
            chosen = criterion.select_table(table, name, window)
            np.testing.assert_array_equal(chosen.damping_opt.values, part.damping_opt.values)
            assert chosen.criterion_opt.attrs["units"] == criterion.CRITERIA[name]["units"]
    with pytest.raises(ValueError, match="reference_table.criterion: 'sharpness'"):
        criterion.select_table(table, "sharpness", "steady")
    with pytest.raises(ValueError, match="reference_table.window: 'late'"):
        criterion.select_table(table, "blur", "late")
    io.check_metadata(table)


def test_criterion_of_a_sine_is_its_rms():
    t = np.linspace(0, 2, 2001)
    disp = xr.DataArray(
        np.stack([2e-3 * np.sin(2 * np.pi * 5 * t), 1e-3 * np.sin(2 * np.pi * 3 * t)]),
        dims=("axis", "time"),
        coords={"axis": ["y", "z"], "time": t},
    )
    expected = np.sqrt(2e-3**2 / 2 + 1e-3**2 / 2)
    assert criterion.camera_criterion(disp, (0.0, 2.0)) == pytest.approx(expected, rel=2e-3)


@pytest.fixture(scope="module")
def tiny(quick_config):
    """A small grid on the quick platform: 2 x 2 x 2 x 3 points of 0.6 s (linear plant)."""
    cfg = view(quick_config["reference_table"], ReferenceGrid)
    cfg.update(
        freq_y_hz={"values": [4.0, 8.0]},
        freq_z_hz={"values": [5.0, 9.0]},
        stiffness_n_m={"values": [10.0, 400.0]},
        damping_n_s_m={"values": [1.0, 5.0, 25.0]},
        duration_s=0.6,
        windows_s={"transient": [0.0, 0.6], "steady": [0.3, 0.6]},
    )
    platform = platform_from(quick_config["platform"])
    assert platform.backend == "linear"
    return platform, GridSpec.of(parse(ReferenceGrid, cfg, "reference_table"), camera_of(quick_config["camera"]))


VARIABLES = [criterion.variable(name) for name in criterion.CRITERIA]


def assert_same(a: xr.Dataset, b: xr.Dataset, **tolerance) -> None:
    """Every criterion variable of a equals b's (exactly, or within `tolerance`: rtol per criterion name)."""
    for name in criterion.CRITERIA:
        var = criterion.variable(name)
        if tolerance:
            np.testing.assert_allclose(a[var].values, b[var].values, rtol=tolerance[name], err_msg=var)
        else:
            np.testing.assert_array_equal(a[var].values, b[var].values, err_msg=var)


@pytest.fixture(scope="module")
def single_chunk(tiny):
    platform, spec = tiny
    return chunks.run_chunk(platform, spec)


def test_chunks_merge_to_the_single_chunk_run(tiny, single_chunk):
    platform, spec = tiny
    parts = [chunks.run_chunk(platform, spec, n_chunks=4, chunk=i) for i in range(4)]
    assert sorted(np.concatenate([c.point.values for c in parts]).tolist()) == list(range(spec.size))
    merged = chunks.merge_chunks(spec, parts)
    single = chunks.merge_chunks(spec, [single_chunk])
    assert_same(merged, single)
    assert all(single[v].dims == ("window", *grid.DIMS) for v in VARIABLES)
    assert all(np.all(np.isfinite(single[v].values)) for v in VARIABLES) and single.attrs["n_failed"] == 0
    assert single.attrs["plant"] == "linear" and single_chunk.attrs["plant"] == "linear"
    with pytest.raises(ValueError, match="missing"):
        chunks.merge_chunks(spec, parts[:2])
    more = [chunks.run_chunk(platform, spec, n_chunks=8, chunk=i) for i in range(8)]  # more chunks than (K, C) blocks
    assert_same(chunks.merge_chunks(spec, more), single)


def test_batched_grid_equals_per_point_evaluation(tiny, single_chunk):
    """Each point alone (one frequency pair per call) gives the batched value."""
    platform, spec = tiny
    points = single_chunk.point.values
    alone = verify.evaluate_points(platform, spec, points, "linear")
    for j, var in enumerate(VARIABLES):
        np.testing.assert_allclose(single_chunk[var].transpose("point", "window").values, alone[:, j], rtol=1e-10)


def test_linear_grid_matches_the_exudyn_grid(tiny, single_chunk, quick_config):
    """Every criterion: the Exudyn path scores each response dataset (exact projection for the blur)."""
    platform, spec = tiny
    exudyn = chunks.run_chunk(replace(platform, backend="exudyn"), spec)
    assert exudyn.attrs["plant"] == "exudyn"
    np.testing.assert_array_equal(exudyn.point.values, single_chunk.point.values)
    assert_same(single_chunk, exudyn, **quick_config["reference_table"]["verify"]["tolerance"])
    with pytest.raises(ValueError, match="different plants"):
        chunks.merge_chunks(
            spec,
            [
                chunks.run_chunk(platform, spec, n_chunks=2, chunk=0),
                chunks.run_chunk(replace(platform, backend="exudyn"), spec, n_chunks=2, chunk=1),
            ],
        )


def test_two_workers_give_identical_numbers(tiny, single_chunk):
    platform, spec = tiny
    parallel = chunks.run_chunk(platform, spec, n_jobs=2)
    assert_same(parallel, single_chunk)
    np.testing.assert_array_equal(parallel.point.values, single_chunk.point.values)


@pytest.mark.parametrize("backend", ["linear", "exudyn"])
def test_failure_is_nan_flag_and_count(tiny, single_chunk, monkeypatch, backend):
    """A failing (K, C) block (linear) or point (Exudyn) gives NaN and a flag; the other points are unchanged."""
    platform, spec = tiny
    if backend == "linear":
        real = chunks.evaluate_block

        def evaluate_block(plant, spec, block):
            if block == 1:
                raise np.linalg.LinAlgError("forced failure of block 1")
            return real(plant, spec, block)

        monkeypatch.setattr(chunks, "evaluate_block", evaluate_block)
        bad = grid.block_points(spec, 1)
        message = "block 1"
    else:
        real = chunks.evaluate

        def evaluate(sim, spec, point):
            if point == spec.point(5):
                raise SolverFailed("forced failure of point 5")
            return real(sim, spec, point)

        monkeypatch.setattr(chunks, "evaluate", evaluate)
        bad = np.array([5])
        message = "point 5"
    ds = chunks.run_chunk(replace(platform, backend=backend), spec)
    assert ds.attrs["n_failed"] == bad.size
    assert all(np.all(np.isnan(ds[v].sel(point=bad))) for v in VARIABLES) and np.all(ds.failed.sel(point=bad) == 1)
    others = ~np.isin(ds.point.values, bad)
    for var in VARIABLES:
        np.testing.assert_allclose(ds[var].values[:, others], single_chunk[var].values[:, others], rtol=0.08)
    assert message in json.loads(ds.attrs["errors"])[0]
    full = chunks.merge_chunks(spec, [ds])
    assert full.attrs["n_failed"] == bad.size
    if backend == "linear":  # a whole (K, C) block failed: criterion.reference_table's mean over it is empty
        with pytest.warns(RuntimeWarning, match="Mean of empty slice"):
            table = criterion.reference_table(full)
    else:
        table = criterion.reference_table(full)
    assert np.all(np.isfinite(table.damping_opt.values))  # one failed C still leaves the others


def test_verification_samples_corners_and_stores_the_difference(tiny, single_chunk, quick_config):
    platform, spec = tiny
    full = chunks.merge_chunks(spec, [single_chunk])
    tolerance = quick_config["reference_table"]["verify"]["tolerance"]
    checked = verify.verify(platform, spec, full, VerifyOptions(n_points=18, tolerance=tolerance, seed=3))
    points = checked.verify_point.values
    corners = {
        int(np.ravel_multi_index(c, spec.shape)) for c in np.ndindex(2, 2, 2, 2) for c in [(c[0], c[1], c[2], 2 * c[3])]
    }  # damping axis has 3 values: corners at 0 and 2
    assert corners <= set(points.tolist()) and len(set(points.tolist())) == 18
    again = verify.verification_points(spec, 18, 3)
    np.testing.assert_array_equal(points, again)  # seeded
    for name in criterion.CRITERIA:
        on_grid = full[criterion.variable(name)].transpose(*grid.DIMS, "window").values.reshape(spec.size, -1)
        np.testing.assert_array_equal(checked[f"verify_{name}_linear"].values, on_grid[points])
        worst = float(checked.verify_relative_difference.sel(criterion=name).max())
        assert 0 < worst < tolerance[name], name
    verify.check_verification(spec, checked, tolerance)  # passes
    io.check_metadata(checked)
    with pytest.raises(ValueError, match="reference_table.verify.n_points"):
        verify.verification_points(spec, 15, 3)


def test_verification_failure_names_the_worst_point(tiny, single_chunk, monkeypatch, quick_config):
    platform, spec = tiny
    full = chunks.merge_chunks(spec, [single_chunk])
    real = chunks.evaluate
    off = spec.point(7)

    def evaluate(sim, spec, point):  # the Exudyn plant's line-of-sight criterion is 20 % larger at point 7
        values = real(sim, spec, point)
        values[1] *= 1.2 if point == off else 1.0
        return values

    monkeypatch.setattr(chunks, "evaluate", evaluate)
    tolerance = quick_config["reference_table"]["verify"]["tolerance"]
    checked = verify.verify(platform, spec, full, VerifyOptions(n_points=spec.size, tolerance=tolerance, seed=1))
    assert 7 in checked.verify_point.values
    match = r"in the line_of_sight criterion, window \w+, at point 7 \(f_y 4 Hz, f_z 9 Hz, K 10 N/m, C 5 N s/m\)"
    with pytest.raises(verify.VerificationFailed, match=match):
        verify.check_verification(spec, checked, tolerance)


def test_bad_grid_config_names_the_key(quick_config):
    cfg = quick_config["reference_table"]

    def refused(match, **changes):
        with pytest.raises(ValueError, match=match):
            parse(ReferenceTableSection, {**cfg, **changes}, "reference_table")

    refused(
        r"reference_table.windows_s.steady: need \[start, end\] with 0 <= start < end <= duration_s",
        windows_s={**cfg["windows_s"], "steady": [0.0, 1e3]},
    )
    refused("reference_table.windows_s: expected a mapping", windows_s=[0.0, 1.0])
    refused("reference_table.criterion: 'sharpness' is not one of", criterion="sharpness")
    refused("reference_table.window: 'late' is not one of reference_table.windows", window="late")
    refused("reference_table.damping_n_s_m: values must be strictly increasing", damping_n_s_m={"values": [3.0, 1.0]})
    refused(
        "reference_table.verify.tolerance.blur: must be > 0",
        verify={**cfg["verify"], "tolerance": {**cfg["verify"]["tolerance"], "blur": 0.0}},
    )
    refused(
        r"reference_table.verify.tolerance: no tolerance for \['blur'\]",
        verify={**cfg["verify"], "tolerance": {"displacement": 0.1, "line_of_sight": 0.1}},
    )


def test_quick_table_in_pipeline(quick_run):
    table = io.open_dataset(quick_run / "reports-quick/reference_table/table.nc")
    full = io.open_dataset(quick_run / "reports-quick/reference_table/grid.nc")
    for name in criterion.CRITERIA:
        for window in full.window.values:
            crit = full[criterion.variable(name)].sel(window=window).transpose(*grid.DIMS).values
            expected = full.damping.values[np.nanargmin(crit, axis=3)]
            np.testing.assert_array_equal(table.damping_opt.sel(criterion=name, window=window).values, expected)
    assert (table.attrs["criterion"], table.attrs["window"]) == ("displacement", "transient")
    assert full.attrs["n_failed"] == 0 and int(full.failed.sum()) == 0
    for figure in ("reference_table.png", "reference_table_criteria.png"):
        assert (quick_run / "reports-quick/figures" / figure).stat().st_size > 10_000


def test_an_optimum_on_an_edge_of_the_c_grid_is_flagged_with_its_share():
    """Seen failing on the previous main: the table had no flag; a cell whose criterion still falls at the grid's
    largest C (0.1-10 N s/m here) got damping_opt 10 like an interior optimum."""
    c = np.geomspace(0.1, 10, 5)  # the synthetic grid's C axis, N s/m
    values = np.empty((2, 2, 2, 5))
    values[...] = (np.log10(c) - np.log10(c[2])) ** 2 + 1  # interior minimum at c[2]
    values[0, 0, 0] = 1 / c  # decreasing in C: the optimum lies beyond the top
    values[0, 1, 0] = c  # increasing: beyond the bottom
    values[1, 1, 1] = 1 / c
    free = one_table(values)  # the damper's bounds unknown: every edge may hide a better C
    expected = np.zeros((2, 2, 2), dtype=int)
    expected[0, 0, 0], expected[0, 1, 0], expected[1, 1, 1] = 2, 1, 2
    np.testing.assert_array_equal(free.optimum_at_grid_edge.values, expected)
    assert float(free.grid_edge_share) == 3 / 8
    assert {"units", "long_name", "flag_values", "flag_meanings"} <= set(free.optimum_at_grid_edge.attrs)
    # the top of the grid is the damper's largest C: the best C the damper can give, kept (flag 3, not counted)
    table = criterion.reference_table(synthetic_grid(values), damper_bounds=(0.0, 10.0))
    chosen = criterion.select_table(table, "displacement", "transient")
    expected[expected == 2] = 3
    np.testing.assert_array_equal(chosen.optimum_at_grid_edge.values, expected)
    assert float(chosen.grid_edge_share) == 1 / 8
