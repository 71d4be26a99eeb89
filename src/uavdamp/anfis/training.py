"""Learning the reference table: samples, the seeded train/check split, model selection, baselines, the record.

Inputs [f_y (Hz), f_z (Hz), K (N/m)], output the optimal damping C (N s/m) of the reference table
(paper: an 80/20 split, the 20 % checking generalisation). Cells whose grid points all failed
(NaN) are left out and counted.

K and C may be learnt as log10 values (config `log_stiffness`, `log_damping`): the grid spaces them
logarithmically over decades, and a first-order rule linear in K or C cannot follow that; the
rules then read "... AND log10_K is MF1 ... THEN log10_C = ...". `DampingModel` applies the
transforms, so callers always pass K in N/m and get C in N s/m.

`train` keeps the checking split out of everything but the final report: the ANFIS structure is
chosen by k-fold cross-validation on the training rows (`uavdamp.model_selection`), the epoch on a
validation part of the training rows (`epoch_selection: validation`), and the checking rows are
predicted once, by the ANFIS and by the baselines (`uavdamp.baselines`) fitted on the same
training rows and targets. `epoch_selection: checking` is MATLAB's anfis with checking data
(chkFIS): the epoch is chosen on the checking rows, whose error is then optimistic.
"""

from __future__ import annotations

import time

import numpy as np
import xarray as xr

from uavdamp.anfis import baselines, model_selection
from uavdamp.anfis.estimator import ANFIS
from uavdamp.anfis.params import AnfisOptions
from uavdamp.reference_table.criteria import select_grid, select_table

INPUTS = ("freq_y", "freq_z", "stiffness")


def table_samples(table: xr.Dataset, target: str = "damping_opt") -> tuple[np.ndarray, np.ndarray, int]:
    """(X (n, 3), y (n,), number of NaN cells dropped) from the table's `target` (freq_y, freq_z, stiffness)."""
    da = table[target].transpose(*INPUTS)
    grids = np.meshgrid(*(table[name].values for name in INPUTS), indexing="ij")
    X = np.column_stack([g.ravel() for g in grids])
    y = da.values.ravel()
    keep = np.isfinite(y)
    return X[keep], y[keep], int((~keep).sum())


def select_target(table: xr.Dataset, grid: xr.Dataset | None, target: tuple[str, str] | None):
    """The table and grid of the criterion and window `target` = (criterion, window) names (config
    `reference_table`): `damping_opt` over INPUTS and the grid's `criterion` over (INPUTS, damping).
    None: the table and grid as given (they already hold one criterion)."""
    if target is None:
        return table, grid
    chosen = select_table(table, *target)
    if grid is not None:
        values = select_grid(grid, *target)
        grid = xr.Dataset({"criterion": values.reset_coords(drop=True)})
    return chosen, grid


def split(n: int, train_fraction: float, seed: int) -> np.ndarray:
    """Boolean mask of the training rows: a seeded random `train_fraction` of n (at least one of each)."""
    if n < 2:
        raise ValueError(f"need at least 2 samples to split, got {n}")
    n_train = min(max(int(round(train_fraction * n)), 1), n - 1)
    mask = np.zeros(n, dtype=bool)
    mask[np.random.default_rng(seed).permutation(n)[:n_train]] = True
    return mask


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
    def unfitted(cls, options: AnfisOptions, estimator=None) -> DampingModel:
        """From the `anfis` section: an ANFIS (or ``estimator``) on the configured transforms."""
        log_k, log_c = options.log_stiffness, options.log_damping
        if estimator is None:
            estimator = ANFIS(
                **options.estimator_params(),
                input_names=["f_y", "f_z", "log10_K" if log_k else "K"],
                input_units=["Hz", "Hz", "1" if log_k else "N/m"],
                output_name="log10_C" if log_c else "C",
                output_units="1" if log_c else "N s/m",
            )
        return cls(estimator, log_k, log_c)

    def inputs(self, X) -> np.ndarray:
        """Rows [f_y Hz, f_z Hz, K N/m] as the learnt inputs (K -> log10 K if configured)."""
        X = np.array(X, dtype=float, ndmin=2)
        if self.log_stiffness:
            X[:, 2] = np.log10(X[:, 2])
        return X

    def target(self, damping) -> np.ndarray:
        """C (N s/m) as the learnt target (log10 C if configured)."""
        return np.log10(damping) if self.log_damping else np.asarray(damping, float)

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
        raw = self.predict_target(X)
        return 10.0**raw if self.log_damping else raw

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


