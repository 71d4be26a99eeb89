"""The paper's ANFIS on the payload (`uavdamp.study.payload_anfis`): its reference against hand sums on a table of
hand values, the dampings it may learn, its training on a closed-form payload table, and the law it becomes (the
model's inputs in the DOFs' order, its clamp, its fallback, a run that holds one C)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from conftest import anfis_options
from test_payload import _section

from uavdamp.anfis.training import train
from uavdamp.settings import ConfigError
from uavdamp.study import payload_anfis as pa
from uavdamp.study import payload_schedule as ps
from uavdamp.study import payload_table as pt
from uavdamp.study.payload_anfis import AnfisPayloadSection


def _hand_table() -> xr.Dataset:
    """The payload table's variables at one K (500 N/m) with hand values: x and pitch at 5 and 20 Hz, three
    dampings whose decay times are 0.1, 0.2 and 0.9 s; the other DOFs blind."""
    crit = np.zeros((6, 2, 1, 3))
    crit[0, :, 0] = [[4.0, 2.0, 1.0], [1.0, 2.0, 8.0]]  # x: lock at 5 Hz, free at 20 Hz
    crit[4, :, 0] = [[1.0, 1.0, 1.0], [2.0, 1.0, 2.0]]  # pitch: the middle C at 20 Hz
    return xr.Dataset(
        {
            "criterion": (("dof", "freq", "stiffness", "damping"), crit, {"units": "rad", "long_name": "LOS"}),
            "decay_time": (("stiffness", "damping"), [[0.1, 0.2, 0.9]], {"units": "s", "long_name": "decay"}),
        },
        {
            "dof": ["x", "y", "z", "rx", "ry", "rz"],
            "freq": [5.0, 20.0],
            "stiffness": ("stiffness", [500.0], {"units": "N m-1", "long_name": "K"}),
            "damping": ("damping", [1.0, 10.0, 100.0], {"units": "N s m-1", "long_name": "C"}),
        },
        {"translation_amplitude_m": 1e-3, "rotation_amplitude_rad": 1e-3},
    )


def _anfis_section(**keys) -> AnfisPayloadSection:
    return _section(anfis={"dofs": ["x", "ry"], "freq_hz": {"values": [5.0, 10.0, 20.0]}, **keys}).anfis


def test_the_reference_is_the_least_sum_of_the_two_lines_in_power():
    """Hand sums: at (f_x, f_ry) = (10, 20) Hz x is (2.5, 2, 4.5) (halfway in log f) and pitch (2, 1, 2): squares
    10.25, 5, 24.25, the middle C; at (5, 5) Hz x (4, 2, 1) and pitch (1, 1, 1): 17, 5, 2, the largest C, or the
    middle one when the largest does not settle in time (its criterion then NaN)."""
    table, grid = pa.reference(_hand_table(), _anfis_section(), math.inf)
    cell = grid.criterion.sel(freq_x=10.0, freq_ry=20.0, stiffness=500.0).values
    np.testing.assert_allclose(cell, np.sqrt([10.25, 5.0, 24.25]), rtol=1e-12)
    assert float(table.damping_opt.sel(freq_x=10.0, freq_ry=20.0, stiffness=500.0)) == 10.0
    assert float(table.damping_opt.sel(freq_x=5.0, freq_ry=5.0, stiffness=500.0)) == 100.0
    assert float(table.criterion_opt.sel(freq_x=5.0, freq_ry=5.0, stiffness=500.0)) == pytest.approx(math.sqrt(2))
    table, grid = pa.reference(_hand_table(), _anfis_section(), 0.5)
    assert np.isnan(grid.criterion.sel(damping=100.0)).all() and np.isfinite(grid.criterion.sel(damping=10.0)).all()
    assert float(table.damping_opt.sel(freq_x=5.0, freq_ry=5.0, stiffness=500.0)) == 10.0
    shares = pa.record_attrs(_anfis_section(), table, grid)  # 1 and 10 N s/m eligible: each cell's best is either
    assert shares.pop("dofs") == "x ry"
    assert shares["share_at_least_eligible_damping"] + shares["share_at_largest_eligible_damping"] == 1.0
    assert shares["share_at_largest_eligible_damping"] == float(np.mean(table.damping_opt.values == 10.0))


def test_dofs_that_do_not_reach_the_line_of_sight_and_bad_keys_are_refused():
    with pytest.raises(ValueError, match="payload.anfis.dofs: neither y nor z"):
        pa.reference(_hand_table(), _anfis_section(dofs=["y", "z"]), math.inf)
    with pytest.raises(ConfigError, match="payload.anfis.dofs"):
        _anfis_section(dofs=["x", "x"])
    with pytest.raises(ConfigError, match="payload.anfis.dofs"):
        _anfis_section(dofs=["x", "pitch"])
    with pytest.raises(ConfigError, match="payload.anfis.freq_hz"):  # beyond the payload table's 2-120 Hz
        _section(anfis={"dofs": ["x", "ry"], "freq_hz": {"values": [1.0, 10.0]}})


class _Plane:
    """A stand-in model: C = f_a + f_b / 1000 + K / 1e6, recording the rows it is asked."""

    def __init__(self):
        self.rows = []

    def predict(self, X):
        X = np.asarray(X, dtype=float)
        self.rows.append(X.copy())
        return X[:, 0] + X[:, 1] / 1e3 + X[:, 2] / 1e6


def test_the_law_asks_the_model_in_its_dofs_order_clamps_and_falls_back():
    lines = np.full((6, 2), math.nan)
    lines[0], lines[4] = (7.0, 1e-3), (9.0, 1e-3)  # x, pitch
    model = _Plane()
    law = pa.AnfisLaw(model, ("x", "ry"), 500.0, 1.0, 100.0)
    assert law(lines, 3.0) == pytest.approx(7.0 + 0.009 + 0.0005)
    np.testing.assert_array_equal(model.rows[-1], [[7.0, 9.0, 500.0]])
    assert pa.AnfisLaw(model, ("ry", "x"), 500.0, 1.0, 100.0)(lines, 3.0) == pytest.approx(9.0 + 0.007 + 0.0005)
    assert pa.AnfisLaw(model, ("x", "ry"), 500.0, 8.0, 100.0)(lines, 3.0) == 8.0  # clamped to the eligible C
    assert pa.AnfisLaw(model, ("x", "ry"), 500.0, 1.0, 5.0)(lines, 3.0) == 5.0
    lines[4] = math.nan, math.nan  # no pitch line: the fallback, the model not asked
    asked = len(model.rows)
    assert law(lines, 3.0) == 3.0 and len(model.rows) == asked


def test_a_replanned_law_is_held_between_the_tracked_updates():
    """The ANFIS's plan on the scheduled law's lines and times: each update's C held until the next."""
    t = np.arange(0, 2.0 + 1e-9, 1e-3)
    lines = np.zeros((5, 6, 2))
    plan = ps.Schedule(np.arange(5) * 0.5, None, lines, None)
    section = _section().schedule
    count = iter(range(1, 6))
    replanned = ps.replanned(plan, t, lambda found, fallback: float(next(count)), section)
    np.testing.assert_array_equal(replanned.damping, [1, 2, 3, 4, 5])
    np.testing.assert_array_equal(replanned.per_sample, np.minimum(np.floor(t / 0.5 + 1e-9) + 1, 5))


