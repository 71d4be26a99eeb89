"""Tests of the scikit-learn-free predictor (uavdamp.anfis.predictor): the same bits as the estimator path of the
DampingModel it was saved from, the model evaluated independently from the dataset's variables, and the refusals.
That the law-running jobs import no scikit-learn: tests/test_architecture.py."""

import math

import numpy as np
import pytest
from conftest import anfis_options

from uavdamp.anfis import DampingModel, DampingPredictor

LO, HI = np.array([5.0, 5.0, 10.0]), np.array([30.0, 30.0, 1000.0])  # f_y, f_z [Hz], K [N/m]


def sample(n, seed, lo=LO, hi=HI):
    """n rows [f_y, f_z, K]: f_y, f_z uniform in [lo, hi] Hz, K log-uniform in [lo, hi] N/m."""
    u = np.random.default_rng(seed).random((n, 3))
    X = lo + (hi - lo) * u
    X[:, 2] = lo[2] * (hi[2] / lo[2]) ** u[:, 2]
    return X


def damping(X):
    """Test function: C [N s/m] = 10^(1 + 0.3 sin(f_y / 5) + 0.2 (f_z / 20)^2 - 0.25 log10(K / 1 N/m))."""
    return 10 ** (1 + 0.3 * np.sin(X[:, 0] / 5) + 0.2 * (X[:, 1] / 20) ** 2 - 0.25 * np.log10(X[:, 2]))


CASES = {
    "grid, log K and C": ({"init": "grid", "n_mfs": 2}, True, True),
    "subtractive, log K and C": ({"init": "subtractive", "radius": 0.6}, True, True),
    "grid, K and C": ({"init": "grid", "n_mfs": 2}, False, False),
}


@pytest.fixture(scope="module", params=list(CASES))
def saved(request):
    """(the fitted DampingModel, its dataset): grid init (MFs shared by rules) or subtractive clustering (every rule
    its own MFs), K and C learnt as log10 values or as they are."""
    structure, log_k, log_c = CASES[request.param]
    model = DampingModel.unfitted(anfis_options(epochs=10, seed=0, log_stiffness=log_k, log_damping=log_c))
    model.estimator.set_params(**structure)
    train = sample(150, 0)
    model.fit(train, damping(train))
    return model, model.to_dataset()


def independent(ds, X):
    """The saved model evaluated from the dataset's variables alone, row by row: each learnt input clamped to its
    range, Gaussian MFs multiplied over the inputs, the first-order consequents weighted by the firing strengths."""
    d = ds.sizes["input"]
    log_k, log_c = bool(ds.attrs["log_stiffness"]), bool(ds.attrs["log_damping"])
    out = []
    for row in X:
        x = [row[0], row[1], math.log10(row[2]) if log_k else row[2]]
        x = [min(max(v, float(ds[f"input_range_{i}"][0])), float(ds[f"input_range_{i}"][1])) for i, v in enumerate(x)]
        num = den = 0.0
        for r in range(ds.sizes["rule"]):
            w = 1.0
            for i in range(d):
                k = int(ds.rule_mf.values[r, i]) - 1
                c, s = float(ds[f"mf_centre_{i}"][k]), float(ds[f"mf_sigma_{i}"][k])
                w *= math.exp(-((x[i] - c) ** 2) / (2 * s * s))
            f = sum(float(ds[f"consequent_{i}"][r]) * x[i] for i in range(d)) + float(ds.consequent_constant[r])
            num, den = num + w * f, den + w
        out.append(10 ** (num / den) if log_c else num / den)
    return np.array(out)


def test_the_predictor_gives_the_models_bits_inside_and_outside_the_ranges(saved):
    """Bit for bit the DampingModel's predictions (the estimator path), read back from the same dataset, at rows
    inside the training box and far outside it (where both clamp)."""
    model, ds = saved
    X = np.vstack([sample(200, 1), sample(50, 2, lo=np.array([0.5, 0.5, 1.0]), hi=np.array([80.0, 80.0, 1e5]))])
    expected = DampingModel.from_dataset(ds).predict(X)
    np.testing.assert_array_equal(DampingPredictor.from_dataset(ds).predict(X), expected)
    np.testing.assert_array_equal(model.predict(X), expected)


def test_the_predictor_evaluates_the_saved_rules(saved):
    """Against the rules evaluated independently from the dataset (rounding only: positive weights, a sum of a few
    terms of one sign per rule)."""
    _, ds = saved
    X = np.vstack([sample(40, 3), [[1.0, 60.0, 5e4]]])
    np.testing.assert_allclose(DampingPredictor.from_dataset(ds).predict(X), independent(ds, X), rtol=1e-12)


def test_one_row_as_a_law_asks_for_it(saved):
    """A law's call, predict([[f_y, f_z, K]]): one value, bit for bit the DampingModel's for the same call, and the
    row's value inside a batch to rounding (BLAS sums a one-column product in another order)."""
    _, ds = saved
    predictor, X = DampingPredictor.from_dataset(ds), sample(5, 4)
    single = predictor.predict([list(X[2])])
    assert single.shape == (1,)
    assert single[0] == DampingModel.from_dataset(ds).predict([list(X[2])])[0]
    assert single[0] == pytest.approx(predictor.predict(X)[2], rel=1e-13)


@pytest.mark.parametrize(
    ("X", "message"),
    [
        ([[10.0, 12.0]], "rows of 3 inputs"),
        ([[10.0, 12.0, 100.0, 1.0]], "rows of 3 inputs"),
        ([[math.nan, 12.0, 100.0]], "finite"),
        ([[10.0, math.inf, 100.0]], "finite"),
    ],
)
def test_bad_rows_are_refused(saved, X, message):
    _, ds = saved
    with pytest.raises(ValueError, match=message):
        DampingPredictor.from_dataset(ds).predict(X)


def test_k_at_or_below_zero_is_refused_where_k_is_learnt_as_its_log():
    model = DampingModel.unfitted(anfis_options(epochs=3, seed=0, log_stiffness=True, log_damping=False))
    model.estimator.set_params(init="grid", n_mfs=2)
    train = sample(60, 5)
    ds = model.fit(train, damping(train)).to_dataset()
    with np.errstate(divide="ignore", invalid="ignore"), pytest.raises(ValueError, match="K > 0"):
        DampingPredictor.from_dataset(ds).predict([[10.0, 12.0, 0.0]])
