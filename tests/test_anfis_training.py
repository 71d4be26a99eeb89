"""The ANFIS training stage: samples from the table, the seeded 80/20 split, cross-validated selection on the
training rows, baselines, the training record."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from conftest import ANFIS_OPTIONS as OPTIONS
from conftest import anfis_options as typed

from uavdamp import io
from uavdamp.anfis import baselines
from uavdamp.anfis import training as learning


def smooth_table(nan_cells: int = 0) -> xr.Dataset:
    fy, fz, k = np.linspace(3, 12, 6), np.linspace(3, 12, 5), np.geomspace(10, 4000, 4)
    FY, FZ, K = np.meshgrid(fy, fz, k, indexing="ij")
    c = 2.0 + 0.3 * FY + 0.1 * FZ + 0.004 * K  # N s/m, smooth and positive
    c.ravel()[:nan_cells] = np.nan
    attrs = {"units": "Hz", "long_name": "f"}
    return xr.Dataset(
        {"damping_opt": (learning.INPUTS, c, {"units": "N s m-1", "long_name": "C"})},
        coords={
            "freq_y": ("freq_y", fy, attrs),
            "freq_z": ("freq_z", fz, attrs),
            "stiffness": ("stiffness", k, {"units": "N m-1", "long_name": "K"}),
        },
    )


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
    with pytest.raises(ValueError, match=r"anfis.train_fraction: must lie in \(0, 1\), got 1.0"):
        typed({**OPTIONS, "train_fraction": 1.0})


def test_training_record_and_fit_quality():
    model, record, seconds = learning.train(smooth_table(nan_cells=2), None, typed(OPTIONS))
    assert record.attrs["n_samples"] == 118 and record.attrs["n_dropped_nan"] == 2
    assert record.attrs["n_training"] == round(0.8 * 118)
    assert record.sizes["epoch"] == 40
    best = record.attrs["best_epoch"]
    assert record.validation_rmse.values[best - 1] == pytest.approx(np.min(record.validation_rmse.values))
    # a linear target is inside a first-order TS model's reach: near-exact on held-out cells
    assert record.attrs["check_rmse_final"] < 1e-3 * float(record.damping_reference.mean())
    np.testing.assert_allclose(
        record.damping_predicted.values, model.predict(np.column_stack([record[n].values for n in learning.INPUTS]))
    )
    assert "IF f_y is" in model.rules_text() and "THEN C =" in model.rules_text()
    # every candidate's CV error, every model's checking error; fit times apart from the record
    assert list(record.candidate_label.values) == ["grid n_mfs=2", "subtractive radius=0.5"]
    assert record.cv_rmse.shape == (2, 3) and record.attrs["cv_folds"] == 3
    assert record.attrs["selected_candidate"] == record.candidate_label.values[np.argmin(record.cv_rmse_mean.values)]
    assert list(record.model.values) == ["anfis", "linear", "knn"]
    assert set(seconds) >= {"anfis", "linear", "knn"} and all(t >= 0 for t in seconds.values())
    for name in list(record.coords) + list(record.data_vars):
        assert {"units", "long_name"} <= set(record[name].attrs), name


def test_cv_never_sees_the_checking_split():
    """Changing every checking cell's C leaves the selection, the ANFIS and the baselines unchanged."""
    table = smooth_table()
    _, y, _ = learning.table_samples(table)
    is_train = learning.split(y.size, OPTIONS["train_fraction"], OPTIONS["seed"])
    poisoned = table.copy(deep=True)
    values = poisoned.damping_opt.transpose(*learning.INPUTS).values.reshape(-1)
    values[~is_train] *= 50.0
    poisoned["damping_opt"] = (learning.INPUTS, values.reshape(table.damping_opt.shape), table.damping_opt.attrs)
    _, clean, _ = learning.train(table, None, typed(OPTIONS))
    _, dirty, _ = learning.train(poisoned, None, typed(OPTIONS))
    assert np.array_equal(dirty.cv_rmse.values, clean.cv_rmse.values)
    assert dirty.attrs["selected_candidate"] == clean.attrs["selected_candidate"]
    assert np.array_equal(dirty.train_rmse.values, clean.train_rmse.values)
    assert np.array_equal(dirty.damping_predicted_by_model.values, clean.damping_predicted_by_model.values)
    assert dirty.attrs["check_rmse_final"] > 10 * clean.attrs["check_rmse_final"]  # the checking rows did change


