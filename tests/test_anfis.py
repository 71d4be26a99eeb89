"""Tests of the ANFIS estimator (uavdamp.anfis): gradient, fit quality, step-size rule, snapshots,
persistence, guards, argument checks, scikit-learn compatibility, subtractive clustering and numerics."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.linalg
import xarray as xr
from scipy import sparse
from skfuzzy import gaussmf
from sklearn.base import clone
from sklearn.exceptions import NotFittedError
from sklearn.model_selection import GridSearchCV, KFold, cross_val_score
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.utils.estimator_checks import check_estimator

from uavdamp.anfis import _math as anfis_math
from uavdamp.anfis import initialisation as anfis_init
from uavdamp.anfis.estimator import ANFIS, EXPECTED_FAILED_CHECKS, loss_and_gradient, update_step_size

# any warning not expected with pytest.warns fails the test
pytestmark = pytest.mark.filterwarnings("error")

LO = np.array([5.0, 5.0, 10.0])  # f_y [Hz], f_z [Hz], K [N/m]
HI = np.array([30.0, 30.0, 1000.0])
NAMES = dict(input_names=["f_y", "f_z", "K"], input_units=["Hz", "Hz", "N/m"], output_name="C", output_units="N s/m")


def smooth(X):
    """Test function: y = 2 + sin(f_y / 5) + 0.5 (f_z / 20)^2 + exp(-K / 500), between 1.3 and 4.7
    for f_y, f_z in [5, 30] Hz and K in [10, 1000] N/m (inputs on very different scales on purpose)."""
    return 2 + np.sin(X[:, 0] / 5) + 0.5 * (X[:, 1] / 20) ** 2 + np.exp(-X[:, 2] / 500)


def sample(n, seed):
    rng = np.random.default_rng(seed)
    X = LO + (HI - LO) * rng.random((n, 3))
    return X, smooth(X)


@pytest.fixture(scope="module")
def fitted():
    """3 inputs x 2 MFs (8 rules), 300 training and 100 validation rows."""
    X, y = sample(400, 0)
    return ANFIS(n_mfs=2, epochs=300, **NAMES).fit(X[:300], y[:300], X[300:], y[300:])


# ---------------------------------------------------------------------------------------------


def random_model(rng, n_inputs, n_mfs, structure):
    """Random premise/consequent parameters with grid (shared MFs) or fcm (one MF per rule) structure."""
    if structure == "grid":
        mf_input = np.repeat(np.arange(n_inputs), n_mfs)
        rule_mf = np.array(list(itertools.product(range(n_mfs), repeat=n_inputs))) + n_mfs * np.arange(n_inputs)
    else:
        mf_input = np.repeat(np.arange(n_inputs), n_mfs)
        rule_mf = np.arange(n_mfs)[:, None] + n_mfs * np.arange(n_inputs)[None, :]
    centres = rng.uniform(-1, 2, mf_input.size)
    sigmas = rng.uniform(0.3, 1.5, mf_input.size)
    consequents = rng.normal(size=(rule_mf.shape[0], n_inputs + 1))
    return centres, sigmas, mf_input, rule_mf, consequents


@pytest.mark.parametrize("structure", ["grid", "fcm"])
def test_gradient_matches_central_differences(structure):
    worst = 0.0
    for seed, n_inputs, n_mfs in itertools.product(range(4), (2, 3), (2, 3)):
        rng = np.random.default_rng(seed)
        centres, sigmas, mf_input, rule_mf, consequents = random_model(rng, n_inputs, n_mfs, structure)
        X = rng.uniform(-1, 2, (50, n_inputs))
        y = np.sin(X.sum(axis=1)) + rng.normal(size=50)
        args = (mf_input, rule_mf, consequents)
        _, g_c, g_s = loss_and_gradient(X, y, centres, sigmas, *args)
        analytic = np.concatenate([g_c, g_s])
        params = np.concatenate([centres, sigmas])
        numeric = np.empty_like(params)
        M = centres.size
        for j in range(params.size):
            h = 1e-5 * max(1.0, abs(params[j]))
            up, down = params.copy(), params.copy()
            up[j] += h
            down[j] -= h
            e_up = loss_and_gradient(X, y, up[:M], up[M:], *args)[0]
            e_down = loss_and_gradient(X, y, down[:M], down[M:], *args)[0]
            numeric[j] = (e_up - e_down) / (2 * h)
        rel = np.linalg.norm(analytic - numeric) / np.linalg.norm(numeric)
        worst = max(worst, rel)
        assert rel < 1e-5, (seed, n_inputs, n_mfs, rel)
    print(f"{structure}: worst relative gradient error {worst:.2e}")


def test_fits_smooth_function_of_three_inputs(fitted):
    """Held-out mean relative error of `smooth` well under 1 % (8 rules, 300 epochs)."""
    X_test, y_test = sample(2000, 1)
    mre = np.mean(np.abs(fitted.predict(X_test) - y_test) / y_test)
    print(f"held-out mean relative error: {100 * mre:.3f} %")
    assert mre < 0.003
    assert fitted.score(X_test, y_test) > 0.999
    # premise learning does work: the error falls well below the initial (grid + LSE) one
    assert fitted.train_rmse_.min() < 0.3 * fitted.train_rmse_[0]


def unit_box_data(n, seed):
    """Inputs spanning exactly [0, 1] (so the internal scaling is the identity) and a smooth output."""
    rng = np.random.default_rng(seed)
    X = rng.random((n, 3))
    X[0], X[1] = 0.0, 1.0
    return X, 1 + np.sin(3 * X[:, 0]) + X[:, 1] ** 2 + 0.5 * X[:, 2]


def test_one_epoch_of_hybrid_learning():
    """Epoch 1: least squares for the consequents (checked against skfuzzy.gaussmf and numpy lstsq);
    then one normalised gradient step of length step_size on the premise."""
    X, y = unit_box_data(100, 13)
    one = ANFIS(epochs=1, step_size=0.01).fit(X, y)
    two = ANFIS(epochs=2, step_size=0.01).fit(X, y)
    assert two.best_epoch_ == 2
    c0, s0 = one.centres_, one.sigmas_
    # grid init: centres at the range ends, neighbours crossing at 0.5
    np.testing.assert_allclose(c0, [0, 1, 0, 1, 0, 1])
    np.testing.assert_allclose(gaussmf(np.array([0.5]), 0.0, s0[0]), 0.5)
    # consequents of epoch 1 from an independent forward pass
    w = np.ones((X.shape[0], one.n_rules_))
    for r, mfs in enumerate(one.rule_mf_):
        for i, m in enumerate(mfs):
            w[:, r] *= gaussmf(X[:, i], c0[m], s0[m])
    w /= w.sum(axis=1, keepdims=True)
    X1 = np.column_stack([X, np.ones(len(X))])
    A = (w[:, :, None] * X1[:, None, :]).reshape(len(X), -1)
    expected = np.linalg.lstsq(A, y, rcond=None)[0].reshape(one.n_rules_, -1)
    np.testing.assert_allclose(one.consequents_, expected, rtol=1e-6, atol=1e-9)
    # the premise step
    _, g_c, g_s = loss_and_gradient(X, y, c0, s0, one.mf_input_, one.rule_mf_, one.consequents_)
    norm = np.sqrt(g_c @ g_c + g_s @ g_s)
    np.testing.assert_allclose(two.centres_, c0 - 0.01 * g_c / norm, rtol=0, atol=1e-12)
    np.testing.assert_allclose(two.sigmas_, s0 - 0.01 * g_s / norm, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(np.r_[two.centres_ - c0, two.sigmas_ - s0]), 0.01, rtol=1e-9)


def test_sigma_floor():
    X, _ = unit_box_data(200, 14)
    y = np.where(X[:, 0] > 0.5, 1.0, 0.0) + 0.1 * X[:, 1]  # a step in x1 pulls its widths down
    free = ANFIS(epochs=300, step_size=0.05).fit(X, y)
    assert free.sigmas_[:2].max() < 0.15
    floored = ANFIS(epochs=300, step_size=0.05, min_sigma_frac=0.2).fit(X, y)
    assert floored.sigmas_.min() >= 0.2
    np.testing.assert_allclose(floored.sigmas_[:2], 0.2)


def test_step_size_rule():
    # four consecutive decreases: x1.1
    assert update_step_size([5, 4, 3, 2, 1], 0.01, 0) == pytest.approx((0.011, 4))
    # two alternations up-down-up-down: x0.9
    assert update_step_size([1, 2, 1, 2, 1], 0.01, 0) == pytest.approx((0.009, 4))
    # the opposite phase (down-up-down-up), a mixed pattern, too short a history: unchanged
    assert update_step_size([2, 1, 2, 1, 2], 0.01, 0) == (0.01, 0)
    assert update_step_size([5, 4, 3, 3, 2], 0.01, 0) == (0.01, 0)
    assert update_step_size([4, 3, 2, 1], 0.01, 0) == (0.01, 0)
    # the pattern must lie after the last change
    assert update_step_size([9, 8, 5, 4, 3, 2, 1], 0.01, 3) == (0.01, 3)
    assert update_step_size([9, 8, 5, 4, 3, 2, 1], 0.01, 2) == pytest.approx((0.011, 6))
    assert update_step_size([1, 2, 1, 2, 1], 0.01, 0, increase=1.5, decrease=0.5) == pytest.approx((0.005, 4))


def test_fit_applies_step_size_rule(fitted):
    step, last = fitted.step_size, 0
    for k in range(fitted.train_rmse_.size):
        assert fitted.step_sizes_[k] == pytest.approx(step, rel=1e-12)
        step, last = update_step_size(fitted.train_rmse_[: k + 1], step, last)
    assert len(set(np.round(fitted.step_sizes_, 15))) > 1  # the rule did act during this fit


def test_validation_snapshot_is_min_validation_epoch():
    """Noisy small training set: validation error has an interior minimum, the model is that epoch."""
    rng = np.random.default_rng(0)
    X = LO + (HI - LO) * rng.random((60, 3))
    y = smooth(X) + 0.1 * rng.standard_normal(60)
    X_val = LO + (HI - LO) * rng.random((60, 3))
    y_val = smooth(X_val)
    model = ANFIS(epochs=200, step_size=0.05).fit(X, y, X_val, y_val)
    assert model.val_rmse_.shape == model.train_rmse_.shape == (200,)
    best = model.best_epoch_
    assert best == np.argmin(model.val_rmse_) + 1
    assert 1 < best < 200
    val_rmse = np.sqrt(np.mean((model.predict(X_val) - y_val) ** 2))
    train_rmse = np.sqrt(np.mean((model.predict(X) - y) ** 2))
    assert val_rmse == pytest.approx(model.val_rmse_.min(), rel=1e-9)
    assert train_rmse == pytest.approx(model.train_rmse_[best - 1], rel=1e-9)
    assert val_rmse < model.val_rmse_[-1]


def test_without_validation_keeps_min_training_epoch():
    X, y = sample(200, 2)
    model = ANFIS(epochs=60).fit(X, y)
    assert model.val_rmse_.size == 0
    assert model.best_epoch_ == np.argmin(model.train_rmse_) + 1
    assert np.sqrt(np.mean((model.predict(X) - y) ** 2)) == pytest.approx(model.train_rmse_.min(), rel=1e-9)


def test_error_goal_stops_training():
    X, y = sample(200, 3)
    full = ANFIS(epochs=200).fit(X, y)
    goal = 0.5 * full.train_rmse_[0]
    model = ANFIS(epochs=200, error_goal=goal).fit(X, y)
    n = model.train_rmse_.size
    assert 1 < n < 200
    assert model.train_rmse_[-1] <= goal < model.train_rmse_[:-1].min()
    assert np.array_equal(model.train_rmse_, full.train_rmse_[:n])


def test_netcdf_round_trip_is_exact(fitted, tmp_path):
    ds = fitted.to_dataset()
    for name in list(ds.coords) + list(ds.data_vars):
        assert {"units", "long_name"} <= set(ds[name].attrs), name
    for value in ds.attrs.values():
        assert isinstance(value, (str, int, float, np.integer, np.floating))
    assert ds["mf_centre_2"].attrs["units"] == "N/m"
    assert ds["consequent_0"].attrs["units"] == "(N s/m)/(Hz)"
    path = tmp_path / "model.nc"
    ds.to_netcdf(path)
    with xr.open_dataset(path) as stored:
        loaded = ANFIS.from_dataset(stored.load())
    rng = np.random.default_rng(5)
    X = LO - 10 + (HI - LO + 20) * rng.random((500, 3))
    assert np.array_equal(fitted.predict(X), loaded.predict(X))
    assert loaded.get_params() == fitted.get_params()
    assert loaded.rules_text() == fitted.rules_text()
    assert loaded.best_epoch_ == fitted.best_epoch_
    for attr in (
        "centres_",
        "sigmas_",
        "initial_centres_",
        "consequents_",
        "rule_mf_",
        "train_rmse_",
        "val_rmse_",
    ):
        assert np.array_equal(getattr(loaded, attr), getattr(fitted, attr)), attr


def test_predictions_bounded_far_outside(fitted):
    X, y = sample(300, 0)
    edge = np.array([[HI[0], LO[1], HI[2]]])
    for far in ([1e6, -1e6, 1e9], [1e300, -1e300, 1e300], [HI[0] + 1, LO[1] - 1, 1e3 * HI[2]]):
        pred = fitted.predict(np.array([far]))
        assert np.isfinite(pred).all()
        assert pred[0] == fitted.predict(edge)[0]  # clamped to the training box
        assert y.min() - 0.5 <= pred[0] <= y.max() + 0.5
    for bad, word in ((np.nan, "NaN"), (np.inf, "infinity"), (-np.inf, "infinity")):
        with pytest.raises(ValueError, match=f"Input X contains {word}"):
            fitted.predict(np.array([[10.0, bad, 100.0]]))
    with pytest.raises(ValueError, match="X has 2 features, but ANFIS is expecting 3"):
        fitted.predict(np.ones((3, 2)))


def test_zero_firing_strength_guard():
    """Narrow MFs far from every sample: every product of memberships underflows to 0."""
    rng = np.random.default_rng(0)
    centres, sigmas, mf_input, rule_mf, consequents = random_model(rng, 3, 2, "grid")
    X = rng.uniform(100, 200, (20, 3))
    loss, g_c, g_s = loss_and_gradient(X, X.sum(axis=1), centres, 0.01 * sigmas, mf_input, rule_mf, consequents)
    assert np.isfinite(loss) and np.isfinite(g_c).all() and np.isfinite(g_s).all()


def test_constant_input_is_ignored_with_warning():
    X, y = sample(300, 4)
    X[:, 2] = 100.0
    y = smooth(X)
    with pytest.warns(UserWarning, match="'K' is constant"):
        model = ANFIS(epochs=50, **NAMES).fit(X, y)
    X_test, y_test = sample(200, 5)
    pred = model.predict(X_test)
    assert np.isfinite(pred).all()
    X_test[:, 2] = 100.0
    assert np.array_equal(pred, model.predict(X_test))  # K clamped to its only value
    assert np.mean(np.abs(pred - smooth(X_test)) / smooth(X_test)) < 0.01
    assert np.isfinite(model.sigmas_).all() and (model.sigmas_ > 0).all()


def test_duplicate_rows():
    X, y = sample(150, 6)
    once = ANFIS(epochs=40).fit(X, y)
    twice = ANFIS(epochs=40).fit(np.vstack([X, X]), np.concatenate([y, y]))
    X_test, _ = sample(100, 7)
    assert np.isfinite(twice.predict(X_test)).all()
    np.testing.assert_allclose(twice.predict(X_test), once.predict(X_test), rtol=1e-6)
    # one point repeated with conflicting outputs: every input constant, prediction is the mean
    X_same = np.tile([[10.0, 20.0, 300.0]], (30, 1))
    y_same = np.linspace(1.0, 2.0, 30)
    with pytest.warns(UserWarning, match="constant"):
        model = ANFIS(epochs=5).fit(X_same, y_same)
    np.testing.assert_allclose(model.predict(X_test), 1.5, rtol=1e-6)


def test_fcm_two_rules_three_inputs():
    """The paper's configuration: three inputs, two rules."""
    X, y = sample(400, 8)
    state = np.random.get_state()[1].copy()
    model = ANFIS(init="fcm", n_rules=2, epochs=200, random_state=3, **NAMES).fit(X[:300], y[:300], X[300:], y[300:])
    assert np.array_equal(np.random.get_state()[1], state)  # numpy's global generator untouched
    assert model.n_rules_ == 2 and model.rule_mf_.shape == (2, 3) and model.centres_.shape == (6,)
    X_test, y_test = sample(1000, 9)
    mre = np.mean(np.abs(model.predict(X_test) - y_test) / y_test)
    print(f"fcm, 2 rules: held-out mean relative error {100 * mre:.3f} %")
    assert mre < 0.015
    text = model.rules_text()
    assert text.count("\n") == 2 and "Rule 2: IF f_y is MF2" in text


