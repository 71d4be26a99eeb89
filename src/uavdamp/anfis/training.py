"""Learning the reference table: samples, the seeded train/check split, model selection, baselines, the record.

Inputs [f_y (Hz), f_z (Hz), K (N/m)], output the optimal damping C (N s/m) of the reference table
(paper: an 80/20 split, the 20 % checking generalisation). Cells whose grid points all failed
(NaN) are left out and counted.

K and C may be learnt as log10 values (config `log_stiffness`, `log_damping`; `uavdamp.anfis.damping`).

`train` keeps the checking split out of everything but the final report: the ANFIS structure is
chosen by k-fold cross-validation on the training rows (`uavdamp.anfis.model_selection`: every candidate's
RMSE with its standard error, rules and regret on the folds' held-out rows; the smallest structure within one
standard error of the best by default), the epoch on a
validation part of the training rows (`epoch_selection: validation`), and the checking rows are
predicted once, by the ANFIS and by the baselines (`uavdamp.anfis.baselines`) fitted on the same
training rows and targets. `epoch_selection: checking` is MATLAB's anfis with checking data
(chkFIS): the epoch is chosen on the checking rows, whose error is then optimistic.

`n_jobs`: the cross-validation's (candidate, fold) fits and the baselines run on that many joblib workers, one
thread each; the record is identical whatever n_jobs.
"""

from __future__ import annotations

import time

import numpy as np
import xarray as xr
from threadpoolctl import threadpool_limits

from uavdamp import parallel
from uavdamp.anfis import baselines, model_selection
from uavdamp.anfis.damping import INPUTS, DampingModel, Regret, regret
from uavdamp.anfis.params import AnfisOptions, split
from uavdamp.reference_table.criteria import select_grid, select_table

__all__ = ["INPUTS", "DampingModel", "regret", "select_target", "split", "table_samples", "train"]


def table_samples(
    table: xr.Dataset, target: str = "damping_opt", inputs: tuple[str, ...] = INPUTS
) -> tuple[np.ndarray, np.ndarray, int]:
    """(X (n, 3), y (n,), number of NaN cells dropped) from the table's `target` over its dimensions `inputs`
    (default INPUTS: freq_y, freq_z, stiffness)."""
    da = table[target].transpose(*inputs)
    grids = np.meshgrid(*(table[name].values for name in inputs), indexing="ij")
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


def _fit_baseline(model: DampingModel, X, y) -> tuple[DampingModel, float]:
    """The baseline fitted on rows X and C; fit seconds."""
    start = time.perf_counter()
    model.fit(X, y)
    return model, time.perf_counter() - start


