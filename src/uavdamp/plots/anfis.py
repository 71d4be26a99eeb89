"""ANFIS figures: membership functions before and after training, error curves, predicted vs reference,
cross-validated structure selection and the comparison with the baselines."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402


def membership_figure(model):
    """One panel per input: Gaussian MFs before (dashed) and after (solid) training."""
    n = len(model.input_names_)
    fig, axes = plt.subplots(1, n, figsize=(4.2 * n, 3.4), constrained_layout=True, squeeze=False)
    before, after = model.membership_functions(initial=True), model.membership_functions()
    for i, ax in enumerate(axes[0]):
        lo, hi = model.input_range_[i]
        x = np.linspace(lo, hi, 400) if hi > lo else np.linspace(lo - 1, hi + 1, 400)
        pairs = zip(zip(*before[i], strict=True), zip(*after[i], strict=True), strict=True)
        for k, ((c0, s0), (c1, s1)) in enumerate(pairs):
            (line,) = ax.plot(x, np.exp(-((x - c1) ** 2) / (2 * s1**2)), lw=1.6, label=f"MF{k + 1}")
            ax.plot(x, np.exp(-((x - c0) ** 2) / (2 * s0**2)), ls="--", lw=1.0, color=line.get_color())
        ax.set(
            xlabel=f"{model.input_names_[i]} ({model.input_units_[i]})",
            ylabel="membership",
            ylim=(0, 1.05),
            title=f"{model.input_names_[i]}: before (dashed), after (solid)",
        )
        ax.legend(fontsize=7)
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
    title = f"checking: median relative error {record.attrs['check_median_relative_error']:.0%}"
    if "check_regret_mean" in record.attrs:
        title += f", mean regret {record.attrs['check_regret_mean']:.3f}"
    ax2.set(xlabel="reference optimal C (N s/m)", ylabel="ANFIS C (N s/m)", title=title)
    ax2.legend()
    return fig


def selection_figure(record: xr.Dataset):
    """Cross-validated RMSE per candidate; checking RMSE and regret (mean, max) per model."""
    with_regret = "check_regret_mean" in record
    fig, axes = plt.subplots(
        1, 3 if with_regret else 2, figsize=(14 if with_regret else 10, 4.2), constrained_layout=True
    )
    unit = record.cv_rmse.attrs["units"]
    labels = [str(v) for v in record.candidate_label.values]
    x = np.arange(len(labels))
    chosen = labels.index(record.attrs["selected_candidate"])
    ax = axes[0]
    ax.errorbar(x, record.cv_rmse_mean, yerr=record.cv_rmse_std, fmt="o", mfc="none", capsize=3, color="C0")
    ax.plot(x[chosen], record.cv_rmse_mean[chosen], "o", color="C0", label="selected")
    ax.set_xticks(x, labels, rotation=30, ha="right", fontsize=8)
    ax.set(ylabel=f"RMSE ({unit})", title=f"{record.attrs['cv_folds']}-fold CV on the training rows")
    ax.legend(fontsize=8)
    models = [str(v) for v in record.model.values]
    xm = np.arange(len(models))
    ax = axes[1]
    ax.bar(xm, record.check_rmse_target, color=["C1" if m == "anfis" else "C7" for m in models])
    ax.set_xticks(xm, models)
    ax.set(ylabel=f"RMSE ({record.check_rmse_target.attrs['units']})", title="checking rows: learnt target")
    if with_regret:
        ax = axes[2]
        ax.bar(
            xm,
            record.check_regret_mean - 1,
            bottom=1,
            color=["C1" if m == "anfis" else "C7" for m in models],
            label="mean",
        )
        ax.plot(xm, record.check_regret_max, "kv", label="max")
        ax.set_xticks(xm, models)
        ax.set(ylabel="criterion / optimal criterion", title="checking rows: regret")
        ax.legend(fontsize=8)
    return fig
