"""The rule base a person can read: each rule's membership functions in its input's units, its consequent, and how
often it fires on the reference table's cells, as a Markdown table (``rules_markdown``, also readable as text).

Units: f_y and f_z as the centre and width sigma of the Gaussian in Hz; K in N/m even when learnt as log10 K:
a Gaussian in log10 K of centre c and width s is centred on 10^c N/m and spans the factor 10^s either side
(its one-sigma band 10^(c - s) to 10^(c + s) N/m). The consequent is printed as learnt (log10 C where
``log_damping``), with C in N s/m at the rule's centre (clamped to the training range, as ``predict`` does) beside
it.

Firing, on the cells given (the table's): the share of cells where the rule has the largest firing strength, and
its mean normalised firing strength w_r / sum_s w_s (the share of the model's output the rule carries).
"""

from __future__ import annotations

import numpy as np

from uavdamp.anfis._math import _firing
from uavdamp.anfis.damping import DampingModel
from uavdamp.anfis.estimator import ANFIS


def firing_strengths(model: ANFIS, X) -> np.ndarray:
    """Normalised firing strengths (rules, n) at rows X of the model's (learnt) inputs, clamped as ``predict``."""
    model._check_fitted()
    X = np.asarray(X, float)
    XcT = np.ascontiguousarray(np.clip(X, model.input_range_[:, 0], model.input_range_[:, 1]).T)
    return _firing(XcT, model.centres_, model.sigmas_, model.mf_input_, model._incidence_)[1]


def _num(value: float, digits: int = 4) -> str:
    """``digits`` significant digits, positional (1530, not 1.53e+03)."""
    return np.format_float_positional(value, precision=digits, unique=False, fractional=False, trim="-")


def _membership(model: DampingModel, i: int, m: int, local: int) -> str:
    """MF m of input i in the input's units: 'MFk: c ± sigma' or, for log10 K, its centre and band in N/m."""
    c, s = model.anfis.centres_[m], model.anfis.sigmas_[m]
    if i == 2 and model.log_stiffness:
        return f"MF{local}: {_num(10**c, 3)} ({_num(10 ** (c - s), 3)} to {_num(10 ** (c + s), 3)})"
    return f"MF{local}: {_num(c, 3)} ± {_num(s, 2)}"


def _consequent(est: ANFIS, r: int) -> str:
    coef = est.consequents_[r]
    terms = [f"{_num(coef[0])} {est.input_names_[0]}"]
    terms += [
        f"{'-' if v < 0 else '+'} {_num(abs(v))} {n}" for v, n in zip(coef[1:-1], est.input_names_[1:], strict=True)
    ]
    return " ".join(terms) + f" {'-' if coef[-1] < 0 else '+'} {_num(abs(coef[-1]))}"


def _heading(model: DampingModel, est: ANFIS) -> list[str]:
    k_unit = "N/m: centre (one-sigma band; learnt as log10 K)" if model.log_stiffness else "N/m: centre ± sigma"
    columns = ["f_y (Hz: centre ± sigma)", "f_z (Hz: centre ± sigma)", f"K ({k_unit})"]
    return [
        "| rule | " + " | ".join(columns) + f" | THEN {est.output_name} = | C at the centre (N s/m, in range) "
        "| strongest on (% of cells) | mean weight (%) |",
        "|" + "---|" * (len(columns) + 5),
    ]


def rules_markdown(model: DampingModel, cells: np.ndarray, title: str = "ANFIS rule base") -> str:
    """The rule base of a fitted DampingModel as Markdown; firing shares on ``cells`` [f_y Hz, f_z Hz, K N/m]."""
    est = model.anfis
    w = firing_strengths(est, model.inputs(cells))
    strongest = np.bincount(np.argmax(w, axis=0), minlength=est.n_rules_) / w.shape[1]
    centre_inputs = np.clip(est.centres_[est.rule_mf_], est.input_range_[:, 0], est.input_range_[:, 1])
    at_centre = model.damping((est.consequents_[:, :-1] * centre_inputs).sum(axis=1) + est.consequents_[:, -1])
    offsets = np.searchsorted(est.mf_input_, np.arange(est.n_features_in_))
    lines = [
        f"# {title}",
        "",
        f"{est.n_rules_} first-order Takagi-Sugeno rules: IF f_y is MF AND f_z is MF AND K is MF THEN "
        f"{est.output_name} is the linear consequent; the output is the firing-weighted mean of the rules' "
        "consequents. Membership mu(x) = exp(-(x - centre)^2 / (2 sigma^2)), product AND; inputs are clamped to "
        "the training range " + ", ".join(_ranges(model)) + ".",
    ]
    if model.log_stiffness or model.log_damping:
        lines.append("In the consequents log10_K = log10(K / 1 N/m) and log10_C = log10(C / 1 N s/m).")
    lines += [
        f"Firing on the {w.shape[1]} table cells: *strongest on* is the share of cells where the rule has the largest "
        "firing strength, *mean weight* its mean normalised firing strength.",
        "",
        *_heading(model, est),
    ]
    for r, mfs in enumerate(est.rule_mf_):
        parts = [_membership(model, i, m, m - offsets[i] + 1) for i, m in enumerate(mfs)]
        lines.append(
            f"| {r + 1} | " + " | ".join(parts) + f" | {_consequent(est, r)} | {_num(at_centre[r], 3)} "
            f"| {100 * strongest[r]:.1f} | {100 * w[r].mean():.1f} |"
        )
    return "\n".join(lines) + "\n"


def _ranges(model: DampingModel) -> list[str]:
    est = model.anfis
    out = []
    for i, (lo, hi) in enumerate(est.input_range_):
        if i == 2 and model.log_stiffness:
            out.append(f"K {_num(10**lo, 3)} to {_num(10**hi, 3)} N/m")
        else:
            unit = est.input_units_[i]
            out.append(f"{est.input_names_[i]} {_num(lo, 3)} to {_num(hi, 3)}{'' if unit in ('', '1') else ' ' + unit}")
    return out