def test_determinism():
    X, y = sample(200, 10)
    for params in (dict(init="grid"), dict(init="fcm", n_rules=3, random_state=7)):
        a = ANFIS(epochs=30, **params).fit(X, y)
        b = ANFIS(epochs=30, **params).fit(X, y)
        assert np.array_equal(a.predict(X), b.predict(X))
        assert np.array_equal(a.centres_, b.centres_) and np.array_equal(a.train_rmse_, b.train_rmse_)


def test_rules_text(fitted):
    text = fitted.rules_text()
    lines = text.splitlines()
    assert len(lines) == 1 + 8
    assert lines[1].startswith("Rule 1: IF f_y is MF1 (c = ")
    assert " Hz, sigma = " in lines[1] and " N/m)" in lines[1] and " AND K is MF1 " in lines[1]
    assert "THEN C = " in lines[1] and "*f_y " in lines[1] and "*K " in lines[1]
    c = fitted.membership_functions()[0][0][0]
    assert f"(c = {c:.4g} Hz" in lines[1]


def test_get_set_params_round_trip():
    model = ANFIS(n_mfs=[2, 3], epochs=7, step_size=0.02, **NAMES)
    params = model.get_params()
    assert params["n_mfs"] == [2, 3] and params["epochs"] == 7 and params["input_names"] == ["f_y", "f_z", "K"]
    clone = ANFIS(**params)
    assert clone.get_params() == params
    assert clone.set_params(epochs=9, init="fcm") is clone
    assert clone.epochs == 9 and clone.init == "fcm" and model.epochs == 7
    assert ANFIS().set_params(**params).get_params() == params
    with pytest.raises(ValueError, match="'epoch'"):
        ANFIS().set_params(epoch=3)
    ANFIS(epochs=-1, init="nope")  # stored as given, checked only in fit
    assert ANFIS(n_mfs="x").n_mfs == "x"


