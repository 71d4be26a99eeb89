"""The ANFIS training stage: samples from the table, the seeded 80/20 split, cross-validated selection on the
training rows, baselines, the training record."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
import xarray as xr
from conftest import ANFIS_OPTIONS as OPTIONS
from conftest import anfis_options as typed
from conftest import copy_workflow, snakemake

from uavdamp import io
from uavdamp.anfis import baselines, model_selection
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
    mean, se, rules = record.cv_rmse_mean.values, record.cv_rmse_se.values, record.n_rules.values
    np.testing.assert_allclose(se, record.cv_rmse.std("fold", ddof=1).values / np.sqrt(3), rtol=1e-15)
    assert record.attrs["selection_rule"] == "one_se"
    within = mean <= mean.min() + se[np.argmin(mean)]
    assert rules[list(record.candidate_label.values).index(record.attrs["selected_candidate"])] == rules[within].min()
    assert record.attrs["n_rules"] == model.anfis.n_rules_
    assert list(record.model.values) == ["anfis", "linear", "knn"]
    assert set(seconds) >= {"anfis", "linear", "knn"} and all(t >= 0 for t in seconds.values())
    for name in list(record.coords) + list(record.data_vars):
        assert {"units", "long_name"} <= set(record[name].attrs), name


# A constructed score table, 4 folds: fold RMSEs, and the rules of each candidate's fold models.
SCORES = {
    "A, 64 rules": ([1.0, 1.2, 0.8, 1.0], 64),  # the best: mean 1, sample std sqrt(0.08 / 3), SE sqrt(0.08 / 3) / 2
    "B, 8 rules": ([1.07, 1.07, 1.07, 1.07], 8),  # within 1 SE (1.07 < 1.0816)
    "C, 4 rules": ([1.09, 1.09, 1.09, 1.09], 4),  # fewer rules, but just outside 1 SE (1.09 > 1.0816)
    "D, 16 rules": ([1.05, 1.05, 1.05, 1.05], 16),  # within 1 SE, more rules than B
}


@pytest.mark.parametrize(("rule", "expected"), [("one_se", "B, 8 rules"), ("best", "A, 64 rules")])
def test_one_se_rule_picks_the_smallest_candidate_within_one_standard_error(rule, expected):
    candidates = [{"init": "fcm", "n_rules": k} for k in range(len(SCORES))]
    results = [(rmse, rules, 0.1) for rmse_folds, rules in SCORES.values() for rmse in rmse_folds]
    chosen, record, _ = model_selection.summarise(candidates, results, 4, rule)
    assert list(SCORES)[chosen] == expected
    threshold = 1.0 + np.sqrt(0.08 / 3) / 2  # closed form: best mean + its std over folds (ddof 1) / sqrt(4)
    assert record.attrs["one_se_threshold"] == pytest.approx(threshold, rel=1e-14)
    np.testing.assert_allclose(record.cv_rmse_se.values, [np.sqrt(0.08 / 3) / 2, 0, 0, 0], atol=1e-15)
    assert record.attrs["best_cv_candidate"] == "fcm n_rules=0" and record.attrs["selection_rule"] == rule


def test_one_se_ties_go_to_the_lower_error_then_the_earlier_candidate():
    mean, se = np.array([1.0, 1.05, 1.04, 1.04]), np.array([0.1, 0.0, 0.0, 0.0])
    assert model_selection.choose(mean, se, np.array([10, 4, 4, 4]), "one_se") == 2
    assert model_selection.choose(mean, se, np.array([4, 4, 8, 8]), "one_se") == 0
    with pytest.raises(ValueError, match="anfis.selection.rule"):
        model_selection.choose(mean, se, np.ones(4), "smallest")


def quadratic_grid(table: xr.Dataset) -> xr.Dataset:
    """A grid whose criterion is 1 + (log10 C - log10 C_opt)^2 around the table's optimum (regret in closed form)."""
    c = np.geomspace(0.1, 100, 9)
    crit = 1 + (np.log10(c)[None, None, None, :] - np.log10(table.damping_opt.values)[..., None]) ** 2
    return xr.Dataset(
        {"criterion": (("freq_y", "freq_z", "stiffness", "damping"), crit)},
        coords={**{k: table[k] for k in learning.INPUTS}, "damping": c},
    )


