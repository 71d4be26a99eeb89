"""The ANFIS training stage: samples from the table, the seeded 80/20 split, the training record."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from uavdamp import io, learning


def smooth_table(nan_cells: int = 0) -> xr.Dataset:
    fy, fz, k = np.linspace(3, 12, 6), np.linspace(3, 12, 5), np.geomspace(10, 4000, 4)
    FY, FZ, K = np.meshgrid(fy, fz, k, indexing="ij")
    c = 2.0 + 0.3 * FY + 0.1 * FZ + 0.004 * K  # N s/m, smooth and positive
    c.ravel()[:nan_cells] = np.nan
    attrs = {"units": "Hz", "long_name": "f"}
    return xr.Dataset({"damping_opt": (learning.INPUTS, c, {"units": "N s m-1", "long_name": "C"})},
                      coords={"freq_y": ("freq_y", fy, attrs), "freq_z": ("freq_z", fz, attrs),
                              "stiffness": ("stiffness", k, {"units": "N m-1", "long_name": "K"})})


OPTIONS = {"init": "grid", "n_mfs": 2, "n_rules": 2, "epochs": 40, "error_goal": 0.0, "step_size": 0.01,
           "step_increase": 1.1, "step_decrease": 0.9, "min_sigma_frac": 0.01, "ridge": 0.0,
           "log_stiffness": False, "log_damping": False, "train_fraction": 0.8, "seed": 7}


def test_samples_drop_failed_cells():
    X, y, dropped = learning.table_samples(smooth_table(nan_cells=3))
    assert X.shape == (6 * 5 * 4 - 3, 3) and y.shape == (117,) and dropped == 3
    assert np.all(np.isfinite(y))
    # row order follows the table's (freq_y, freq_z, stiffness) C order
    assert X[-1].tolist() == pytest.approx([12.0, 12.0, 4000.0])


def test_split_is_seeded_and_sized():
    a, b = learning.split(100, 0.8, 1), learning.split(100, 0.8, 1)
    np.testing.assert_array_equal(a, b)
    assert a.sum() == 80
    assert not np.array_equal(a, learning.split(100, 0.8, 2))
    with pytest.raises(ValueError, match="train_fraction"):
        learning.split(10, 1.0, 0)


def test_training_record_and_fit_quality():
    model, record = learning.train(smooth_table(nan_cells=2), None, OPTIONS)
    assert record.attrs["n_samples"] == 118 and record.attrs["n_dropped_nan"] == 2
    assert record.attrs["n_training"] == round(0.8 * 118)
    assert record.sizes["epoch"] == 40
    best = record.attrs["best_epoch"]
    assert record.check_rmse.values[best - 1] == pytest.approx(np.min(record.check_rmse.values))
    # a linear target is inside a first-order TS model's reach: near-exact on held-out cells
    assert record.attrs["check_rmse_final"] < 1e-3 * float(record.damping_reference.mean())
    np.testing.assert_allclose(record.damping_predicted.values,
                               model.predict(np.column_stack([record[n].values for n in learning.INPUTS])))
    assert "IF f_y is" in model.rules_text() and "THEN C =" in model.rules_text()


def test_log_transforms_round_trip_and_regret():
    """log10 K and C: predictions in N s/m, positive; regret 1 at the optimum, > 1 away from it."""
    table = smooth_table()
    model, record = learning.train(table, None, {**OPTIONS, "log_stiffness": True, "log_damping": True})
    assert "log10_K is" in model.rules_text() and "THEN log10_C =" in model.rules_text()
    assert np.all(record.damping_predicted.values > 0)
    X = np.column_stack([record[n].values for n in learning.INPUTS])
    again = learning.TableModel.from_dataset(model.to_dataset())
    np.testing.assert_array_equal(again.predict(X), model.predict(X))
    # a grid whose criterion is 1 + |log10 C - log10 C*|, C* = 3.16 N s/m: regret 1 at C*, 2 a decade away
    c = np.geomspace(0.1, 100, 7)
    crit = np.broadcast_to(1 + np.abs(np.log10(c) - np.log10(c[3])), table.damping_opt.shape + (7,))
    grid = xr.Dataset({"criterion": (("freq_y", "freq_z", "stiffness", "damping"), crit)},
                      coords={**{k: table[k] for k in learning.INPUTS}, "damping": c})
    np.testing.assert_allclose(learning.regret(grid, X, np.full(len(X), c[3])), 1.0, rtol=1e-12)
    np.testing.assert_allclose(learning.regret(grid, X, np.full(len(X), c[5])), 2.0, rtol=1e-12)
    halfway = learning.regret(grid, X, np.full(len(X), np.sqrt(c[3] * c[4])))  # interpolated in log C
    np.testing.assert_allclose(halfway, 1.25, rtol=1e-12)


def test_training_is_deterministic():
    _, a = learning.train(smooth_table(), None, {**OPTIONS, "init": "fcm", "epochs": 15})
    _, b = learning.train(smooth_table(), None, {**OPTIONS, "init": "fcm", "epochs": 15})
    xr.testing.assert_identical(a, b)


def test_quick_stage_outputs(quick_run):
    model = learning.TableModel.from_dataset(io.open_dataset(quick_run / "reports/anfis/model.nc"))
    record = io.open_dataset(quick_run / "reports/anfis/training.nc")
    X = np.column_stack([record[n].values for n in learning.INPUTS])
    np.testing.assert_array_equal(model.predict(X), record.damping_predicted.values)
    assert record.sizes["epoch"] == 50 and np.all(record.regret.values >= 1 - 1e-12)
    rules = (quick_run / "reports/anfis/rules.txt").read_text()
    assert rules.count("IF ") == model.anfis.n_rules_
    for name in ("anfis_membership", "anfis_training"):
        assert (quick_run / f"reports/figures/{name}.png").stat().st_size > 10_000