def _cv_regret(cv: xr.Dataset, predictions: list, folds: list, anfis: DampingModel, X, cost) -> None:
    """Adds to the CV record the mean and worst regret of every candidate on its folds' held-out rows."""
    n_folds = len(folds)
    per_row = np.empty((cv.sizes["candidate"], len(X)))
    for k, pred in enumerate(predictions):
        test = folds[k % n_folds][1]
        per_row[k // n_folds, test] = cost(X[test], anfis.damping(pred))
    what = "over the training rows, each predicted by the fold model that held it out,"
    cv["cv_regret_mean"] = (
        "candidate",
        per_row.mean(axis=1),
        {"units": "1", "long_name": f"mean {what} of the regret"},
    )
    cv["cv_regret_max"] = (
        "candidate",
        per_row.max(axis=1),
        {"units": "1", "long_name": f"maximum {what} of the regret"},
    )


def _fit_models(X, y, is_train, options: AnfisOptions, grid, n_jobs: int, inputs: tuple[str, ...] = INPUTS):
    """The cross-validated ANFIS and the baselines, fitted on the training rows; CV record; fit times (s)."""
    candidates = [c.params() for c in options.selection.candidates]
    anfis = DampingModel.unfitted(options, inputs=inputs)
    Xt, yt = X[is_train], y[is_train]
    target = anfis.target(yt)
    folds = model_selection.splits(len(yt), options.selection.folds, options.seed)
    tasks = model_selection.fold_tasks(anfis.estimator, anfis.inputs(Xt), target, candidates, folds)
    names = list(options.baselines)
    tasks += [
        (_fit_baseline, (DampingModel.unfitted(options, baselines.make(n, 3, options.seed)), Xt, yt)) for n in names
    ]
    costs = [model_selection.cost(c, X.shape[1]) for c in candidates for _ in folds]
    costs += [baselines.COSTS[n] for n in names]
    out = parallel.run(tasks, n_jobs, costs)
    cv_out, fitted = out[: -len(names) or None], out[len(out) - len(names) :]
    scores = [
        (np.sqrt(np.mean((p - target[t]) ** 2)), r, s)
        for (p, r, s), (_, t) in zip(cv_out, folds * len(candidates), strict=True)
    ]
    est = anfis.estimator
    chosen, cv, cv_times = model_selection.summarise(
        candidates, scores, len(folds), options.selection.rule, est.output_units, est.output_name
    )
    if grid is not None:
        _cv_regret(cv, [p for p, _, _ in cv_out], folds, anfis, Xt, Regret(grid, inputs))
    est.set_params(**candidates[chosen])
    times = {f"cv {model_selection.label(c)} (mean per fold)": t for c, t in zip(candidates, cv_times, strict=True)}
    start = time.perf_counter()
    if options.epoch_selection == "checking":  # MATLAB chkFIS: the epoch chosen on the checking rows
        anfis.fit(Xt, yt, X[~is_train], y[~is_train])
    else:
        anfis.fit(Xt, yt)
    times["anfis"] = time.perf_counter() - start
    times.update({name: seconds for name, (_, seconds) in zip(names, fitted, strict=True)})
    return {"anfis": anfis, **{name: model for name, (model, _) in zip(names, fitted, strict=True)}}, cv, times


def _rmse(a, b) -> np.ndarray:
    return np.sqrt(np.mean((a - b) ** 2, axis=1))


def _model_scores(models: dict, X, y, is_train, grid, inputs: tuple[str, ...] = INPUTS) -> xr.Dataset:
    """Per model: checking errors in the learnt target and in C, and regret; predictions per sample."""
    check, anfis = ~is_train, models["anfis"]
    y_learnt, units, out = anfis.target(y), anfis.anfis.output_units, anfis.anfis.output_name
    target = np.array([model.predict_target(X) for model in models.values()])
    damping = np.array([model.damping(t) for model, t in zip(models.values(), target, strict=True)])
    relative = np.median(np.abs(damping[:, check] - y[check]) / np.abs(y[check]), axis=1)
    scores = {
        "check_rmse_target": (
            _rmse(target[:, check], y_learnt[check]),
            units,
            f"checking RMSE of the learnt target {out}",
        ),
        "check_rmse_damping": (_rmse(damping[:, check], y[check]), "N s m-1", "checking RMSE of the damping C"),
        "check_median_relative_error": (relative, "1", "checking median of |C predicted - C reference| / C reference"),
        "train_rmse_target": (
            _rmse(target[:, is_train], y_learnt[is_train]),
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
        cost = Regret(grid, inputs)
        regrets = np.array([cost(X, d) for d in damping])
        what = "criterion at the model's damping / optimal criterion"
        ds["regret_by_model"] = (("model", "sample"), regrets, {"units": "1", "long_name": what})
        ds["check_regret_mean"] = (
            "model",
            regrets[:, check].mean(axis=1),
            {"units": "1", "long_name": "checking mean of the regret"},
        )
        ds["check_regret_max"] = (
            "model",
            regrets[:, check].max(axis=1),
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


def _epoch_record(fitted, mode: str, validation_fraction: float) -> xr.Dataset:
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


def _samples(table: xr.Dataset, X, y, is_train, scores: xr.Dataset, inputs: tuple[str, ...] = INPUTS) -> xr.Dataset:
    """Per table cell: its inputs, reference and ANFIS damping, split and (with a grid) the ANFIS's regret."""
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
            **{name: ("sample", X[:, j], {**table[name].attrs}) for j, name in enumerate(inputs)},
        },
        coords={"sample": ("sample", np.arange(y.size), {"units": "1", "long_name": "reference table cell"})},
    )
    if "regret_by_model" in scores:
        samples["regret"] = (
            "sample",
            scores.regret_by_model.sel(model="anfis").values,
            {"units": "1", "long_name": "criterion at the ANFIS damping / optimal criterion"},
        )
    return samples


def _summary(model: DampingModel, scores: xr.Dataset, samples: xr.Dataset, options: AnfisOptions, dropped: int):
    """The record's attributes: the chosen ANFIS, the sample counts and its checking errors."""
    anfis, s = scores.sel(model="anfis"), samples
    train = s.is_training.values == 1
    error = s.damping_predicted.values - s.damping_reference.values
    attrs = {
        "epoch_selection": options.epoch_selection,
        "best_epoch": int(model.anfis.best_epoch_),
        "n_rules": int(model.anfis.n_rules_),
        "n_samples": int(s.sizes["sample"]),
        "n_training": int(train.sum()),
        "n_dropped_nan": dropped,
        "train_rmse_final": float(np.sqrt(np.mean(error[train] ** 2))),
        "check_rmse_final": float(anfis.check_rmse_damping),
        "check_mean_relative_error": float(np.mean(np.abs(error[~train] / s.damping_reference.values[~train]))),
        "check_median_relative_error": float(anfis.check_median_relative_error),
    }
    if "check_regret_mean" in scores:
        attrs.update(check_regret_mean=float(anfis.check_regret_mean), check_regret_max=float(anfis.check_regret_max))
    return attrs


def check_grid_edges(table: xr.Dataset) -> None:
    """ValueError if the chosen table's optimal C sits on an edge of the C grid inside the damper's range
    (`optimum_at_grid_edge` 1 or 2, `uavdamp.reference_table.criteria.grid_edge`): there it is only a bound, and the
    ANFIS would learn it as a value. A table without the flag (written before it existed) is not checked."""
    if "optimum_at_grid_edge" not in table:
        return
    flags = table.optimum_at_grid_edge.values
    bottom, top = int((flags == 1).sum()), int((flags == 2).sum())
    if bottom + top:
        raise ValueError(
            f"reference table: the optimal C of {(bottom + top) / flags.size:.1%} of its cells ({top} at the top, "
            f"{bottom} at the bottom of {flags.size}) lies on an edge of the C grid reference_table.damping_n_s_m "
            "(start, stop) inside the damper's range platform.isolator.damping_min_n_s_m/damping_max_n_s_m: there "
            "the table's best C is only a bound, and the ANFIS would learn it as a value; widen "
            "reference_table.damping_n_s_m (stop up to damping_max_n_s_m, start down towards damping_min_n_s_m), "
            "or set the damper's bounds to the grid's if that is the damper, and rerun"
        )


def train(
    table: xr.Dataset,
    grid: xr.Dataset | None,
    options: AnfisOptions,
    target: tuple[str, str] | None = None,
    n_jobs: int = 1,
    inputs: tuple[str, ...] = INPUTS,
) -> tuple[DampingModel, xr.Dataset, dict]:
    """Select, fit and check the ANFIS and the baselines; return the ANFIS, the record, fit times (s).

    target: (criterion, window) of a table and grid over every criterion and window (`select_target`);
    the ANFIS learns that criterion's optimal C and the regret uses its grid slice. ValueError before any fit if
    that optimum sits on an edge of the C grid inside the damper's range (`check_grid_edges`).

    With the `grid` (criterion over C) the record also holds each cell's regret per model: the
    criterion at the predicted C over the best criterion (1 = as good as the table's optimum), and every
    candidate's regret on the cross-validation's held-out rows. n_jobs: joblib workers (the record does not
    depend on it). The fit times are apart from the record, which is identical on two runs. `inputs`: the
    table's three input dimensions, two frequencies (Hz) then the stiffness (N m-1); default INPUTS.
    """
    table, grid = select_target(table, grid, target)
    check_grid_edges(table)
    X, y, dropped = table_samples(table, inputs=inputs)
    is_train = split(y.size, options.train_fraction, options.seed)
    with threadpool_limits(limits=1):  # one thread per process, the parallelism is across fits (n_jobs)
        models, cv, times = _fit_models(X, y, is_train, options, grid, n_jobs, inputs)
        scores = _model_scores(models, X, y, is_train, grid, inputs)
    model = models["anfis"]
    samples = _samples(table, X, y, is_train, scores, inputs)
    record = xr.merge(
        [_epoch_record(model.anfis, options.epoch_selection, options.validation_fraction), samples, scores, cv],
        combine_attrs="override",
    )
    record.attrs = {**cv.attrs, **_summary(model, scores, samples, options, dropped)}
    if target is not None:
        record.attrs.update(criterion=target[0], window=target[1])
    return model, record, times