def test_cv_record_has_each_candidates_regret_on_the_held_out_rows():
    """cv_regret_mean/max: the regret of every training row predicted by the fold model that held it out."""
    table = smooth_table()
    grid = quadratic_grid(table)
    options = typed(OPTIONS)
    _, record, _ = learning.train(table, grid, options)
    X, y, _ = learning.table_samples(table)
    is_train = learning.split(y.size, options.train_fraction, options.seed)
    Xt, yt = X[is_train], y[is_train]
    for k, candidate in enumerate(options.selection.candidates):
        regret = np.empty(len(yt))
        for fit, test in model_selection.splits(len(yt), 3, options.seed):
            model = learning.DampingModel.unfitted(options)
            model.estimator.set_params(**candidate.params())
            regret[test] = learning.regret(grid, Xt[test], model.fit(Xt[fit], yt[fit]).predict(Xt[test]))
        assert float(record.cv_regret_mean[k]) == pytest.approx(regret.mean(), rel=1e-12)
        assert float(record.cv_regret_max[k]) == pytest.approx(regret.max(), rel=1e-12)
    assert np.all(record.cv_regret_max.values >= record.cv_regret_mean.values) and np.all(record.cv_regret_mean >= 1)


@pytest.mark.filterwarnings("ignore::sklearn.exceptions.ConvergenceWarning")  # the GP on a plane
def test_results_do_not_depend_on_the_number_of_workers():
    options = typed({**OPTIONS, "baselines": list(baselines.BASELINES)})
    one = learning.train(smooth_table(), None, options, n_jobs=1)
    two = learning.train(smooth_table(), None, options, n_jobs=2)
    xr.testing.assert_identical(one[1], two[1])
    xr.testing.assert_identical(one[0].to_dataset(), two[0].to_dataset())


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
    grid = quadratic_grid(table)
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
            {"selection": {"folds": 3, "rule": "one_se", "candidates": [{"init": "grid", "radius": 0.5}]}},
            r"anfis.selection.candidates\[0\].n_mfs: init 'grid' takes 'n_mfs' only",
        ),
        (
            {"selection": {"folds": 3, "rule": "one_se", "candidates": [{"init": "fcm"}]}},
            r"candidates\[0\].n_rules: init 'fcm' takes 'n_rules'",
        ),
        (
            {"selection": {"folds": 1, "rule": "one_se", "candidates": [{"init": "grid", "n_mfs": 2}]}},
            "anfis.selection.folds",
        ),
        (
            {"selection": {"folds": 3, "rule": "fewest", "candidates": [{"init": "grid", "n_mfs": 2}]}},
            r"anfis.selection.rule: must be one of \['one_se', 'best'\], got 'fewest'",
        ),
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
        "selection": {"folds": 3, "rule": "one_se", "candidates": [{"init": "fcm", "n_rules": 3}]},
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
    table = [line.split("|")[1:-1] for line in (quick_run / "reports-quick/anfis/rules.md").read_text().splitlines()]
    rows = [cells for cells in table if cells and cells[0].strip().isdigit()]
    assert [int(cells[0]) for cells in rows] == list(range(1, model.anfis.n_rules_ + 1))
    for column in (-2, -1):  # the strongest-rule shares and the mean weights (%), each summing to 100 over the rules
        assert sum(float(cells[column]) for cells in rows) == pytest.approx(100, abs=0.05 * len(rows))
    for name in ("anfis_membership", "anfis_training", "anfis_selection"):
        assert (quick_run / f"reports-quick/figures/{name}.png").stat().st_size > 10_000