@pytest.mark.parametrize(
    "params, match",
    [
        (dict(n_mfs=0), "n_mfs"),
        (dict(n_mfs="2"), "n_mfs"),
        (dict(n_mfs=[2, 2]), "n_mfs"),
        (dict(n_mfs=20), "n_mfs"),
        (dict(init="kmeans"), "init"),
        (dict(init="fcm"), "n_rules"),
        (dict(init="fcm", n_rules=0), "n_rules"),
        (dict(init="subtractive", radius=0.0), "radius"),
        (dict(init="subtractive", radius=1.5), "radius"),
        (dict(validation_fraction=1.0), "validation_fraction"),
        (dict(validation_fraction=-0.1), "validation_fraction"),
        (dict(epochs=0), "epochs"),
        (dict(epochs=2.5), "epochs"),
        (dict(error_goal=-1.0), "error_goal"),
        (dict(step_size=0.0), "step_size"),
        (dict(step_size=np.nan), "step_size"),
        (dict(step_increase=0.9), "step_increase"),
        (dict(step_decrease=1.2), "step_decrease"),
        (dict(min_sigma_frac=0.0), "min_sigma_frac"),
        (dict(ridge=-1e-3), "ridge"),
        (dict(random_state=-1), "random_state"),
        (dict(random_state=True), "random_state"),
        (dict(input_names=["a", "b"]), "input_names"),
        (dict(input_names=["a", "a", "b"]), "input_names"),
        (dict(input_units="Hz"), "input_units"),
        (dict(output_name=""), "output_name"),
    ],
)
def test_bad_arguments_raise(params, match):
    X, y = sample(50, 11)
    with pytest.raises(ValueError, match=match):
        ANFIS(**{"epochs": 2, **params}).fit(X, y)


