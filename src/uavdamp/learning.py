"""Learning the reference table with ANFIS: samples, the seeded train/check split, the training record.

Inputs [f_y (Hz), f_z (Hz), K (N/m)], output the optimal damping C (N s/m) of the reference table
(paper: an 80/20 split, the 20 % checking generalisation). Cells whose grid points all failed
(NaN) are left out and counted.

K and C may be learnt as log10 values (config `log_stiffness`, `log_damping`): the grid spaces them
logarithmically over decades, and a first-order rule linear in K or C cannot follow that; the
rules then read "... AND log10_K is MF1 ... THEN log10_C = ...". `TableModel` applies the
transforms, so callers always pass K in N/m and get C in N s/m.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from uavdamp.anfis import ANFIS

INPUTS = ("freq_y", "freq_z", "stiffness")
INPUT_NAMES = ("f_y", "f_z", "K")
INPUT_UNITS = ("Hz", "Hz", "N/m")
MODEL_OPTIONS = ("n_mfs", "init", "n_rules", "epochs", "error_goal", "step_size", "step_increase",
                 "step_decrease", "min_sigma_frac", "ridge")


def table_samples(table: xr.Dataset, target: str = "damping_opt") -> tuple[np.ndarray, np.ndarray, int]:
    """(X (n, 3), y (n,), number of NaN cells dropped) from the table's `target` (freq_y, freq_z, stiffness)."""
    da = table[target].transpose(*INPUTS)
    grids = np.meshgrid(*(table[name].values for name in INPUTS), indexing="ij")
    X = np.column_stack([g.ravel() for g in grids])
    y = da.values.ravel()
    keep = np.isfinite(y)
    return X[keep], y[keep], int((~keep).sum())


def split(n: int, train_fraction: float, seed: int) -> np.ndarray:
    """Boolean mask of the training rows: a seeded random `train_fraction` of n (at least one of each)."""
    if not 0 < train_fraction < 1:
        raise ValueError(f"anfis.train_fraction: must be in (0, 1), got {train_fraction}")
    if n < 2:
        raise ValueError(f"need at least 2 samples to split, got {n}")
    n_train = min(max(int(round(train_fraction * n)), 1), n - 1)
    mask = np.zeros(n, dtype=bool)
    mask[np.random.default_rng(seed).permutation(n)[:n_train]] = True
    return mask


class TableModel:
    """An ANFIS on (optionally log10) K and C: predict([[f_y Hz, f_z Hz, K N/m]]) -> C in N s/m."""

    def __init__(self, anfis: ANFIS, log_stiffness: bool, log_damping: bool):
        self.anfis, self.log_stiffness, self.log_damping = anfis, bool(log_stiffness), bool(log_damping)

    @classmethod
    def unfitted(cls, options: dict) -> "TableModel":
        """From the config's `anfis` section."""
        log_k, log_c = bool(options["log_stiffness"]), bool(options["log_damping"])
        kwargs = {name: options[name] for name in MODEL_OPTIONS if name in options}
        anfis = ANFIS(**kwargs, random_state=int(options["seed"]),
                      input_names=["f_y", "f_z", "log10_K" if log_k else "K"],
                      input_units=["Hz", "Hz", "1" if log_k else "N/m"],
                      output_name="log10_C" if log_c else "C", output_units="1" if log_c else "N s/m")
        return cls(anfis, log_k, log_c)

    def inputs(self, X) -> np.ndarray:
        X = np.array(X, dtype=float, ndmin=2)
        if self.log_stiffness:
            X[:, 2] = np.log10(X[:, 2])
        return X

    def fit(self, X, y, X_val, y_val) -> "TableModel":
        out = np.log10 if self.log_damping else np.asarray
        self.anfis.fit(self.inputs(X), out(y), self.inputs(X_val), out(y_val))
        return self

    def predict(self, X) -> np.ndarray:
        """C, N s/m, for rows [f_y Hz, f_z Hz, K N/m]."""
        raw = self.anfis.predict(self.inputs(X))
        return 10.0**raw if self.log_damping else raw

    def rules_text(self) -> str:
        """The rules in words, after a line saying what the log10 inputs and output are."""
        logs = [text for on, text in ((self.log_stiffness, "log10_K = log10(K / (1 N/m))"),
                                      (self.log_damping, "log10_C = log10(C / (1 N s/m))")) if on]
        return ("; ".join(logs) + "\n" if logs else "") + self.anfis.rules_text()

    def to_dataset(self) -> xr.Dataset:
        ds = self.anfis.to_dataset()
        ds.attrs.update(log_stiffness=int(self.log_stiffness), log_damping=int(self.log_damping))
        return ds

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> "TableModel":
        return cls(ANFIS.from_dataset(ds), bool(ds.attrs["log_stiffness"]), bool(ds.attrs["log_damping"]))


