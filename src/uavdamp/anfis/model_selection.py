"""Choosing the ANFIS structure by k-fold cross-validation (scikit-learn GridSearchCV, seeded KFold).

A candidate is a small dict of ANFIS structure parameters, e.g. ``{"init": "grid", "n_mfs": 3}``,
``{"init": "fcm", "n_rules": 4}`` or ``{"init": "subtractive", "radius": 0.5}``; every other
parameter comes from the estimator passed in. The caller passes the training rows only: whatever
is held out for checking never reaches this module.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr
from sklearn.base import BaseEstimator
from sklearn.model_selection import GridSearchCV, KFold


def label(candidate: dict) -> str:
    """Short text of a candidate, e.g. 'grid n_mfs=3'."""
    rest = " ".join(f"{k}={v}" for k, v in candidate.items() if k != "init")
    return f"{candidate['init']} {rest}".strip()


def cross_validate(
    estimator: BaseEstimator, X: np.ndarray, y: np.ndarray, candidates: list[dict], folds: int, seed: int
) -> tuple[dict, xr.Dataset, np.ndarray]:
    """k-fold CV RMSE of every candidate on (X, y); returns the best candidate, the record, fit times.

    Folds: ``KFold(folds, shuffle=True, random_state=seed)``, the same for every candidate. The
    best candidate has the lowest mean fold RMSE (ties: the earlier candidate). The record has
    ``cv_rmse`` (candidate, fold) and its mean and standard deviation, in the units of y; the
    mean fit time per candidate (s) is returned apart, as it differs between runs.
    """
    if not (isinstance(folds, int) and 2 <= folds <= len(y)):
        raise ValueError(f"anfis.selection.folds: must be an int between 2 and the {len(y)} training rows, got {folds}")
    grid = [{k: [v] for k, v in c.items()} for c in candidates]
    search = GridSearchCV(
        estimator,
        grid,
        scoring="neg_root_mean_squared_error",
        cv=KFold(folds, shuffle=True, random_state=seed),
        refit=False,
        error_score="raise",
    )
    search.fit(X, y)
    res = search.cv_results_
    # GridSearchCV orders the results by its own parameter grid: map them back to our candidates
    order = [next(j for j, p in enumerate(res["params"]) if p == c) for c in candidates]
    rmse = -np.array([[res[f"split{f}_test_score"][j] for f in range(folds)] for j in order])
    mean = rmse.mean(axis=1)
    best = int(np.argmin(mean))
    units = getattr(estimator, "output_units", "1")
    name = getattr(estimator, "output_name", "y")
    record = xr.Dataset(
        {
            "cv_rmse": (("candidate", "fold"), rmse, {"units": units, "long_name": f"cross-validated RMSE of {name}"}),
            "cv_rmse_mean": (
                "candidate",
                mean,
                {"units": units, "long_name": f"mean over folds of the RMSE of {name}"},
            ),
            "cv_rmse_std": (
                "candidate",
                rmse.std(axis=1),
                {"units": units, "long_name": f"standard deviation over folds of the RMSE of {name}"},
            ),
        },
        coords={
            "candidate": (
                "candidate",
                np.arange(1, len(candidates) + 1),
                {"units": "1", "long_name": "candidate number"},
            ),
            "candidate_label": (
                "candidate",
                np.array([label(c) for c in candidates], dtype=object),
                {"units": "1", "long_name": "ANFIS structure of the candidate"},
            ),
            "fold": ("fold", np.arange(1, folds + 1), {"units": "1", "long_name": "cross-validation fold"}),
        },
        attrs={
            "selected_candidate": label(candidates[best]),
            "selected_params": json.dumps(candidates[best]),
            "cv_folds": folds,
        },
    )
    return candidates[best], record, np.asarray(res["mean_fit_time"])[order]