def test_bad_data_raise():
    X, y = sample(50, 12)
    model = ANFIS(epochs=2)
    X_nan = X.copy()
    X_nan[3, 1] = np.nan
    for args, match in [
        ((X_nan, y), "Input X contains NaN"),
        ((X, y[:-1]), r"inconsistent numbers of samples: \[50, 49\]"),
        ((X[:, 0], y), "Expected 2D array, got 1D array"),
        ((X, y, X), "X_val and y_val"),
        ((X, y, X[:, :2], y), "X has 2 features, but ANFIS is expecting 3"),
        ((X, y, X, y[:5]), r"inconsistent numbers of samples: \[50, 5\]"),
    ]:
        with pytest.raises(ValueError, match=match):
            model.fit(*args)
    with pytest.raises(NotFittedError, match="not fitted"):
        ANFIS().predict(X)
    assert not hasattr(ANFIS(), "n_rules_")


def test_any_number_of_inputs():
    rng = np.random.default_rng(15)
    x = rng.uniform(0, 6, (200, 1))
    one = ANFIS(n_mfs=5, epochs=100).fit(x, np.sin(x[:, 0]))
    assert one.n_rules_ == 5
    assert np.abs(one.predict(x) - np.sin(x[:, 0])).max() < 0.05
    X = rng.random((200, 4))
    y = X[:, 0] ** 2 + np.cos(X[:, 1]) + X[:, 2] * X[:, 3]
    four = ANFIS(n_mfs=[3, 1, 2, 1], epochs=50).fit(X, y)
    assert four.n_rules_ == 6 and four.centres_.shape == (7,)
    assert four.score(X, y) > 0.99
    again = ANFIS.from_dataset(four.to_dataset())
    assert np.array_equal(again.predict(X), four.predict(X))
    assert [c.size for c, _ in again.membership_functions()] == [3, 1, 2, 1]