def regret(grid: xr.Dataset, X: np.ndarray, damping: np.ndarray) -> np.ndarray:
    """criterion(C) / min over C of the criterion, at table cells X [f_y, f_z, K] (grid values),
    with the grid's criterion interpolated linearly in log C: what a damping choice costs."""
    out = np.empty(len(X))
    log_c = np.log(grid.damping.values)
    for i, (fy, fz, k) in enumerate(X):
        row = grid.criterion.sel(freq_y=fy, freq_z=fz, stiffness=k).values
        ok = np.isfinite(row)
        value = np.interp(
            np.log(np.clip(damping[i], grid.damping.values[0], grid.damping.values[-1])), log_c[ok], row[ok]
        )
        out[i] = value / np.nanmin(row)
    return out


def _fit_models(X, y, is_train, options: AnfisOptions):
    """The cross-validated ANFIS and the baselines, fitted on the training rows; CV record; fit times (s)."""
    seed, mode = options.seed, options.epoch_selection
    candidates = [c.params() for c in options.selection.candidates]
    anfis = DampingModel.unfitted(options)
    Xt, yt = anfis.inputs(X[is_train]), anfis.target(y[is_train])
    best, cv, cv_times = model_selection.cross_validate(
        anfis.estimator, Xt, yt, candidates, options.selection.folds, seed
    )
    anfis.estimator.set_params(**best)
    times = {f"cv {model_selection.label(c)} (mean per fold)": t for c, t in zip(candidates, cv_times, strict=True)}
    models = {"anfis": anfis}
    for name in options.baselines:
        models[name] = DampingModel.unfitted(options, baselines.make(name, X.shape[1], seed))
    for name, model in models.items():
        start = time.perf_counter()
        if name == "anfis" and mode == "checking":  # MATLAB chkFIS: the epoch chosen on the checking rows
            model.fit(X[is_train], y[is_train], X[~is_train], y[~is_train])
        else:
            model.fit(X[is_train], y[is_train])
        times[name] = time.perf_counter() - start
    return models, cv, times


def _model_scores(models: dict, X, y, is_train, grid) -> xr.Dataset:
    """Per model: checking errors in the learnt target and in C, and regret; predictions per sample."""
    check = ~is_train
    anfis = models["anfis"]
    y_learnt, units = anfis.target(y), anfis.anfis.output_units
    target, damping, cost = [], [], []
    for model in models.values():
        target.append(model.predict_target(X))
        damping.append(10.0 ** target[-1] if model.log_damping else target[-1])
        if grid is not None:
            cost.append(regret(grid, X, damping[-1]))
    target, damping = np.array(target), np.array(damping)
    out = anfis.anfis.output_name
    scores = {
        "check_rmse_target": (
            np.sqrt(np.mean((target[:, check] - y_learnt[check]) ** 2, axis=1)),
            units,
            f"checking RMSE of the learnt target {out}",
        ),
        "check_rmse_damping": (
            np.sqrt(np.mean((damping[:, check] - y[check]) ** 2, axis=1)),
            "N s m-1",
            "checking RMSE of the damping C",
        ),
        "check_median_relative_error": (
            np.median(np.abs(damping[:, check] - y[check]) / np.abs(y[check]), axis=1),
            "1",
            "checking median of |C predicted - C reference| / C reference",
        ),
        "train_rmse_target": (
            np.sqrt(np.mean((target[:, is_train] - y_learnt[is_train]) ** 2, axis=1)),
            units,
            f"training RMSE of the learnt target {out}",
        ),
    }
    ds = xr.Dataset({k: ("model", v, {"units": u, "long_name": n}) for k, (v, u, n) in scores.items()})
    ds["damping_predicted_by_model"] = (
        ("model", "sample"),
        damping,
        {"units": "N s m-1", "long_name": "C predicted by each model"},
    )
    if grid is not None:
        cost = np.array(cost)
        ds["regret_by_model"] = (
            ("model", "sample"),
            cost,
            {"units": "1", "long_name": "criterion at the model's damping / optimal criterion"},
        )
        ds["check_regret_mean"] = (
            "model",
            cost[:, check].mean(axis=1),
            {"units": "1", "long_name": "checking mean of the regret"},
        )
        ds["check_regret_max"] = (
            "model",
            cost[:, check].max(axis=1),
            {"units": "1", "long_name": "checking maximum of the regret"},
        )
    names = list(models)
    return ds.assign_coords(
        model=("model", np.array(names, dtype=object), {"units": "1", "long_name": "model name"}),
        model_description=(
            "model",
            np.array([baselines.LONG_NAMES[n] for n in names], dtype=object),
            {"units": "1", "long_name": "what the model is"},
        ),
    )


