"""Laws that hold for all inputs, checked with hypothesis.

- the camera criterion is invariant to a constant offset of either axis (a standard deviation);
- a clipped demand never leaves the damper bounds, and a demand inside them passes unchanged;
- an ANFIS refitted on scaled inputs predicts the same at the scaled points (its initialisation, step size and
  sigma floor are fractions of each input's range);
- the reference table's argmins equal a brute-force search (loops over the cells) on random small grids,
  with ties and failed (NaN) points.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import xarray as xr
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from uavdamp import contract
from uavdamp.anfis.estimator import ANFIS
from uavdamp.damping import laws
from uavdamp.reference_table import criteria as criterion
from uavdamp.reference_table import grid

finite = st.floats(min_value=-1e9, max_value=1e9, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None)
@given(
    offset_y=st.floats(-1.0, 1.0),
    offset_z=st.floats(-1.0, 1.0),
    seed=st.integers(0, 2**32 - 1),
    start=st.integers(0, 50),
    length=st.integers(2, 100),
)
def test_criterion_is_invariant_to_a_constant_offset(offset_y, offset_z, seed, start, length):
    rng = np.random.default_rng(seed)
    t = np.arange(200) * 0.01
    disp = rng.normal(0, 1e-3, (2, 200))
    window = (t[start], t[min(start + length, 199)])
    base = criterion.camera_criterion(xr.DataArray(disp, dims=("axis", "time"), coords={"time": t}), window)
    shifted = disp + np.array([[offset_y], [offset_z]])
    moved = criterion.camera_criterion(xr.DataArray(shifted, dims=("axis", "time"), coords={"time": t}), window)
    # the offset cancels in x - mean(x) up to round-off of |offset| ~ 1 against samples ~ 1e-3
    assert moved == pytest.approx(base, rel=1e-9, abs=1e-13)


@settings(max_examples=200, deadline=None)
@given(demand=finite, lo=st.floats(0, 1e4), width=st.floats(0, 1e4), t_now=st.floats(0, 100))
def test_clipped_demand_never_leaves_the_bounds(demand, lo, width, t_now):
    bounds = contract.DamperBounds(lo, lo + width)
    c = contract.clip(demand, bounds, t_now)
    assert bounds.c_min <= c <= bounds.c_max and bounds.contains(c)
    if bounds.c_min <= demand <= bounds.c_max:
        assert c == demand
    else:
        assert c == (bounds.c_min if demand < bounds.c_min else bounds.c_max)


@settings(max_examples=100, deadline=None)
@given(
    values=st.lists(finite, min_size=1, max_size=6),
    v_abs=st.tuples(finite, finite),
    v_rel=st.tuples(finite, finite),
    lo=st.floats(0, 100),
    width=st.floats(0, 100),
)
def test_every_law_clipped_stays_within_the_bounds(values, v_abs, v_rel, lo, width):
    bounds = contract.DamperBounds(lo, lo + width)
    obs = contract.Observation(0.0, np.zeros(1), np.zeros((1, 6)), np.asarray(v_abs), np.zeros(2), np.zeros(2))
    schedule = laws.Schedule(values)
    demands = [schedule(obs) for _ in range(len(values) + 2)]
    assert demands == [*values, values[-1], values[-1]]
    skyhook = laws.Skyhook(values[0], values[-1], 1e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # v_abs . v_rel may overflow to inf: still a sign
        sky = skyhook.decide(np.asarray(v_abs), np.asarray(v_rel))
    for demand in [*demands, laws.Constant(values[0])(obs), sky]:
        assert bounds.c_min <= contract.clip(demand, bounds, 0.0) <= bounds.c_max


LO, HI = np.array([5.0, 5.0, 10.0]), np.array([30.0, 30.0, 1000.0])


def _smooth(X):
    return 2 + np.sin(X[:, 0] / 5) + 0.5 * (X[:, 1] / 20) ** 2 + np.exp(-X[:, 2] / 500)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scale=st.tuples(*[st.floats(1e-3, 1e3)] * 3), init=st.sampled_from(["grid", "fcm", "subtractive"]))
def test_anfis_prediction_is_invariant_to_input_scaling_after_refit(scale, init):
    rng = np.random.default_rng(7)
    X = LO + (HI - LO) * rng.random((120, 3))
    X_new = LO + (HI - LO) * rng.random((20, 3))
    s = np.asarray(scale)
    options = {"grid": {"n_mfs": 2}, "fcm": {"n_rules": 2}, "subtractive": {}}[init]
    plain = ANFIS(init=init, epochs=15, **options).fit(X, _smooth(X)).predict(X_new)
    scaled = ANFIS(init=init, epochs=15, **options).fit(X * s, _smooth(X)).predict(X_new * s)
    np.testing.assert_allclose(scaled, plain, rtol=1e-7)


def _brute_force(values, damping, stiffness):
    """Per cell: the first (smallest C) minimum of the non-NaN points, by loops."""
    ny, nz, nk, nc = values.shape
    c_opt = np.full((ny, nz, nk), np.nan)
    crit_opt = np.full((ny, nz, nk), np.nan)
    k_opt = np.full((ny, nz), np.nan)
    c_at_k = np.full((ny, nz), np.nan)
    for i in range(ny):
        for j in range(nz):
            best = (math.inf, None, None)
            for k in range(nk):
                for c in range(nc):
                    v = values[i, j, k, c]
                    if not math.isnan(v) and (math.isnan(crit_opt[i, j, k]) or v < crit_opt[i, j, k]):
                        crit_opt[i, j, k], c_opt[i, j, k] = v, damping[c]
                    if not math.isnan(v) and v < best[0]:
                        best = (v, k, c)
            if best[1] is not None:
                k_opt[i, j], c_at_k[i, j] = stiffness[best[1]], damping[best[2]]
    return c_opt, crit_opt, k_opt, c_at_k


@settings(max_examples=150, deadline=None)
@given(
    values=hnp.arrays(
        float,
        hnp.array_shapes(min_dims=4, max_dims=4, min_side=1, max_side=3),
        elements=st.sampled_from([0.1, 0.2, 0.3, 0.5, 1.0, np.nan]),
    )
)
def test_reference_table_argmins_equal_brute_force(values):
    ny, nz, nk, nc = values.shape
    spec = grid.GridSpec(
        freq_y=np.arange(1.0, ny + 1),
        freq_z=np.arange(1.0, nz + 1),
        stiffness=np.arange(1.0, nk + 1) * 10,
        damping=np.arange(1.0, nc + 1) * 2,
        amplitude=1e-3,
        duration=1.0,
        windows={"transient": (0.0, 1.0)},
    )
    ds = xr.Dataset(
        {
            criterion.variable("displacement"): (
                ("window", *grid.DIMS),
                values[None],
                criterion.CRITERIA["displacement"],
            ),
            "failed": (grid.DIMS, np.isnan(values).astype(np.int8), {"units": "1", "long_name": "f"}),
        },
        coords={**spec.coords(), **spec.window_coords()},
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN slices in the spread and gain reductions
        table = criterion.select_table(criterion.reference_table(ds), "displacement", "transient")
    c_opt, crit_opt, k_opt, c_at_k = _brute_force(values, spec.damping, spec.stiffness)
    np.testing.assert_array_equal(table.damping_opt.values, c_opt)
    np.testing.assert_array_equal(table.criterion_opt.values, crit_opt)
    np.testing.assert_array_equal(table.stiffness_opt.values, k_opt)
    np.testing.assert_array_equal(table.damping_at_stiffness_opt.values, c_at_k)
