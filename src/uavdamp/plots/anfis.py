"""ANFIS figures: membership functions before and after training, error curves, predicted vs reference."""

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
        for k, ((c0, s0), (c1, s1)) in enumerate(zip(zip(*before[i]), zip(*after[i]))):
            line, = ax.plot(x, np.exp(-((x - c1) ** 2) / (2 * s1**2)), lw=1.6, label=f"MF{k + 1}")
            ax.plot(x, np.exp(-((x - c0) ** 2) / (2 * s0**2)), ls="--", lw=1.0, color=line.get_color())
        ax.set(xlabel=f"{model.input_names_[i]} ({model.input_units_[i]})", ylabel="membership", ylim=(0, 1.05),
               title=f"{model.input_names_[i]}: before (dashed), after (solid)")
        ax.legend(fontsize=7)
    return fig


def training_figure(record: xr.Dataset):
    """Left: training and checking RMSE per epoch, best epoch marked. Right: predicted vs reference C."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    ax1.plot(record.epoch, record.train_rmse, label="training")
    ax1.plot(record.epoch, record.check_rmse, label="checking")
    ax1.axvline(record.attrs["best_epoch"], color="k", ls=":", lw=0.8, label="kept epoch")
    ax1.set(xlabel="epoch", ylabel=f"RMSE ({record.train_rmse.attrs['units']})",
            title="ANFIS hybrid learning: " + record.train_rmse.attrs["long_name"].replace("training RMSE of ", ""))
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