def regret(grid: xr.Dataset, X: np.ndarray, damping: np.ndarray) -> np.ndarray:
    """criterion(C) / min over C of the criterion, at table cells X [f_y, f_z, K] (grid values),
    with the grid's criterion interpolated linearly in log C: what a damping choice costs."""
    out = np.empty(len(X))
    log_c = np.log(grid.damping.values)
    for i, (fy, fz, k) in enumerate(X):
        row = grid.criterion.sel(freq_y=fy, freq_z=fz, stiffness=k).values
        ok = np.isfinite(row)
        value = np.interp(np.log(np.clip(damping[i], grid.damping.values[0], grid.damping.values[-1])),
                          log_c[ok], row[ok])
        out[i] = value / np.nanmin(row)
    return out


def train(table: xr.Dataset, grid: xr.Dataset | None, options: dict) -> tuple[TableModel, xr.Dataset]:
    """Fit on the training split, keep the best-checking epoch; return the model and its record.

    With the `grid` (criterion over C) the record also holds each cell's regret: the criterion
    at the predicted C over the best criterion (1 = as good as the table's optimum).
    """
    X, y, dropped = table_samples(table)
    is_train = split(y.size, float(options["train_fraction"]), int(options["seed"]))
    model = TableModel.unfitted(options).fit(X[is_train], y[is_train], X[~is_train], y[~is_train])
    predicted = model.predict(X)
    fitted = model.anfis
    epochs = np.arange(1, len(fitted.train_rmse_) + 1)
    unit = {"units": "N s m-1"}
    learnt = {"units": fitted.output_units}

    def rmse(mask):
        return float(np.sqrt(np.mean((predicted[mask] - y[mask]) ** 2)))

    record = xr.Dataset(
        {
            "train_rmse": ("epoch", fitted.train_rmse_, {**learnt, "long_name": f"training RMSE of {fitted.output_name}"}),
            "check_rmse": ("epoch", fitted.val_rmse_, {**learnt, "long_name": f"checking (held-out) RMSE of {fitted.output_name}"}),
            "step_size": ("epoch", fitted.step_sizes_, {"units": "1", "long_name": "premise step size (fraction of input range)"}),
            "damping_reference": ("sample", y, {**unit, "long_name": "optimal C in the reference table"}),
            "damping_predicted": ("sample", predicted, {**unit, "long_name": "C predicted by the trained ANFIS"}),
            "is_training": ("sample", is_train.astype(np.int8), {"units": "1", "long_name": "1: training split, 0: checking split"}),
            **{name: ("sample", X[:, j], {**table[name].attrs}) for j, name in enumerate(INPUTS)},
        },
        coords={
            "epoch": ("epoch", epochs, {"units": "1", "long_name": "training epoch"}),
            "sample": ("sample", np.arange(y.size), {"units": "1", "long_name": "reference table cell"}),
        },
        attrs={
            "best_epoch": int(fitted.best_epoch_),
            "n_rules": int(fitted.n_rules_),
            "n_samples": int(y.size),
            "n_training": int(is_train.sum()),
            "n_dropped_nan": dropped,
            "train_rmse_final": rmse(is_train),
            "check_rmse_final": rmse(~is_train),
            "check_mean_relative_error": float(np.mean(np.abs(predicted[~is_train] - y[~is_train])
                                                       / np.maximum(np.abs(y[~is_train]), 1e-12))),
            "check_median_relative_error": float(np.median(np.abs(predicted[~is_train] - y[~is_train])
                                                           / np.maximum(np.abs(y[~is_train]), 1e-12))),
        },
    )
    if grid is not None:
        cost = regret(grid, X, predicted)
        record["regret"] = ("sample", cost, {"units": "1", "long_name": "criterion at the ANFIS damping / optimal criterion"})
        record.attrs["check_regret_mean"] = float(np.mean(cost[~is_train]))
        record.attrs["check_regret_max"] = float(np.max(cost[~is_train]))
    return model, record
