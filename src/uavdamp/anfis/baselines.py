"""Baseline regressors of the reference table, to judge the ANFIS against (all scikit-learn estimators).

* ``linear``: piecewise-linear interpolation of the training cells (scipy LinearNDInterpolator on a
  Delaunay triangulation of the inputs scaled to [0, 1]); outside the training cells' convex hull
  the nearest training cell's value (NearestNDInterpolator). A regular-grid interpolator cannot
  be used: the training cells are a random 80 % of the grid, not a grid.
* ``gp``: Gaussian-process regression, kernel constant * anisotropic RBF + white noise, the
  hyper-parameters by maximum marginal likelihood, on standardised inputs and a normalised output.
* ``knn``: k nearest neighbours (k = 5, inverse-distance weights) on standardised inputs.
* ``hgb``: histogram gradient boosting (scikit-learn defaults, but leaves of at least 5 samples: the
  training set has a few hundred rows).

Settings are choices, not tuned; ``make`` builds them, seeded where they are random.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.ensemble import HistGradientBoostingRegressor
from sklearn.gaussian_process import GaussianProcessRegressor
from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel
from sklearn.neighbors import KNeighborsRegressor
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.utils.validation import check_is_fitted, validate_data

from uavdamp.anfis.params import BASELINES

# rough fit cost on the default table in the units of model_selection.cost (rules of an ANFIS, ~0.015 s each),
# to start the costliest fits first: the exact GP takes a minute
COSTS = {"linear": 12.0, "gp": 4000.0, "knn": 1.0, "hgb": 10.0}
LONG_NAMES = {
    "anfis": "ANFIS (cross-validated structure)",
    "linear": "linear interpolation of the training cells, nearest cell outside their hull",
    "gp": "Gaussian-process regression (RBF + white noise)",
    "knn": "5 nearest neighbours, inverse-distance weights",
    "hgb": "histogram gradient boosting",
}


class LinearInterpolation(RegressorMixin, BaseEstimator):
    """Piecewise-linear interpolation of scattered training points, nearest point outside their hull.

    Inputs are scaled to [0, 1] by their training range before the Delaunay triangulation, so that
    inputs in different units weigh alike (a constant input is left unscaled).
    """

    def fit(self, X, y):
        from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator

        X, y = validate_data(self, X, y, y_numeric=True, dtype=np.float64)
        self.lo_ = X.min(axis=0)
        span = X.max(axis=0) - self.lo_
        self.scale_ = np.where(span > 0, span, 1.0)
        Xs = (X - self.lo_) / self.scale_
        varying = span > 0
        self.varying_ = varying
        self.nearest_ = NearestNDInterpolator(Xs, y)
        if varying.sum() >= 2 and len(y) > varying.sum():
            self.linear_ = LinearNDInterpolator(Xs[:, varying], y)
        else:  # too few points or inputs to triangulate: nearest neighbour only
            self.linear_ = None
        return self

    def predict(self, X):
        check_is_fitted(self)
        X = validate_data(self, X, reset=False, dtype=np.float64)
        Xs = (X - self.lo_) / self.scale_
        out = np.full(len(X), np.nan) if self.linear_ is None else self.linear_(Xs[:, self.varying_])
        outside = ~np.isfinite(out)
        out[outside] = self.nearest_(Xs[outside])
        return out


def make(name: str, n_features: int, seed: int) -> BaseEstimator:
    """An unfitted baseline by name (one of BASELINES)."""
    if name == "linear":
        return LinearInterpolation()
    if name == "gp":
        kernel = ConstantKernel(1.0, (1e-3, 1e3)) * RBF(np.ones(n_features), (1e-2, 1e3)) + WhiteKernel(
            1e-3, (1e-8, 1.0)
        )
        return make_pipeline(StandardScaler(), GaussianProcessRegressor(kernel, normalize_y=True, random_state=seed))
    if name == "knn":
        return make_pipeline(StandardScaler(), KNeighborsRegressor(n_neighbors=5, weights="distance"))
    if name == "hgb":
        return HistGradientBoostingRegressor(min_samples_leaf=5, random_state=seed)
    raise ValueError(f"anfis.baselines: unknown baseline {name!r}; choose from {', '.join(BASELINES)}")