def test_training_on_a_closed_form_table_records_the_reference_and_the_regret():
    """The ANFIS learns the reference of a closed-form payload table (two K, coarse): its record's reference C per
    sample is the reference's, its predictions are the model's, and every regret is at least 1 (the reference
    is each cell's least criterion)."""
    section = _section(
        table={
            "stiffness_n_m": {"values": [250.0, 500.0]},
            "freq_hz": {"start": 2.0, "stop": 120.0, "num": 13, "spacing": "log"},
        },
        anfis={"dofs": ["x", "ry"], "freq_hz": {"start": 2.0, "stop": 120.0, "num": 7, "spacing": "log"}},
    )
    payload_table = pt.table_dataset(section)
    reference, grid = pa.reference(payload_table, section.anfis, section.schedule.max_decay_time)
    model, record, _ = train(reference, grid, anfis_options(epochs=10), inputs=section.anfis.inputs)
    X = np.column_stack([record[n].values for n in section.anfis.inputs])
    expected = [float(reference.damping_opt.sel(freq_x=a, freq_ry=b, stiffness=k)) for a, b, k in X]
    np.testing.assert_array_equal(record.damping_reference.values, expected)
    np.testing.assert_allclose(record.damping_predicted.values, model.predict(X), rtol=1e-12)
    assert (record.regret_by_model.values >= 1 - 1e-12).all()
    assert record.sizes["sample"] == 98
    assert model.anfis.input_names[:2] == ["f_x", "f_ry"]