def test_the_stage_gives_the_same_numbers_on_one_and_two_threads(quick_run, tmp_path):
    """The quick run's anfis job ran on 1 thread (config/quick.yaml); rerun alone on 2, it writes the same model and
    record."""
    work = copy_workflow(tmp_path)
    shutil.copytree(quick_run / "reports-quick/reference_table", work / "reports-quick/reference_table")
    for path in (work / "reports-quick").rglob("*.nc"):
        path.touch()
    target = "reports-quick/anfis/model.nc"
    args = ("-j2", target, "--allowed-rules", "anfis", "--configfile", "config/quick.yaml", "--set-threads", "anfis=2")
    result = snakemake(work, *args)
    assert result.returncode == 0, result.stderr[-3000:]
    logs = [(root / "reports-quick/logs/anfis.log").read_text() for root in (quick_run, work)]
    assert "workers: 1" in logs[0] and "workers: 2" in logs[1]
    for name in ("model.nc", "training.nc"):
        first, second = (io.open_dataset(root / "reports-quick/anfis" / name) for root in (quick_run, work))
        xr.testing.assert_equal(first, second)
        provenance = ("history", "command_line", "config_files", "run_started")
        same = {k for k in first.attrs if k not in provenance}
        assert {k: first.attrs[k] for k in same} == {k: second.attrs[k] for k in same}, name


def test_regret_is_numpys_interpolation_cell_by_cell():
    """The vectorised regret equals np.interp in log C cell by cell, bit for bit: at grid dampings, between them,
    outside them (clamped), and at cells with failed (NaN) points."""
    table = smooth_table()
    c = np.geomspace(0.1, 100, 9)
    rng = np.random.default_rng(2)
    crit = rng.uniform(1, 3, table.damping_opt.shape + (9,))
    crit[0, 0, 0, [2, 5]] = np.nan
    grid = xr.Dataset(
        {"criterion": (("freq_y", "freq_z", "stiffness", "damping"), crit)},
        coords={**{k: table[k] for k in learning.INPUTS}, "damping": c},
    )
    X, _, _ = learning.table_samples(table)
    damping = np.concatenate([c[rng.integers(0, 9, 40)], rng.uniform(0.01, 300, len(X) - 40)])
    expected = []
    for (fy, fz, k), value in zip(X, damping, strict=True):
        row = grid.criterion.sel(freq_y=fy, freq_z=fz, stiffness=k).values
        ok = np.isfinite(row)
        at = np.interp(np.log(np.clip(value, c[0], c[-1])), np.log(c)[ok], row[ok])
        expected.append(at / np.nanmin(row))
    np.testing.assert_array_equal(learning.regret(grid, X, damping), expected)
    with pytest.raises(KeyError, match="freq_y = 3.3"):
        learning.regret(grid, X[:1] + [0.3, 0, 0], damping[:1])


def test_a_table_whose_optimum_sits_on_the_c_grid_edge_is_refused_before_learning():
    """Seen failing on the previous main: the ANFIS learnt the grid's last C (a bound) as the optimum, silently."""
    table = smooth_table()
    flags = np.zeros(table.damping_opt.shape, dtype=np.int8)
    flags[:, :, -1] = 2  # the stiffest quarter of the cells: optimum at the grid's top C
    flags[0, 0, 0] = 3  # at the damper's own bound: kept
    table["optimum_at_grid_edge"] = (learning.INPUTS, flags, {"units": "1", "long_name": "edge flag"})
    message = (
        r"reference table: the optimal C of 25\.0% of its cells \(30 at the top, 0 at the bottom of 120\) lies on "
        r"an edge of the C grid reference_table\.damping_n_s_m \(start, stop\)"
    )
    with pytest.raises(ValueError, match=message) as error:
        learning.train(table, None, typed(OPTIONS))
    assert "widen reference_table.damping_n_s_m" in str(error.value)
    flags[:, :, -1] = 0
    table["optimum_at_grid_edge"] = (learning.INPUTS, flags, {"units": "1", "long_name": "edge flag"})
    learning.check_grid_edges(table)  # only the damper's bound: accepted
