"""The damping model on its physical inputs, and the regret of a damping choice.

``DampingModel`` wraps an ANFIS (or any scikit-learn regressor) learning [f_y Hz, f_z Hz, K N/m] -> C N s/m,
with K and C optionally learnt as log10 values (config ``log_stiffness``, ``log_damping``): the grid spaces
them logarithmically over decades, and a first-order rule linear in K or C cannot follow that; the rules then
read "... AND log10_K is MF1 ... THEN log10_C = ...". Callers always pass K in N/m and get C in N s/m.

``Regret``: criterion(C) / min over C of the criterion at a table cell, the grid's criterion interpolated
linearly in log C (1 = as good as the table's optimum).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import xarray as xr

from uavdamp.anfis.estimator import ANFIS
from uavdamp.anfis.params import AnfisOptions
from uavdamp.anfis.predictor import damping_of, learnt_inputs

INPUTS = ("freq_y", "freq_z", "stiffness")


class DampingModel:
    """A regressor of the optimal damping on (optionally log10) K and C: predict([[f_y Hz, f_z Hz, K N/m]]) -> C in
    N s/m.

    ``estimator`` is an ANFIS (``anfis``, the study's model) or any scikit-learn regressor.
    """

    def __init__(self, estimator, log_stiffness: bool, log_damping: bool):
        self.estimator, self.log_stiffness, self.log_damping = estimator, bool(log_stiffness), bool(log_damping)

    @property
    def anfis(self) -> ANFIS:
        return self.estimator

    @classmethod
    def unfitted(cls, options: AnfisOptions, estimator=None, inputs: tuple[str, ...] = INPUTS) -> DampingModel:
        """From the `anfis` section: an ANFIS (or ``estimator``) on the configured transforms; `inputs` the
        table's dimensions the rows follow (two frequencies ``freq_NAME`` in Hz, then ``stiffness``), the ANFIS's
        inputs then named f_NAME."""
        log_k, log_c = options.log_stiffness, options.log_damping
        if estimator is None:
            estimator = ANFIS(
                **options.estimator_params(),
                input_names=[*(name.replace("freq_", "f_") for name in inputs[:2]), "log10_K" if log_k else "K"],
                input_units=["Hz", "Hz", "1" if log_k else "N/m"],
                output_name="log10_C" if log_c else "C",
                output_units="1" if log_c else "N s/m",
            )
        return cls(estimator, log_k, log_c)

    def inputs(self, X) -> np.ndarray:
        """Rows [f_y Hz, f_z Hz, K N/m] as the learnt inputs (K -> log10 K if configured)."""
        return learnt_inputs(X, self.log_stiffness)

    def target(self, damping) -> np.ndarray:
        """C (N s/m) as the learnt target (log10 C if configured)."""
        return np.log10(damping) if self.log_damping else np.asarray(damping, float)

    def damping(self, target) -> np.ndarray:
        """The learnt target (C or log10 C) as C, N s/m."""
        return damping_of(target, self.log_damping)

    def fit(self, X, y, X_val=None, y_val=None) -> DampingModel:
        """Fit on rows X and C; X_val, y_val (ANFIS only) choose the epoch instead of its validation_fraction."""
        if X_val is None:
            self.estimator.fit(self.inputs(X), self.target(y))
        else:
            self.estimator.fit(self.inputs(X), self.target(y), self.inputs(X_val), self.target(y_val))
        return self

    def predict_target(self, X) -> np.ndarray:
        """The learnt target (C or log10 C) for rows [f_y Hz, f_z Hz, K N/m]."""
        return self.estimator.predict(self.inputs(X))

    def predict(self, X) -> np.ndarray:
        """C, N s/m, for rows [f_y Hz, f_z Hz, K N/m]."""
        return self.damping(self.predict_target(X))

    def rules_text(self) -> str:
        """The rules in words, after a line saying what the log10 inputs and output are."""
        logs = [
            text
            for on, text in (
                (self.log_stiffness, "log10_K = log10(K / (1 N/m))"),
                (self.log_damping, "log10_C = log10(C / (1 N s/m))"),
            )
            if on
        ]
        return ("; ".join(logs) + "\n" if logs else "") + self.anfis.rules_text()

    def to_dataset(self) -> xr.Dataset:
        ds = self.anfis.to_dataset()
        ds.attrs.update(log_stiffness=int(self.log_stiffness), log_damping=int(self.log_damping))
        return ds

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> DampingModel:
        return cls(ANFIS.from_dataset(ds), bool(ds.attrs["log_stiffness"]), bool(ds.attrs["log_damping"]))


def _interp(x: np.ndarray, xp: np.ndarray, fp: np.ndarray) -> np.ndarray:
    """Row-wise ``np.interp(x[i], xp, fp[i])`` for x (n,), one increasing xp (m,) and fp (n, m); numpy's formula."""
    j = np.clip(np.searchsorted(xp, x, side="right") - 1, 0, xp.size - 2)
    rows = np.arange(x.size)
    left, right = fp[rows, j], fp[rows, j + 1]
    value = (right - left) / (xp[j + 1] - xp[j]) * (x - xp[j]) + left
    value = np.where(x == xp[j], left, value)
    return np.where(x >= xp[-1], fp[:, -1], np.where(x <= xp[0], fp[:, 0], value))


class Regret:
    """criterion(C) / min over C of the criterion at table cells, from a grid's ``criterion`` (inputs, damping),
    `inputs` its three input dimensions (default INPUTS); NaN criteria (a failed point, a damping left out) are
    interpolated over."""

    def __init__(self, grid: xr.Dataset, inputs: tuple[str, ...] = INPUTS):
        self.inputs = tuple(inputs)
        self.criterion = np.asarray(grid.criterion.transpose(*self.inputs, "damping").values, float)
        self.axes = [pd.Index(grid[name].values) for name in self.inputs]
        self.damping = np.asarray(grid.damping.values, float)
        self.optimum = np.nanmin(self.criterion, axis=-1)

    def __call__(self, X: np.ndarray, damping: np.ndarray) -> np.ndarray:
        """Regret at cells X [f_y, f_z, K] (grid values exactly) of the dampings C (N s/m), 1."""
        index = []
        for name, axis, values in zip(self.inputs, self.axes, np.asarray(X, float).T, strict=True):
            k = axis.get_indexer(values)
            if (k < 0).any():
                raise KeyError(f"{name} = {float(values[k < 0][0]):g} is not a value of the grid")
            index.append(k)
        rows, best = self.criterion[tuple(index)], self.optimum[tuple(index)]
        log_c = np.log(np.clip(damping, self.damping[0], self.damping[-1]))
        xp = np.log(self.damping)
        finite = np.isfinite(rows).all(axis=1)
        value = np.empty(len(rows))
        value[finite] = _interp(log_c[finite], xp, rows[finite])
        for i in np.flatnonzero(~finite):  # failed points: interpolate over the others
            ok = np.isfinite(rows[i])
            value[i] = np.interp(log_c[i], xp[ok], rows[i, ok])
        return value / best


def regret(grid: xr.Dataset, X: np.ndarray, damping: np.ndarray) -> np.ndarray:
    """criterion(C) / min over C of the criterion, at table cells X [f_y, f_z, K] (grid values),
    with the grid's criterion interpolated linearly in log C: what a damping choice costs."""
    return Regret(grid)(X, damping)
