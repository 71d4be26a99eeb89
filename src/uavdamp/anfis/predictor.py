"""A trained damping model's predictions on numpy alone: what a damping law asks of it while a run steps.

``DampingPredictor.from_dataset(ds)`` reads what ``DampingModel.to_dataset`` wrote and gives C (N s/m) for rows
[f_y Hz, f_z Hz, K N/m] with the arithmetic of ``DampingModel.predict`` (the same bits:
tests/test_anfis_predictor.py), without importing scikit-learn. Each Snakemake job is its own interpreter, and the
estimator's import (scikit-learn with scipy.stats and scipy.sparse) takes about 1.2 s of it; the jobs that only run
laws on a trained model (the study, the payload stage, the benchmark's runs) load this instead. Training, the rules
in words, the figures and the .fis export keep ``DampingModel``.

``learnt_inputs`` and ``damping_of`` are the model's transforms (K and C optionally learnt as log10 values), shared
with ``DampingModel``.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from uavdamp.anfis._math import _incidence, _predict
from uavdamp.anfis.netcdf import fitted_arrays


def learnt_inputs(X, log_stiffness: bool) -> np.ndarray:
    """Rows [f_y Hz, f_z Hz, K N/m] (n, 3) as the learnt inputs: a new float array, K -> log10 K if configured."""
    X = np.array(X, dtype=float, ndmin=2)
    if log_stiffness:
        X[:, 2] = np.log10(X[:, 2])
    return X


def damping_of(target, log_damping: bool) -> np.ndarray:
    """The learnt target (C or log10 C) as C, N s/m."""
    return 10.0 ** np.asarray(target, float) if log_damping else np.asarray(target, float)


class DampingPredictor:
    """The fitted ANFIS of a ``DampingModel`` for prediction only: ``predict([[f_y Hz, f_z Hz, K N/m]])`` -> C in
    N s/m, each learnt input clamped to its training range as the estimator does."""

    def __init__(self, arrays: dict, log_stiffness: bool, log_damping: bool):
        self.log_stiffness, self.log_damping = bool(log_stiffness), bool(log_damping)
        self.n_inputs = int(arrays["n_features_in_"])
        self._input_range = arrays["input_range_"]
        self._rules = (
            arrays["centres_"],
            arrays["sigmas_"],
            arrays["mf_input_"],
            _incidence(arrays["rule_mf_"], arrays["centres_"].size),
            arrays["consequents_"],
        )

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> DampingPredictor:
        """From a fitted ``DampingModel``'s dataset (its ``to_dataset``: the ANFIS and the two log flags)."""
        return cls(fitted_arrays(ds), bool(ds.attrs["log_stiffness"]), bool(ds.attrs["log_damping"]))

    def predict(self, X) -> np.ndarray:
        """C, N s/m (n,), for rows X (n, 3) [f_y Hz, f_z Hz, K N/m]; ValueError for another number of columns or a
        learnt input that is not finite (K <= 0 where K is learnt as log10 K)."""
        rows = np.array(X, dtype=float, ndmin=2)
        if rows.ndim != 2 or rows.shape[1] != self.n_inputs:
            raise ValueError(
                f"X: rows of {self.n_inputs} inputs [f_y Hz, f_z Hz, K N/m] needed, got shape {rows.shape}"
            )
        inputs = learnt_inputs(rows, self.log_stiffness)
        if not np.isfinite(inputs).all():
            raise ValueError(f"X: every learnt input must be finite (K > 0 where learnt as log10 K), got {X!r}")
        return damping_of(_predict(inputs, self._input_range, *self._rules), self.log_damping)