def test_matlab_checking_epoch_selection():
    """epoch_selection checking (MATLAB chkFIS): the kept epoch minimises the checking RMSE."""
    table = smooth_table()
    model, record, _ = learning.train(table, None, typed({**OPTIONS, "epoch_selection": "checking", "epochs": 30}))
    check = record.is_training.values == 0
    X = np.column_stack([record[n].values for n in learning.INPUTS])
    rmse = np.sqrt(np.mean((model.predict(X[check]) - record.damping_reference.values[check]) ** 2))
    assert rmse == pytest.approx(float(record.validation_rmse.min()), rel=1e-9)
    assert record.attrs["best_epoch"] == np.argmin(record.validation_rmse.values) + 1
    assert "chkFIS" in record.validation_rmse.attrs["long_name"]


def test_linear_interpolation_baseline():
    """Piecewise-linear interpolation reproduces a linear function inside the training cells' hull and
    gives the nearest training cell's value outside it."""
    rng = np.random.default_rng(3)
    X = rng.uniform([3, 3, 1], [12, 12, 3.5], (80, 3))
    y = 1.0 + 0.2 * X[:, 0] - 0.1 * X[:, 1] + 0.7 * X[:, 2]
    model = baselines.LinearInterpolation().fit(X, y)
    inside = X.mean(axis=0) + 0.1 * (X[:5] - X.mean(axis=0))
    np.testing.assert_allclose(model.predict(inside), 1.0 + inside @ [0.2, -0.1, 0.7], rtol=1e-12)
    far = np.array([[100.0, 100.0, 100.0]])
    scaled = (np.vstack([X, far]) - X.min(axis=0)) / np.ptp(X, axis=0)
    corner = np.argmin(np.sum((scaled[:-1] - scaled[-1]) ** 2, axis=1))
    assert model.predict(far)[0] == y[corner]


@pytest.mark.filterwarnings("ignore:The optimal value found:sklearn.exceptions.ConvergenceWarning")
def test_all_baselines_and_regret_per_model():
    """(The table is a plane in C: the GP's noise level and length scales run to their bounds, and say so.)"""
    table = smooth_table()
    c = np.geomspace(0.1, 100, 9)
    crit = 1 + (np.log10(c)[None, None, None, :] - np.log10(table.damping_opt.values)[..., None]) ** 2
    grid = xr.Dataset(
        {"criterion": (("freq_y", "freq_z", "stiffness", "damping"), crit)},
        coords={**{k: table[k] for k in learning.INPUTS}, "damping": c},
    )
    options = {**OPTIONS, "baselines": list(baselines.BASELINES), "log_stiffness": True, "log_damping": True}
    _, record, _ = learning.train(table, grid, typed(options))
    assert list(record.model.values) == ["anfis", *baselines.BASELINES]
    assert np.all(record.regret_by_model.values >= 1 - 1e-12)
    assert np.all(record.check_regret_mean.values >= 1) and np.all(record.check_regret_max >= record.check_regret_mean)
    assert record.check_rmse_target.attrs["units"] == "1" and record.check_rmse_damping.attrs["units"] == "N s m-1"
    np.testing.assert_array_equal(record.regret.values, record.regret_by_model.sel(model="anfis").values)