# --------------------------------------------------------------------------------- scikit-learn


@pytest.mark.filterwarnings("ignore")  # the checks feed constant and 1-sample inputs on purpose
@pytest.mark.parametrize(
    "estimator",
    [ANFIS(init="subtractive", epochs=20), ANFIS(init="fcm", n_rules=3, epochs=20, validation_fraction=0.2)],
    ids=["subtractive", "fcm-validation"],
)
def test_check_estimator(estimator):
    """scikit-learn's own estimator checks (a grid init on their 10-feature data is 1024 rules: slow, so the
    clustering inits run here; the grid init is exercised by every other test)."""
    # on_skip=None: the one skipped check is the array-API one, which needs SCIPY_ARRAY_API set
    check_estimator(estimator, expected_failed_checks=EXPECTED_FAILED_CHECKS, on_skip=None)


def test_clone_pipeline_cross_val_score():
    X, y = sample(150, 20)
    model = ANFIS(epochs=30, n_mfs=[2, 3, 2], **NAMES)
    copy = clone(model)
    assert copy.get_params() == model.get_params() and not hasattr(copy, "consequents_")
    scores = cross_val_score(make_pipeline(StandardScaler(), model), X, y, cv=KFold(3, shuffle=True, random_state=0))
    assert scores.shape == (3,) and np.all(scores > 0.9)