def _epoch_record(fitted: ANFIS, mode: str, validation_fraction: float) -> xr.Dataset:
    """Training and epoch-selection RMSE and step size per epoch of the chosen ANFIS."""
    learnt = {"units": fitted.output_units}
    rows = (
        "the checking rows (MATLAB chkFIS: optimistic checking error)"
        if mode == "checking"
        else f"a validation {validation_fraction:.0%} of the training rows"
    )
    validation = fitted.val_rmse_ if fitted.val_rmse_.size else np.full(fitted.train_rmse_.shape, np.nan)
    return xr.Dataset(
        {
            "train_rmse": (
                "epoch",
                fitted.train_rmse_,
                {**learnt, "long_name": f"training RMSE of {fitted.output_name}"},
            ),
            "validation_rmse": (
                "epoch",
                validation,
                {**learnt, "long_name": f"RMSE of {fitted.output_name} on {rows} (choose the epoch)"},
            ),
            "step_size": (
                "epoch",
                fitted.step_sizes_,
                {"units": "1", "long_name": "premise step size (fraction of input range)"},
            ),
        },
        coords={
            "epoch": ("epoch", np.arange(1, fitted.train_rmse_.size + 1), {"units": "1", "long_name": "training epoch"})
        },
    )


def train(
    table: xr.Dataset, grid: xr.Dataset | None, options: AnfisOptions, target: tuple[str, str] | None = None
) -> tuple[DampingModel, xr.Dataset, dict]:
    """Select, fit and check the ANFIS and the baselines; return the ANFIS, the record, fit times (s).

    target: (criterion, window) of a table and grid over every criterion and window (`select_target`);
    the ANFIS learns that criterion's optimal C and the regret uses its grid slice.

    With the `grid` (criterion over C) the record also holds each cell's regret per model: the
    criterion at the predicted C over the best criterion (1 = as good as the table's optimum).
    The fit times are apart from the record, which is identical on two runs.
    """
    mode = options.epoch_selection
    table, grid = select_target(table, grid, target)
    X, y, dropped = table_samples(table)
    is_train = split(y.size, options.train_fraction, options.seed)
    models, cv, times = _fit_models(X, y, is_train, options)
    model = models["anfis"]
    scores = _model_scores(models, X, y, is_train, grid)
    predicted = scores.damping_predicted_by_model.sel(model="anfis").values
    samples = xr.Dataset(
        {
            "damping_reference": ("sample", y, {"units": "N s m-1", "long_name": "optimal C in the reference table"}),
            "damping_predicted": ("sample", predicted, {"units": "N s m-1", "long_name": "C predicted by the ANFIS"}),
            "is_training": (
                "sample",
                is_train.astype(np.int8),
                {"units": "1", "long_name": "1: training split, 0: checking split"},
            ),
            **{name: ("sample", X[:, j], {**table[name].attrs}) for j, name in enumerate(INPUTS)},
        },
        coords={"sample": ("sample", np.arange(y.size), {"units": "1", "long_name": "reference table cell"})},
    )
    if grid is not None:
        samples["regret"] = (
            "sample",
            scores.regret_by_model.sel(model="anfis").values,
            {"units": "1", "long_name": "criterion at the ANFIS damping / optimal criterion"},
        )
    record = xr.merge(
        [_epoch_record(model.anfis, mode, options.validation_fraction), samples, scores, cv],
        combine_attrs="override",
    )
    anfis = scores.sel(model="anfis")
    rel = np.abs(predicted - y) / np.abs(y)
    record.attrs = {
        **cv.attrs,
        "epoch_selection": mode,
        "best_epoch": int(model.anfis.best_epoch_),
        "n_rules": int(model.anfis.n_rules_),
        "n_samples": int(y.size),
        "n_training": int(is_train.sum()),
        "n_dropped_nan": dropped,
        "train_rmse_final": float(np.sqrt(np.mean((predicted[is_train] - y[is_train]) ** 2))),
        "check_rmse_final": float(anfis.check_rmse_damping),
        "check_mean_relative_error": float(np.mean(rel[~is_train])),
        "check_median_relative_error": float(anfis.check_median_relative_error),
    }
    if target is not None:
        record.attrs.update(criterion=target[0], window=target[1])
    if grid is not None:
        record.attrs["check_regret_mean"] = float(anfis.check_regret_mean)
        record.attrs["check_regret_max"] = float(anfis.check_regret_max)
    return model, record, times
