"""Choosing the ANFIS structure by k-fold cross-validation (seeded KFold), the accuracy-size trade on purpose.

A candidate is a small dict of ANFIS structure parameters, e.g. ``{"init": "grid", "n_mfs": 3}``,
``{"init": "fcm", "n_rules": 4}`` or ``{"init": "subtractive", "radius": 0.5}``; every other
parameter comes from the estimator passed in. The caller passes the training rows only: whatever
is held out for checking never reaches this module.

Every (candidate, fold) fit is independent: `uavdamp.parallel.run` spreads them (and any other task of the caller's,
such as the baselines) over joblib's loky workers with one BLAS/OpenMP thread each, and in-process
with one BLAS thread when ``n_jobs`` is 1, so the numbers do not depend on the thread count.

``choose``: with rule ``best`` the lowest mean fold RMSE; with ``one_se`` (Breiman et al. 1984, Hastie et al.
2009 sec. 7.10) the candidate with the fewest rules whose mean RMSE is at most the lowest mean plus that
candidate's standard error (sample std over folds / sqrt(folds)); ties: the lower mean RMSE, then the earlier.
"""

from __future__ import annotations

import json
import time

import numpy as np
import xarray as xr
from sklearn.base import BaseEstimator, clone
from sklearn.model_selection import KFold

RULES = ("one_se", "best")


def label(candidate: dict) -> str:
    """Short text of a candidate, e.g. 'grid n_mfs=3'."""
    rest = " ".join(f"{k}={v}" for k, v in candidate.items() if k != "init")
    return f"{candidate['init']} {rest}".strip()


def cost(candidate: dict, n_inputs: int) -> float:
    """A rough size of a candidate's fit (its expected rules), to order the work; subtractive: ~2 / radius^d."""
    if candidate["init"] == "grid":
        return float(candidate["n_mfs"]) ** n_inputs
    if candidate["init"] == "fcm":
        return float(candidate["n_rules"])
    return 2.0 / float(candidate["radius"]) ** n_inputs


def splits(n: int, folds: int, seed: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """(fit rows, held-out rows) of each fold: ``KFold(folds, shuffle=True, random_state=seed)``."""
    if not (isinstance(folds, int) and 2 <= folds <= n):
        raise ValueError(f"anfis.selection.folds: must be an int between 2 and the {n} training rows, got {folds}")
    return list(KFold(folds, shuffle=True, random_state=seed).split(np.zeros((n, 1))))


def fit_fold(estimator: BaseEstimator, params: dict, X, y, fit_rows, test_rows) -> tuple[np.ndarray, int, float]:
    """(predictions on the held-out rows, rules, fit seconds) of the estimator with ``params`` fitted on fit_rows."""
    model = clone(estimator).set_params(**params)
    start = time.perf_counter()
    model.fit(X[fit_rows], y[fit_rows])
    seconds = time.perf_counter() - start
    return model.predict(X[test_rows]), int(model.n_rules_), seconds


def fold_tasks(estimator, X, y, candidates: list[dict], folds: list) -> list:
    """One ``fit_fold`` task per (candidate, fold), candidate-major."""
    return [(fit_fold, (estimator, c, X, y, fit, test)) for c in candidates for fit, test in folds]


def choose(mean: np.ndarray, se: np.ndarray, n_rules: np.ndarray, rule: str) -> int:
    """Index of the chosen candidate from mean fold RMSE, its standard error and rules (see module doc)."""
    if rule not in RULES:
        raise ValueError(f"anfis.selection.rule: must be one of {list(RULES)}, got {rule!r}")
    best = int(np.argmin(mean))
    if rule == "best":
        return best
    within = np.flatnonzero(mean <= mean[best] + se[best])
    return int(min(within, key=lambda j: (n_rules[j], mean[j], j)))


def _variables(rmse, se, n_rules, units: str, name: str) -> dict:
    folds = rmse.shape[1]
    return {
        "cv_rmse": (("candidate", "fold"), rmse, {"units": units, "long_name": f"cross-validated RMSE of {name}"}),
        "cv_rmse_mean": (
            "candidate",
            rmse.mean(axis=1),
            {"units": units, "long_name": f"mean over folds of the RMSE of {name}"},
        ),
        "cv_rmse_std": (
            "candidate",
            rmse.std(axis=1, ddof=1),
            {"units": units, "long_name": "sample standard deviation over folds of cv_rmse"},
        ),
        "cv_rmse_se": (
            "candidate",
            se,
            {"units": units, "long_name": f"standard error of cv_rmse_mean: cv_rmse_std / sqrt({folds})"},
        ),
        "cv_n_rules": (("candidate", "fold"), n_rules, {"units": "1", "long_name": "rules of each fold's model"}),
    }


def summarise(
    candidates: list[dict], results: list, n_folds: int, rule: str, units: str = "1", name: str = "y"
) -> tuple[int, xr.Dataset, np.ndarray]:
    """(chosen index, CV record, mean fit seconds per candidate) from the ``fit_fold`` results and fold RMSEs.

    ``results``: per candidate, per fold, (rmse, rules, seconds). The record has ``cv_rmse`` (candidate, fold),
    its mean, sample std and standard error, ``cv_n_rules`` and the candidates' mean rule count ``n_rules``.
    """
    table = np.array(results, dtype=float).reshape(len(candidates), n_folds, 3)
    rmse, n_rules = table[..., 0], table[..., 1].astype(int)
    se = rmse.std(axis=1, ddof=1) / np.sqrt(n_folds)
    mean_rules = n_rules.mean(axis=1)
    chosen = choose(rmse.mean(axis=1), se, mean_rules, rule)
    best = int(np.argmin(rmse.mean(axis=1)))
    record = xr.Dataset(
        _variables(rmse, se, n_rules, units, name),
        coords={
            "candidate": ("candidate", np.arange(1, len(candidates) + 1), {"units": "1", "long_name": "candidate"}),
            "candidate_label": (
                "candidate",
                np.array([label(c) for c in candidates], dtype=object),
                {"units": "1", "long_name": "ANFIS structure of the candidate"},
            ),
            "n_rules": ("candidate", mean_rules, {"units": "1", "long_name": "rules (mean over the folds' models)"}),
            "fold": ("fold", np.arange(1, n_folds + 1), {"units": "1", "long_name": "cross-validation fold"}),
        },
        attrs={
            "selection_rule": rule,
            "selected_candidate": label(candidates[chosen]),
            "selected_params": json.dumps(candidates[chosen]),
            "best_cv_candidate": label(candidates[best]),
            "one_se_threshold": float(rmse.mean(axis=1)[best] + se[best]),
            "cv_folds": n_folds,
        },
    )
    return chosen, record, table[..., 2].mean(axis=1)