def test_grid_search_over_structure_round_trips(tmp_path):
    """GridSearchCV over n_mfs and the initialisation returns a fitted best estimator; its NetCDF copy
    predicts identically."""
    X, y = sample(200, 21)
    grid = [
        {"init": ["grid"], "n_mfs": [1, 2]},
        {"init": ["subtractive"], "radius": [0.5]},
        {"init": ["fcm"], "n_rules": [3]},
    ]
    search = GridSearchCV(ANFIS(epochs=40, **NAMES), grid, cv=KFold(3, shuffle=True, random_state=0)).fit(X, y)
    assert len(search.cv_results_["params"]) == 4
    best = search.best_estimator_
    assert best.get_params()["init"] == search.best_params_["init"] and hasattr(best, "consequents_")
    # one MF per input is a single linear rule: the smooth target needs more, so it does not win
    assert search.best_params_ != {"init": "grid", "n_mfs": 1}
    path = tmp_path / "best.nc"
    best.to_dataset().to_netcdf(path)
    with xr.open_dataset(path) as stored:
        loaded = ANFIS.from_dataset(stored.load())
    X_test, _ = sample(300, 22)
    assert np.array_equal(loaded.predict(X_test), best.predict(X_test))


def test_validation_fraction_holds_out_seeded_rows():
    """validation_fraction: the rows carved out are not trained on, and the kept epoch is their minimum."""
    X, y = sample(100, 23)
    model = ANFIS(epochs=60, validation_fraction=0.25, random_state=4).fit(X, y)
    val = np.zeros(100, dtype=bool)
    val[np.random.default_rng(4).permutation(100)[:25]] = True
    assert model.val_rmse_.size == 60 and model.best_epoch_ == np.argmin(model.val_rmse_) + 1
    rmse = np.sqrt(np.mean((model.predict(X[val]) - y[val]) ** 2))
    assert rmse == pytest.approx(model.val_rmse_.min(), rel=1e-9)
    explicit = ANFIS(epochs=60).fit(X[~val], y[~val], X[val], y[val])
    assert np.array_equal(explicit.predict(X), model.predict(X))


# --------------------------------------------------------------------------------- numerics


def test_shifted_target_fits_as_well():
    """1e12 + f(x) fits as well as f(x): the output is centred and scaled inside fit."""
    X, y = sample(300, 24)
    plain = ANFIS(epochs=100).fit(X, y)
    shifted = ANFIS(epochs=100).fit(X, 1e12 + y)
    # 1e12 has an ulp of 1.2e-4: that is the precision left for f(x) in the shifted data itself
    assert abs(shifted.train_rmse_.min() - plain.train_rmse_.min()) < 1e-3
    X_test, _ = sample(200, 25)
    np.testing.assert_allclose(shifted.predict(X_test) - 1e12, plain.predict(X_test), rtol=0, atol=2e-3)


def test_huge_targets_are_scaled_and_unrepresentable_refused():
    X, y = sample(200, 26)
    plain = ANFIS(epochs=60).fit(X, y)
    huge = ANFIS(epochs=60).fit(X, 1e130 * y)
    assert not np.array_equal(huge.centres_, huge.initial_centres_)  # the premise did move
    np.testing.assert_allclose(huge.centres_, plain.centres_, rtol=1e-7)
    np.testing.assert_allclose(huge.predict(X) / 1e130, plain.predict(X), rtol=1e-7)
    y_wide = np.zeros(200)
    y_wide[:2] = 1e308, -1e308  # each finite, their difference is not
    with pytest.raises(ValueError, match="range is not a finite float64"):
        ANFIS(epochs=2).fit(X, y_wide)


