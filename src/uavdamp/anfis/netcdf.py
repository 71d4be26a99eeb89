"""The ANFIS as text and as an xarray.Dataset: its rules in words, and an exact NetCDF round trip.

Functions of a fitted ``uavdamp.anfis.ANFIS`` (its ``rules_text``, ``to_dataset`` and
``from_dataset`` call these). Every number is stored in the original input and output units; the
output offset and scale used inside ``fit`` are already folded into the consequents, so ``predict``
of a loaded model uses exactly the stored numbers and is bit-identical.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from uavdamp.io import json_default


def _unit_suffix(unit: str) -> str:
    return "" if unit in ("", "1") else " " + unit


def _ratio_units(out: str, inp: str) -> str:
    if inp in ("", "1"):
        return out
    return f"1/({inp})" if out in ("", "1") else f"({out})/({inp})"


def rules_text(model, precision: int = 4) -> str:
    """The rules in words, one per line, numbers with ``precision`` significant digits."""
    offsets = np.searchsorted(model.mf_input_, np.arange(model.n_features_in_))
    out = model.output_name
    lines = [
        f"{model.n_rules_} first-order Takagi-Sugeno rules, membership mu(x) = exp(-(x - c)^2 / (2 sigma^2)); "
        f"{out} in {model.output_units}; inputs: "
        + ", ".join(f"{n} in {u}" for n, u in zip(model.input_names_, model.input_units_, strict=True))
    ]

    def num(v: float) -> str:
        return f"{v:.{precision}g}"

    for r, mfs in enumerate(model.rule_mf_):
        conds = []
        for i, m in enumerate(mfs):
            u = _unit_suffix(model.input_units_[i])
            conds.append(
                f"{model.input_names_[i]} is MF{m - offsets[i] + 1} "
                f"(c = {num(model.centres_[m])}{u}, sigma = {num(model.sigmas_[m])}{u})"
            )
        coef = model.consequents_[r]
        expr = f"{num(coef[0])}*{model.input_names_[0]}"
        for i in range(1, model.n_features_in_):
            expr += f" {'-' if coef[i] < 0 else '+'} {num(abs(coef[i]))}*{model.input_names_[i]}"
        expr += f" {'-' if coef[-1] < 0 else '+'} {num(abs(coef[-1]))}"
        lines.append(f"Rule {r + 1}: IF " + " AND ".join(conds) + f" THEN {out} = {expr}")
    return "\n".join(lines)


def _coords(model) -> dict:
    d = model.n_features_in_
    return {
        "input": ("input", np.arange(1, d + 1), {"long_name": "input number", "units": "1"}),
        "input_name": (
            "input",
            np.array(model.input_names_, dtype=object),
            {"long_name": "input variable name", "units": "1"},
        ),
        "input_units": (
            "input",
            np.array(model.input_units_, dtype=object),
            {"long_name": "units of each input", "units": "1"},
        ),
        "rule": ("rule", np.arange(1, model.n_rules_ + 1), {"long_name": "rule number", "units": "1"}),
        "epoch": (
            "epoch",
            np.arange(1, model.train_rmse_.size + 1),
            {"long_name": "training epoch number", "units": "1"},
        ),
    }


def _input_variables(model, i: int) -> dict:
    """The MF variables, training range and consequent coefficient of input i, in its units."""
    name, unit = model.input_names_[i], model.input_units_[i]
    sel = model.mf_input_ == i
    out = {}
    for var, values, what in [
        ("mf_centre", model.centres_, "centre c"),
        ("mf_sigma", model.sigmas_, "width sigma"),
        ("mf_centre_initial", model.initial_centres_, "initial centre c"),
        ("mf_sigma_initial", model.initial_sigmas_, "initial width sigma"),
    ]:
        long_name = f"{what} of the Gaussian membership functions of input {name}"
        out[f"{var}_{i}"] = (f"mf_{i}", values[sel], {"long_name": long_name, "units": unit})
    out[f"input_range_{i}"] = (
        "bound",
        model.input_range_[i],
        {"long_name": f"training range (min, max) of input {name}; predict clamps to it", "units": unit},
    )
    out[f"consequent_{i}"] = (
        "rule",
        model.consequents_[:, i],
        {
            "long_name": f"consequent coefficient of input {name} in each rule",
            "units": _ratio_units(model.output_units, unit),
        },
    )
    return out


def to_dataset(model) -> xr.Dataset:
    """The fitted model as an xarray.Dataset (original units; one set of MF variables per input).

    Per input i: ``mf_centre_i``, ``mf_sigma_i`` (and ``*_initial_i``) along ``mf_i``,
    ``input_range_i`` (min, max) and the consequent coefficient ``consequent_i`` along ``rule``,
    each in its own units; ``consequent_constant``, ``rule_mf`` (1-based MF numbers), per-epoch
    ``train_rmse``, ``val_rmse`` (if validated) and ``step_size``. Hyper-parameters are the
    JSON text attribute ``hyperparameters``.
    """
    d, out_u, out = model.n_features_in_, model.output_units, model.output_name
    offsets = np.searchsorted(model.mf_input_, np.arange(d))
    ds = xr.Dataset(coords=_coords(model))
    ds["rule_mf"] = (
        ("rule", "input"),
        (model.rule_mf_ - offsets + 1).astype(np.int32),
        {"long_name": "membership function number (1-based, per input) used by each rule", "units": "1"},
    )
    for i in range(d):
        ds = ds.assign(_input_variables(model, i))
    constant = {"long_name": "consequent constant term of each rule", "units": out_u}
    ds["consequent_constant"] = ("rule", model.consequents_[:, -1], constant)
    ds["train_rmse"] = ("epoch", model.train_rmse_, {"long_name": f"training RMSE of {out}", "units": out_u})
    if model.val_rmse_.size:
        ds["val_rmse"] = ("epoch", model.val_rmse_, {"long_name": f"validation RMSE of {out}", "units": out_u})
    step = {"long_name": "premise step size as a fraction of the input ranges", "units": "1"}
    ds["step_size"] = ("epoch", model.step_sizes_, step)
    ds.attrs = {
        "title": "ANFIS model: first-order Takagi-Sugeno rules, Gaussian membership functions",
        "model": "y = sum_r w_r f_r / sum_r w_r, w_r = prod_i exp(-(x_i - c)^2 / (2 sigma^2)), "
        "f_r = sum_i consequent_i x_i + consequent_constant; inputs clamped to input_range_i",
        "output_name": out,
        "output_units": out_u,
        "best_epoch": int(model.best_epoch_),
        "hyperparameters": json.dumps(model.get_params(), default=json_default),
    }
    return ds


def fitted_arrays(ds: xr.Dataset) -> dict:
    """The fitted attributes of an ANFIS (``n_features_in_``, ``input_range_``, ``centres_``, ...) from
    ``to_dataset`` output, by attribute name; the rules' MF indices (``rule_mf_``) count over all inputs' MFs."""
    names = [str(v) for v in ds["input_name"].values]
    d = len(names)
    sizes = [ds.sizes[f"mf_{i}"] for i in range(d)]
    offsets = np.cumsum([0] + sizes[:-1])

    def joined(var: str) -> np.ndarray:
        return np.concatenate([np.asarray(ds[f"{var}_{i}"].values, float) for i in range(d)])

    coefs = [np.asarray(ds[f"consequent_{i}"].values, float) for i in range(d)]
    return {
        "n_features_in_": d,
        "input_names_": names,
        "input_units_": [str(v) for v in ds["input_units"].values],
        "input_range_": np.stack([np.asarray(ds[f"input_range_{i}"].values, float) for i in range(d)]),
        "mf_input_": np.repeat(np.arange(d), sizes),
        "rule_mf_": np.asarray(ds["rule_mf"].values, dtype=np.int64) - 1 + offsets,
        "centres_": joined("mf_centre"),
        "sigmas_": joined("mf_sigma"),
        "initial_centres_": joined("mf_centre_initial"),
        "initial_sigmas_": joined("mf_sigma_initial"),
        "consequents_": np.column_stack(coefs + [np.asarray(ds["consequent_constant"].values, float)]),
        "train_rmse_": np.asarray(ds["train_rmse"].values, float),
        "val_rmse_": np.asarray(ds["val_rmse"].values, float) if "val_rmse" in ds else np.array([]),
        "step_sizes_": np.asarray(ds["step_size"].values, float),
        "best_epoch_": int(ds.attrs["best_epoch"]),
    }


def from_dataset(cls, ds: xr.Dataset):
    """Rebuild a fitted ``cls`` (ANFIS) from ``to_dataset`` output, without its incidence matrix."""
    model = cls(**json.loads(ds.attrs["hyperparameters"]))
    for name, value in fitted_arrays(ds).items():
        setattr(model, name, value)
    return model