@pytest.mark.parametrize(
    "change, match",
    [
        ({"baselines": ["svm"]}, "anfis.baselines: unknown baseline 'svm'"),
        ({"epoch_selection": "best"}, "anfis.epoch_selection"),
        ({"validation_fraction": 0.0}, "anfis.validation_fraction"),
        (
            {"selection": {"folds": 3, "candidates": [{"init": "grid", "radius": 0.5}]}},
            r"anfis.selection.candidates\[0\].n_mfs: init 'grid' takes 'n_mfs' only",
        ),
        (
            {"selection": {"folds": 3, "candidates": [{"init": "fcm"}]}},
            r"candidates\[0\].n_rules: init 'fcm' takes 'n_rules'",
        ),
        ({"selection": {"folds": 1, "candidates": [{"init": "grid", "n_mfs": 2}]}}, "anfis.selection.folds"),
    ],
)
def test_bad_options_raise(change, match):
    with pytest.raises(ValueError, match=match):
        learning.train(smooth_table(), None, typed({**OPTIONS, **change}))


def test_log_transforms_round_trip_and_regret():
    """log10 K and C: predictions in N s/m, positive; regret 1 at the optimum, > 1 away from it."""
    table = smooth_table()
    model, record, _ = learning.train(table, None, typed({**OPTIONS, "log_stiffness": True, "log_damping": True}))
    assert "log10_K is" in model.rules_text() and "THEN log10_C =" in model.rules_text()
    assert np.all(record.damping_predicted.values > 0)
    X = np.column_stack([record[n].values for n in learning.INPUTS])
    again = learning.DampingModel.from_dataset(model.to_dataset())
    np.testing.assert_array_equal(again.predict(X), model.predict(X))
    # a grid whose criterion is 1 + |log10 C - log10 C*|, C* = 3.16 N s/m: regret 1 at C*, 2 a decade away
    c = np.geomspace(0.1, 100, 7)
    crit = np.broadcast_to(1 + np.abs(np.log10(c) - np.log10(c[3])), table.damping_opt.shape + (7,))
    grid = xr.Dataset(
        {"criterion": (("freq_y", "freq_z", "stiffness", "damping"), crit)},
        coords={**{k: table[k] for k in learning.INPUTS}, "damping": c},
    )
    np.testing.assert_allclose(learning.regret(grid, X, np.full(len(X), c[3])), 1.0, rtol=1e-12)
    np.testing.assert_allclose(learning.regret(grid, X, np.full(len(X), c[5])), 2.0, rtol=1e-12)
    halfway = learning.regret(grid, X, np.full(len(X), np.sqrt(c[3] * c[4])))  # interpolated in log C
    np.testing.assert_allclose(halfway, 1.25, rtol=1e-12)


def test_training_is_deterministic():
    options = {
        **OPTIONS,
        "epochs": 15,
        "baselines": ["linear", "knn", "hgb"],
        "selection": {"folds": 3, "candidates": [{"init": "fcm", "n_rules": 3}]},
    }
    _, a, _ = learning.train(smooth_table(), None, typed(options))
    _, b, _ = learning.train(smooth_table(), None, typed(options))
    xr.testing.assert_identical(a, b)


def test_quick_stage_outputs(quick_run):
    model = learning.DampingModel.from_dataset(io.open_dataset(quick_run / "reports-quick/anfis/model.nc"))
    record = io.open_dataset(quick_run / "reports-quick/anfis/training.nc")
    X = np.column_stack([record[n].values for n in learning.INPUTS])
    np.testing.assert_array_equal(model.predict(X), record.damping_predicted.values)
    assert record.sizes["epoch"] == 50 and np.all(record.regret.values >= 1 - 1e-12)
    rules = (quick_run / "reports-quick/anfis/rules.txt").read_text()
    assert rules.count("IF ") == model.anfis.n_rules_
    for name in ("anfis_membership", "anfis_training", "anfis_selection"):
        assert (quick_run / f"reports-quick/figures/{name}.png").stat().st_size > 10_000