def test_complex_and_sparse_input_refused():
    X, y = sample(50, 27)
    with pytest.raises(ValueError, match="Complex data not supported"):
        ANFIS(epochs=2).fit(X + 1j, y)
    with pytest.raises(TypeError, match="Sparse data was passed"):
        ANFIS(epochs=2).fit(sparse.csr_matrix(X), y)


# --------------------------------------------------------------------------------- subtractive clustering


def test_subtractive_clustering_finds_known_centres():
    """Three tight blobs of equal size in the unit square: three centres, one on each blob."""
    rng = np.random.default_rng(28)
    truth = np.array([[0.2, 0.2], [0.8, 0.3], [0.5, 0.85]])
    points = np.vstack([c + 0.01 * rng.standard_normal((40, 2)) for c in truth])
    centres = anfis_init.subtractive_centres(points, radius=0.5)
    assert centres.shape == (3, 2)
    nearest = np.linalg.norm(centres[:, None, :] - truth[None, :, :], axis=2)
    assert sorted(np.argmin(nearest, axis=1)) == [0, 1, 2]
    assert nearest.min(axis=1).max() < 0.03


@pytest.mark.parametrize("distance, expected", [(0.3, 1), (0.45, 2), (0.9, 2)])
def test_subtractive_gray_zone_rule(distance, expected):
    """Chiu's accept/reject rule, closed form for two stacks of identical points (20 at a, 8 at b):
    P_a = 20 + 8 e, P_b = 8 + 20 e with e = exp(-4 D^2 / r^2); after a, P_b' = P_b - P_a exp(-4 D^2 / (1.25 r)^2).
    b is accepted if P_b' / P_a > 0.5, refused if < 0.15, else accepted iff D / r + P_b' / P_a >= 1."""
    r = 0.5
    points = np.vstack([np.zeros((20, 2)), np.tile([distance, 0.0], (8, 1))])
    e = np.exp(-4 * distance**2 / r**2)
    ratio = (8 + 20 * e - (20 + 8 * e) * np.exp(-4 * distance**2 / (1.25 * r) ** 2)) / (20 + 8 * e)
    accept = ratio > 0.5 or (ratio >= 0.15 and distance / r + ratio >= 1)
    assert (2 if accept else 1) == expected  # the closed form agrees with the case's label
    assert len(anfis_init.subtractive_centres(points, r)) == expected


def test_subtractive_init_sigmas_and_rule_count():
    X, y = sample(300, 29)
    model = ANFIS(init="subtractive", radius=0.5, epochs=1, **NAMES).fit(X, y)
    points = np.column_stack([(X - X.min(axis=0)) / np.ptp(X, axis=0), (y - y.min()) / np.ptp(y)])
    assert model.n_rules_ == len(anfis_init.subtractive_centres(points, 0.5))
    # genfis2: sigma = radius * range / sqrt(8) for every MF of an input
    for (_, sigmas), span in zip(model.membership_functions(initial=True), np.ptp(X, axis=0), strict=True):
        np.testing.assert_allclose(sigmas, 0.5 * span / np.sqrt(8))


# ----------------------------------------------------------------------------------------------------
# The ANFIS learning rule's linear algebra and step-size rule against independent computations.


def _problem(n: int, n_rules: int, seed: int = 4):
    rng = np.random.default_rng(seed)
    X = rng.uniform(-1, 1, (n, 2))
    w = rng.uniform(0.1, 1.0, (n_rules, n))
    w /= w.sum(axis=0)
    X1T = anfis_math._with_ones_row(X)
    A = (w[:, None, :] * X1T[None, :, :]).reshape(-1, n).T  # (n, rules * 3)
    y = rng.normal(size=n)
    return w, X1T, A, y


@pytest.mark.parametrize("n", [40, 6])  # more rows than unknowns, and exactly as many (2 rules x 3)
def test_ridge_consequents_are_the_regularised_normal_equations(n):
    w, X1T, A, y = _problem(n, 2)
    ridge = 0.3
    gram = A.T @ A
    expected = scipy.linalg.solve(gram + ridge * np.trace(gram) / gram.shape[0] * np.eye(gram.shape[0]), A.T @ y)
    got = anfis_math._solve_consequents(w, X1T, y, ridge)
    assert got.shape == (2, 3)
    np.testing.assert_allclose(got.ravel(), expected, rtol=1e-9, atol=1e-12)


