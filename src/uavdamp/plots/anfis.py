"""ANFIS figures: membership functions before and after training, error curves, predicted vs reference,
the cross-validated structures (rules against error, the one-SE choice) and the comparison with the baselines."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from uavdamp.anfis.damping import DampingModel
from uavdamp.plots.style import plain_log_ticks

MARKERS = {"grid": "s", "fcm": "o", "subtractive": "^"}
FEW = 12  # up to this many MFs per input, the ordered panel names each MF and the top one draws the initial MFs
ORDER_CMAP = "viridis"  # the trained MFs' colours, along the order of their centres


def _axis(model, i: int):
    """(x in the learnt unit over the training range, x in the input's unit, axis label, log axis?) for input i."""
    est = model.anfis
    lo, hi = est.input_range_[i]
    x = np.linspace(lo, hi, 400) if hi > lo else np.linspace(lo - 1, hi + 1, 400)
    if i == 2 and model.log_stiffness:
        return x, 10**x, "K (N/m)", True
    unit = est.input_units_[i]
    return x, x, f"{est.input_names_[i]}{'' if unit in ('', '1') else f' ({unit})'}", False


def _rank_colours(centres: np.ndarray) -> np.ndarray:
    """One colour per MF along ORDER_CMAP by the rank of its centre (lowest centre: the map's start)."""
    rank = np.argsort(np.argsort(centres, kind="stable"), kind="stable")
    return plt.get_cmap(ORDER_CMAP)(0.9 * rank / max(centres.size - 1, 1))  # not its last, pale yellow


def _curves(ax, x, shown, centres, sigmas, style: dict, colours=None) -> None:
    for k, (c, s) in enumerate(zip(centres, sigmas, strict=True)):
        colour = {} if colours is None else {"color": colours[k]}
        ax.plot(shown, np.exp(-((x - c) ** 2) / (2 * s**2)), **style, **colour)


def _ordered(ax, model, i: int, after, before) -> None:
    """Each MF as its centre and one-sigma band (trained, the band in its curve's colour) and initial centre
    (grey), ordered by trained centre."""
    (c1, s1), (c0, _) = after, before
    order = np.argsort(c1, kind="stable")
    rank = np.arange(order.size)
    shown = (lambda v: 10**v) if (i == 2 and model.log_stiffness) else (lambda v: v)
    colours = _rank_colours(c1)[order]
    ax.hlines(rank, shown(c1[order] - s1[order]), shown(c1[order] + s1[order]), colors=colours, lw=2, alpha=0.8)
    ax.plot(shown(c1[order]), rank, "|", color="k", ms=8, label="trained: centre, one-sigma band")
    ax.plot(shown(c0[order]), rank, "o", mfc="none", color="0.45", ms=4, label="initial centre")
    if order.size <= FEW:
        ax.set_yticks(rank, [f"MF{k + 1}" for k in order], fontsize=7)
    ax.set_ylim(-0.7, order.size - 0.3)
    ax.set_ylabel("MFs ordered by centre")


def _membership_panel(ax, x, shown, after, before, label: str) -> None:
    """The trained MFs, coloured along ORDER_CMAP by centre (thin where more than FEW), and the initial ones
    (dashed grey) where there are at most FEW: beyond that the ordered panel below shows their centres."""
    count = after[0].size
    crowded = count > FEW
    if not crowded:
        _curves(ax, x, shown, *before, {"ls": "--", "lw": 0.8, "color": "0.55", "alpha": 0.8})
    width = 0.8 if crowded else 1.4
    _curves(ax, x, shown, *after, {"ls": "-", "lw": width, "alpha": 0.9}, colours=_rank_colours(after[0]))
    note = " (initial: centres below)" if crowded else ""
    ax.set(ylabel="membership", ylim=(0, 1.05), title=f"{label}: {count} MF{'s' if count > 1 else ''}{note}")


def membership_figure(model):
    """Per input: the MFs after training (coloured by the order of their centre) and before (dashed, where at most
    FEW), and each MF's centre and width ordered by centre.

    ``model``: a DampingModel (K in N/m on a log axis where learnt as log10 K) or a bare ANFIS. No per-MF legend:
    readable at 2 MFs and at 65. Grey: outside the training range (inputs are clamped to it), shown where a centre
    left it."""

    model = model if isinstance(model, DampingModel) else DampingModel(model, False, False)
    est = model.anfis
    n = est.n_features_in_
    fig, axes = plt.subplots(2, n, figsize=(4.3 * n, 6.4), constrained_layout=True, squeeze=False)
    before, after = est.membership_functions(initial=True), est.membership_functions()
    for i in range(n):
        x, shown, label, log = _axis(model, i)
        top, bottom = axes[0, i], axes[1, i]
        _membership_panel(top, x, shown, after[i], before[i], label)
        _ordered(bottom, model, i, after[i], before[i])
        centres = np.concatenate([after[i][0], before[i][0]])
        span = x[-1] - x[0]
        lo, hi = min(x[0], centres.min() - 0.03 * span), max(x[-1], centres.max() + 0.03 * span)
        for ax in (top, bottom):
            ax.set_xlabel(label)
            if log:
                ax.set_xscale("log")
            limits = (10**lo, 10**hi) if log else (lo, hi)
            ax.set_xlim(*limits)
            for a, b in ((limits[0], shown[0]), (shown[-1], limits[1])):  # outside the training range: clamped
                if b > a:
                    ax.axvspan(a, b, color="0.9", zorder=0)
    axes[0, 0].plot([], [], color=plt.get_cmap(ORDER_CMAP)(0.5), label="trained (colour: centre order)")
    if any(mf[0].size <= FEW for mf in after):  # initial MFs drawn somewhere
        axes[0, 0].plot([], [], ls="--", color="0.55", label="initial")
    axes[0, 0].legend(fontsize=7, loc="lower left")
    axes[1, 0].legend(fontsize=7, loc="lower right")
    return fig


def training_figure(record: xr.Dataset):
    """Left: training and epoch-selection RMSE per epoch, kept epoch marked. Right: predicted vs reference C."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    ax1.plot(record.epoch, record.train_rmse, label="training")
    chosen_on = "checking (MATLAB chkFIS)" if record.attrs["epoch_selection"] == "checking" else "validation"
    ax1.plot(record.epoch, record.validation_rmse, label=chosen_on)
    ax1.axvline(record.attrs["best_epoch"], color="k", ls=":", lw=0.8, label="kept epoch")
    ax1.set(
        xlabel="epoch",
        ylabel=f"RMSE ({record.train_rmse.attrs['units']})",
        title="ANFIS hybrid learning: " + record.train_rmse.attrs["long_name"].replace("training RMSE of ", ""),
    )
    ax1.legend()
    train = record.is_training.values == 1
    ref, pred = record.damping_reference.values, record.damping_predicted.values
    ax2.loglog(ref[train], pred[train], "o", ms=3, alpha=0.6, label="training")
    ax2.loglog(ref[~train], pred[~train], "s", ms=4, alpha=0.8, label="checking")
    lims = [min(ref.min(), pred.min()), max(ref.max(), pred.max())]
    ax2.plot(lims, lims, "k--", lw=0.8)
    scores = [f"median relative error {record.attrs['check_median_relative_error']:.0%}"]
    if "check_regret_mean" in record.attrs:
        scores.append(f"mean regret {record.attrs['check_regret_mean']:.3f}")
    title = "checking rows:\n" + ", ".join(scores)  # two lines: one would overrun the panel's width
    ax2.set(xlabel="reference optimal C (N s/m)", ylabel="ANFIS C (N s/m)", title=title)
    ax2.legend()
    return fig


def _by_init(ax, record: xr.Dataset, y, yerr=None) -> None:
    """One point per candidate at (rules, y), one marker per init; the chosen candidate ringed."""
    labels = [str(v) for v in record.candidate_label.values]
    rules, inits, y = record.n_rules.values, np.array([lab.split()[0] for lab in labels]), np.asarray(y)
    for k, init in enumerate(MARKERS):
        pick = inits == init
        err = None if yerr is None else np.asarray(yerr)[pick]
        if pick.any():
            ax.errorbar(rules[pick], y[pick], yerr=err, fmt=MARKERS[init], color=f"C{k}", capsize=3, label=init)
    chosen = labels.index(record.attrs["selected_candidate"])
    ax.plot(rules[chosen], y[chosen], "o", ms=14, mfc="none", mec="k", mew=1.5, label="selected")
    ax.set_xscale("log")
    ticks = [t for t in (1, 2, 4, 8, 16, 32, 64, 128, 256, 512) if rules.min() / 1.5 <= t <= rules.max() * 1.5]
    ax.set_xticks(ticks, [str(t) for t in ticks])
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.set_xlabel("rules (mean over the folds' models)")


def _candidates(axes, record: xr.Dataset) -> None:
    unit = record.cv_rmse.attrs["units"]
    ax = axes[0]
    _by_init(ax, record, record.cv_rmse_mean.values, record.cv_rmse_se.values)
    ax.axhline(record.attrs["one_se_threshold"], color="k", ls="--", lw=0.8, label="best + 1 SE")
    chosen = record.attrs["selected_candidate"]
    ax.set(
        ylabel=f"CV RMSE ({unit}), bars: standard error",
        title=f"{record.attrs['cv_folds']}-fold CV: {chosen} ({record.attrs['selection_rule']})",
    )
    ax.legend(fontsize=7)
    if "cv_regret_mean" in record:
        ax = axes[1]
        inits = np.array([str(v).split()[0] for v in record.candidate_label.values])
        worst = record.cv_regret_max.values - 1
        for k, init in enumerate(MARKERS):
            pick = inits == init
            ax.plot(record.n_rules.values[pick], worst[pick], MARKERS[init], mfc="none", color=f"C{k}")
        _by_init(ax, record, record.cv_regret_mean.values - 1)
        ax.plot([], [], "o", mfc="none", color="0.3", label="worst (hollow)")
        ax.set_yscale("log")
        ax.set(ylabel="CV regret - 1 (log): mean (filled), worst (hollow)", title="regret on the folds' held-out rows")
        ax.legend(fontsize=7)


def _regret_points(ax, record: xr.Dataset, colours: list[str]) -> None:
    """Checking regret - 1 per model as points (mean filled, max hollow): a log axis where they span more than a
    decade, else a linear one from 0 (points, not bars: a bar on a log axis has no base)."""
    mean, worst = record.check_regret_mean.values - 1, record.check_regret_max.values - 1
    xm = np.arange(mean.size)
    for x, m, w, c in zip(xm, mean, worst, colours, strict=True):
        ax.plot(x, m, "o", color=c, ms=8, ls="none")
        ax.plot(x, w, "v", mfc="none", mec=c, mew=1.5, ms=8, ls="none")
    ax.plot([], [], "o", color="0.4", ls="none", label="mean")
    ax.plot([], [], "v", mfc="none", mec="0.4", mew=1.5, ls="none", label="max")
    ax.set_xlim(-0.5, mean.size - 0.5)
    shown = np.concatenate([mean, worst])
    shown = shown[np.isfinite(shown) & (shown > 0)]
    log = bool(shown.size) and shown.max() / shown.min() > 10
    if log:
        ax.set_yscale("log")
        ax.margins(y=0.15)
        plain_log_ticks(ax)
    else:
        ax.set_ylim(0, 1.25 * float(shown.max()) if shown.size else 1.0)
    scale = "log; " if log else ""
    ax.set(ylabel=f"regret - 1 ({scale}regret = criterion / optimal)", title="checking rows: regret")
    ax.legend(fontsize=8, loc="best")


def _models(axes, record: xr.Dataset) -> None:
    models = [str(v) for v in record.model.values]
    xm = np.arange(len(models))
    colours = ["C1" if m == "anfis" else "C7" for m in models]
    ax = axes[0]
    ax.bar(xm, record.check_rmse_target, color=colours)
    ax.set_xticks(xm, models)
    ax.set(ylabel=f"RMSE ({record.check_rmse_target.attrs['units']})", title="checking rows: learnt target")
    if "check_regret_mean" in record:
        _regret_points(axes[1], record, colours)
        axes[1].set_xticks(xm, models)


def selection_figure(record: xr.Dataset):
    """Top: every candidate's rules against CV RMSE (bars: SE, the one-SE line, the chosen one ringed) and CV
    regret. Bottom: checking RMSE and regret (mean, max) of the ANFIS and the baselines."""
    fig, axes = plt.subplots(2, 2, figsize=(11, 8), constrained_layout=True)
    _candidates(axes[0], record)
    _models(axes[1], record)
    for ax in axes.ravel():
        if not ax.has_data():
            ax.set_axis_off()
    return fig
