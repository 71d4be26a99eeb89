"""The camera criterion and the reference-table reductions against closed forms (issue 17's planted bugs).

Each test names the planted bug or mutant it kills. Expected values are closed forms of sampled sines over
whole periods or hand-built grids whose optimum is known by construction, never the code under test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from uavdamp import criterion, grid, strategies
from uavdamp.contract import DamperBounds

DT = 1e-3  # s


def displacement(t: np.ndarray, y: np.ndarray, z: np.ndarray) -> xr.DataArray:
    return xr.DataArray(np.stack([y, z]), dims=("axis", "time"), coords={"axis": ["y", "z"], "time": t})


def two_halves(amp_y: tuple[float, float], amp_z: tuple[float, float], freq_hz: float = 4.0):
    """0 before t = 1 s; sines of amplitude a0 on [1, 1.5] s and a1 on (1.5, 2] s; zero after 2 s (to 3 s)."""
    t = np.round(np.arange(0, 3 + DT / 2, DT), 9)
    phase = np.sin(2 * np.pi * freq_hz * (t - 1.0))
    first, second = (t >= 1.0) & (t <= 1.5), (t > 1.5) & (t <= 2.0)
    y = np.where(first, amp_y[0], 0.0) * phase + np.where(second, amp_y[1], 0.0) * phase
    z = np.where(first, amp_z[0], 0.0) * phase + np.where(second, amp_z[1], 0.0) * phase
    return t, y, z


def sampled_sine_variance(n_periods_samples: int, n_samples: int) -> float:
    """Variance (1/N) of sin over n_samples points that hold whole periods (n_periods_samples of them) plus zeros.

    sum sin^2 over whole periods sampled uniformly = (samples in whole periods) / 2, sum sin = 0 (N > 2 per period).
    """
    return 0.5 * n_periods_samples / n_samples


def test_window_after_zero_selects_only_the_window():
    """Kills 'window ignored' and 'window halved': the sine sits in [1, 2] s, zeros elsewhere (3 s record).

    Window [1, 2] s: 1001 samples, the 1000 of four whole 4 Hz periods (the sample at 2 s is sin = 0), so
    sigma^2 = A^2 (1000 / 2) / 1001 exactly (1/N, mean exactly 0).
    """
    a_y, a_z = 2e-3, 1e-3
    t, y, z = two_halves((a_y, a_y), (a_z, a_z))
    expected = math.sqrt((a_y**2 + a_z**2) * sampled_sine_variance(1000, 1001))
    assert criterion.camera_criterion(displacement(t, y, z), (1.0, 2.0)) == pytest.approx(expected, rel=1e-12)


def test_window_end_is_honoured_when_the_amplitude_changes_halfway():
    """Kills 'window halved': amplitude 1 mm on [1, 1.5] s, 3 mm on (1.5, 2] s; window [1, 2] s.

    Each half holds two whole 4 Hz periods (500 samples); sum of squares A1^2 250 + A2^2 250 over 1001 samples;
    the mean is 0. A halved window ([1, 1.5] s) would give 1 mm / sqrt(2) * sqrt(500 / 501), far from this.
    """
    t, y, z = two_halves((1e-3, 3e-3), (0.0, 0.0))
    expected = math.sqrt((1e-3**2 * 250 + 3e-3**2 * 250) / 1001)
    assert criterion.camera_criterion(displacement(t, y, z), (1.0, 2.0)) == pytest.approx(expected, rel=1e-12)
    first_half = math.sqrt(1e-3**2 * 250 / 501)
    assert criterion.camera_criterion(displacement(t, y, z), (1.0, 1.5)) == pytest.approx(first_half, rel=1e-12)


def test_standard_deviation_is_the_1_over_n_one():
    """Kills ddof=1: four samples (+a, -a, +a, -a) have sigma = a exactly (1/N); ddof=1 gives a sqrt(4/3)."""
    t = np.array([0.0, 0.1, 0.2, 0.3])
    y = np.array([1.0, -1.0, 1.0, -1.0]) * 3e-3
    got = criterion.camera_criterion(displacement(t, y, np.zeros(4)), (0.0, 0.3))
    assert got == pytest.approx(3e-3, rel=1e-14)


def test_window_with_fewer_than_two_samples_is_refused():
    t = np.array([0.0, 0.1, 0.2, 0.3])
    with pytest.raises(ValueError, match=r"window \[0.15, 0.19\] s holds fewer than 2 samples"):
        criterion.camera_criterion(displacement(t, t, t), (0.15, 0.19))
    # the window's edges are inclusive (to 1e-12 s): [0.1, 0.2] holds the two samples 0.1 and 0.2
    assert criterion.camera_criterion(displacement(t, t, 0 * t), (0.1, 0.2)) == pytest.approx(0.05, rel=1e-12)


# ----------------------------------------------------------------------------------------- reference table


def synthetic_grid(values: np.ndarray) -> xr.Dataset:
    """A grid dataset whose displacement criterion is `values` (f_y, f_z, K, C) in one window."""
    shape = values.shape
    spec = grid.GridSpec(
        freq_y=np.arange(1.0, shape[0] + 1),
        freq_z=np.arange(1.0, shape[1] + 1),
        stiffness=np.array([10.0, 20.0, 50.0, 100.0][: shape[2]]),
        damping=np.array([1.0, 2.0, 4.0, 8.0, 16.0][: shape[3]]),
        amplitude=1e-3,
        duration=1.0,
        windows={"transient": (0.0, 1.0)},
    )
    data = {
        criterion.variable("displacement"): (("window", *grid.DIMS), values[None], criterion.CRITERIA["displacement"])
    }
    failed = np.isnan(values).astype(np.int8)
    return xr.Dataset(
        {**data, "failed": (grid.DIMS, failed, {"units": "1", "long_name": "f"})},
        coords={**spec.coords(), **spec.window_coords()},
    )


def table_of(ds: xr.Dataset, *args, **kwargs) -> xr.Dataset:
    """The displacement, transient-window table of a synthetic grid (what the ANFIS learns by default)."""
    return criterion.select_table(criterion.reference_table(ds, *args, **kwargs), "displacement", "transient")


def test_overall_best_stiffness_and_its_damping_by_construction():
    """Kills 'stiffness_opt off by one index' and 'damping_at_stiffness_opt always the first K'.

    Every cell holds 1.0 except one planted minimum per frequency pair at a (K, C) chosen by hand.
    """
    values = np.ones((2, 2, 4, 5))
    planted = {(0, 0): (2, 3, 0.1), (0, 1): (0, 1, 0.2), (1, 0): (3, 4, 0.3), (1, 1): (1, 0, 0.4)}
    for (i, j), (k, c, v) in planted.items():
        values[i, j, k, c] = v
        values[i, j, (k + 1) % 4, (c + 2) % 5] = 0.9  # another K's best C differs: the first-K answer is wrong
    table = table_of(synthetic_grid(values))
    stiffness, damping = [10.0, 20.0, 50.0, 100.0], [1.0, 2.0, 4.0, 8.0, 16.0]
    for (i, j), (k, c, v) in planted.items():
        assert float(table.stiffness_opt[i, j]) == stiffness[k]
        assert float(table.damping_at_stiffness_opt[i, j]) == damping[c]
        assert float(table.criterion_at_stiffness_opt[i, j]) == v


def test_flat_band_by_construction():
    """Kills 'the flat band reduced to the optimum': criterion 1.2, 1.04, 1.0, 1.05, 1.5 over C = 1..16.

    Within (1 + 0.05) of the optimum 1.0: C = 2, 4, 8 (1.05 is on the edge: inclusive). Within 1.03: C = 4 alone.
    """
    values = np.ones((1, 1, 1, 5))
    values[0, 0, 0] = [1.2, 1.04, 1.0, 1.05, 1.5]
    table = table_of(synthetic_grid(values), flat_tolerance=0.05)
    assert float(table.damping_flat_min.squeeze()) == 2.0
    assert float(table.damping_flat_max.squeeze()) == 8.0
    assert "within 5%" in table.damping_flat_min.attrs["long_name"]
    narrow = table_of(synthetic_grid(values), flat_tolerance=0.03)
    assert float(narrow.damping_flat_min.squeeze()) == float(narrow.damping_flat_max.squeeze()) == 4.0


@pytest.mark.filterwarnings("ignore:All-NaN slice:RuntimeWarning", "ignore:Mean of empty slice:RuntimeWarning")
def test_flat_band_of_an_all_failed_cell_is_nan():
    values = np.ones((1, 1, 2, 5))
    values[0, 0, 1] = np.nan
    table = table_of(synthetic_grid(values))
    assert np.isnan(table.damping_flat_min.values[0, 0, 1]) and np.isnan(table.damping_flat_max.values[0, 0, 1])
    assert table.damping_flat_min.values[0, 0, 0] == 1.0 and table.damping_flat_max.values[0, 0, 0] == 16.0
    assert np.isnan(table.damping_opt.values[0, 0, 1])


def test_scheduling_gain_is_exactly_seven_thirds_on_the_fixture():
    """Kills 'scheduling gain as a max': tests/test_reference_table.py's fixture, worked by hand.

    At K index 1 the best C is C0 (0.2) for f_y index 0 and C3 (0.2) for f_y 1, 2; all other cells 1.0.
    Mean over the 9 frequency pairs: C0 (3 * 0.2 + 6) / 9 = 0.733, C3 (6 * 0.2 + 3) / 9 = 0.467, C1, C2 1:
    the best constant is C3. criterion(C3) / criterion_opt: 1.0 / 0.2 = 5 for the 3 pairs with f_y 0, 1 for
    the other 6; mean 21 / 9 = 7 / 3 (a max would give 5). damping_opt spread: C3 / C0 = 8 / 1.
    """
    values = np.ones((3, 3, 2, 4))
    values[..., 0, 2] = 0.5
    values[0, :, 1, 0] = 0.2
    values[1:, :, 1, 3] = 0.2
    table = table_of(synthetic_grid(values))
    assert float(table.scheduling_gain[1]) == pytest.approx(7 / 3, rel=1e-14)
    assert float(table.scheduling_gain[0]) == 1.0
    assert float(table.damping_best_constant[1]) == 8.0 and float(table.damping_best_constant[0]) == 4.0
    np.testing.assert_array_equal(
        table.criterion_best_constant.values[:, :, 1], np.where(np.arange(3)[:, None] == 0, 1.0, 0.2) * np.ones((3, 3))
    )
    assert float(table.damping_opt_spread[1]) == 8.0 and float(table.damping_opt_spread[0]) == 1.0


def test_ties_take_the_smallest_damping_and_failures_are_counted():
    values = np.full((1, 1, 2, 5), 0.7)
    values[0, 0, 0, [1, 3, 4]] = 0.3
    values[0, 0, 1, :] = 0.3  # all equal at K index 1: C = 1 and the smaller K (index 0 also 0.3) wins
    ds = synthetic_grid(values)
    ds["failed"] = (grid.DIMS, np.zeros(values.shape, np.int8), {"units": "1", "long_name": "failed"})
    ds["failed"][0, 0, 1, 2] = 1
    table = table_of(ds)
    assert table.damping_opt.values[0, 0].tolist() == [2.0, 1.0]
    assert float(table.stiffness_opt.squeeze()) == 10.0 and float(table.damping_at_stiffness_opt.squeeze()) == 2.0
    assert table.attrs["n_failed_points"] == 1 and table.attrs["tie_rule"] == "smallest damping among equal minima"
    assert table_of(synthetic_grid(values)).attrs["n_failed_points"] == 0


def test_optimal_passive_ties_take_the_smallest_damping():
    """Kills 'optimal-passive ties resolved to the largest C': a cost flat at its minimum over C in [2, 50]."""
    bounds = DamperBounds(0.0, 200.0)
    candidates = np.geomspace(0.5, 200.0, 12)

    def cost(c: float) -> float:
        return 1.0 + max(0.0, math.log(2.0 / c)) + max(0.0, math.log(c / 50.0))

    c_best, value = strategies.best_constant(cost, candidates, bounds)
    assert value == 1.0
    first_flat = candidates[candidates >= 2.0][0]  # the smallest candidate on the flat part
    assert c_best <= first_flat and cost(c_best) == 1.0


TABLE_METADATA = {  # name: (dims, units, long_name) of every variable reference_table returns (flat_tolerance 0.05)
    "damping_opt": (("freq_y", "freq_z", "stiffness"), "N s m-1", "damping minimising the criterion at each stiffness"),
    "criterion_opt": (("freq_y", "freq_z", "stiffness"), "m", "criterion at damping_opt (displacement)"),
    "damping_flat_min": (("freq_y", "freq_z", "stiffness"), "N s m-1", "smallest damping within 5% of criterion_opt"),
    "damping_flat_max": (("freq_y", "freq_z", "stiffness"), "N s m-1", "largest damping within 5% of criterion_opt"),
    "stiffness_opt": (("freq_y", "freq_z"), "N m-1", "stiffness of the overall best (K, C)"),
    "damping_at_stiffness_opt": (("freq_y", "freq_z"), "N s m-1", "damping of the overall best (K, C)"),
    "criterion_at_stiffness_opt": (("freq_y", "freq_z"), "m", "criterion of the overall best (K, C) (displacement)"),
    "damping_opt_spread": (("stiffness",), "1", "max / min of damping_opt over the input frequencies"),
    "damping_best_constant": (
        ("stiffness",),
        "N s m-1",
        "single damping minimising the mean criterion over all frequencies",
    ),
    "criterion_best_constant": (
        ("freq_y", "freq_z", "stiffness"),
        "m",
        "criterion with damping_best_constant (displacement)",
    ),
    "scheduling_gain": (("stiffness",), "1", "mean of criterion_best_constant / criterion_opt over the frequencies"),
}


def test_every_table_variable_carries_its_dims_units_and_long_name():
    """The NetCDF contract (CF units, long_name), written out here: a changed unit or name fails."""
    values = np.random.default_rng(5).uniform(0.1, 1.0, (2, 3, 2, 4))
    ds = synthetic_grid(values)
    table = table_of(ds)
    assert set(table.data_vars) == set(TABLE_METADATA)
    for name, (dims, units, long_name) in TABLE_METADATA.items():
        assert table[name].dims == dims, name
        assert table[name].attrs == {"units": units, "long_name": long_name}, name
    assert table.attrs == {
        "flat_tolerance": 0.05,
        "tie_rule": "smallest damping among equal minima",
        "n_failed_points": 0,
        "criterion": "displacement",
        "window": "transient",
    }
    for coord in ("freq_y", "freq_z", "stiffness"):
        xr.testing.assert_identical(table[coord], ds[coord])
    assert "damping" not in table.coords
    assert criterion.CRITERION_ATTRS == {
        "units": "m",
        "long_name": "camera displacement sqrt(sigma_y^2 + sigma_z^2) over the window",
    }


def test_table_with_nan_cells_is_nan_where_all_failed_and_finite_elsewhere():
    values = np.random.default_rng(6).uniform(0.1, 1.0, (2, 2, 2, 3))
    values[1, 1] = np.nan  # every K and C failed at this frequency pair
    with np.errstate(all="ignore"):
        table = table_of(synthetic_grid(values))
    for name in ("stiffness_opt", "damping_at_stiffness_opt", "criterion_at_stiffness_opt"):
        assert np.isnan(table[name].values[1, 1]) and np.all(np.isfinite(table[name].values.ravel()[:3])), name
    assert np.all(np.isfinite(table.scheduling_gain)) and np.all(np.isfinite(table.damping_best_constant))