def test_more_unknowns_than_rows_takes_the_minimum_norm_solution_ignoring_ridge():
    w, X1T, A, y = _problem(5, 3)  # 9 unknowns, 5 rows
    expected = scipy.linalg.pinv(A, rtol=1e-10) @ y
    got = anfis_math._solve_consequents(w, X1T, y, 0.5)
    np.testing.assert_allclose(got.ravel(), expected, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("gap", [1e-6, 1e-12])
def test_an_ill_conditioned_problem_takes_the_truncated_svd_solution(gap):
    """Two rules firing alike up to `gap`: cond(A) ~ 1 / gap. At 1e-6 the Cholesky of A^T A (cond 1e12) succeeds
    but loses 6 digits, so the SVD path is taken (its answer: QR least squares to cond eps = 1e-10 of the
    largest); at 1e-12 the singular values below 1e-10 of the largest are dropped (pinv(A, rtol=1e-10) y),
    not inverted."""
    w, X1T, A, y = _problem(40, 2)
    w[1] = w[0] + gap * np.random.default_rng(1).uniform(0, 1, 40)
    A = (w[:, None, :] * X1T[None, :, :]).reshape(-1, 40).T
    got = anfis_math._solve_consequents(w, X1T, y, 0.0).ravel()
    if gap > 1e-9:
        expected = scipy.linalg.lstsq(A, y, lapack_driver="gelsy")[0]
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-7 * np.abs(expected).max())
    else:
        expected = scipy.linalg.pinv(A, rtol=1e-10) @ y
        np.testing.assert_allclose(got, expected, rtol=1e-6, atol=1e-9)


@pytest.mark.parametrize(
    ("errors", "expected_step", "expected_change"),
    [
        ([1.0, 0.9, 0.8, 0.7, 0.6], 1.1, 4),  # four decreases: x 1.1
        ([1.0, 1.2, 1.1, 1.3, 1.2], 0.9, 4),  # up, down, up, down: x 0.9
        ([1.0, 1.0, 0.5, 0.8, 0.4], 1.0, 0),  # a tie is not an increase: no change
        ([1.0, 0.9, 0.8, 0.85, 0.7], 1.0, 0),  # only the second half alternates
        ([1.0, 1.1, 1.2, 1.3, 1.4], 1.0, 0),  # four increases
        ([1.0, 1.2, 1.1, 1.3], 1.0, 0),  # fewer than five errors since the last change
    ],
)
def test_step_size_rule_cases(errors, expected_step, expected_change):
    step, change = anfis_math.update_step_size(errors, 1.0, 0)
    assert step == pytest.approx(expected_step, rel=1e-15) and change == expected_change


def test_step_size_rule_counts_from_the_last_change():
    errors = [1.0, 0.9, 0.8, 0.7, 0.6, 0.5, 0.4]
    assert anfis_math.update_step_size(errors, 2.0, 4) == (2.0, 4)  # 2 errors since index 4
    step, change = anfis_math.update_step_size(errors, 2.0, 2)
    assert step == pytest.approx(2.2, rel=1e-15) and change == 6


def test_a_fit_beyond_the_memory_limit_is_refused_with_its_estimate():
    """Grid init, 2 MFs on 3 inputs: R = 8 rules, R (d + 1) = 32 coefficients; on 1000 rows the regressor and its copy
    are 2 x 8 B x 1000 x 32 = 512,000 B, the Gram matrix 8 B x 32^2 = 8,192 B: 0.000520 GB, refused under 0.0005 GB
    and fitted at 0.00053 GB."""
    rng = np.random.default_rng(3)
    X = rng.uniform(0.0, 1.0, (1000, 3))
    y = X.sum(axis=1)
    expected_gb = (2 * 8 * 1000 * 32 + 8 * 32**2) / 1e9
    with pytest.raises(ValueError, match=rf"need about {expected_gb:.3g} GB \(1000 rows x 8 rules x 4 coefficients\)"):
        ANFIS(n_mfs=2, epochs=1, max_memory_gb=0.0005).fit(X, y)
    ANFIS(n_mfs=2, epochs=1, max_memory_gb=0.00053).fit(X, y)
    with pytest.raises(ValueError, match="max_memory_gb must be a finite number > 0"):
        ANFIS(max_memory_gb=0.0).fit(X, y)


def test_the_red_teams_subtractive_fit_on_5_x_1e6_inputs_is_refused_not_crashed():
    """5 rows of 1,000,000 inputs (it segfaulted in numpy.linalg.lstsq): 5 rules x 1,000,001 coefficients, a Gram
    matrix of 8 B x (5,000,005)^2 = 2.0e5 GB alone."""
    X = np.random.default_rng(0).uniform(size=(5, 1_000_000))
    with pytest.raises(ValueError, match=r"need about 2e\+05 GB \(5 rows x 5 rules x 1000001 coefficients\)"):
        ANFIS(init="subtractive", epochs=1).fit(X, np.arange(5.0))
