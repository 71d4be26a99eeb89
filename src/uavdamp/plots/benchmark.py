"""Benchmark figures: controllers x criteria (mean and worst over the evaluation set), and box plots over scenarios."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402


def criteria_figure(ds: xr.Dataset, damper: str = "ideal"):
    """Heat maps of log10 J (controllers x criteria): evaluation mean and worst, one column per stiffness."""
    ks = ds.stiffness.values
    size = (min(16.0, 5.5 * ks.size), 8.5)
    fig, axes = plt.subplots(2, ks.size, figsize=size, squeeze=False, constrained_layout=True)
    for col, k in enumerate(ks):
        for row, name in enumerate(("J_mean", "J_worst")):
            ax = axes[row, col]
            values = ds[name].sel(stiffness=k, damper=damper).transpose("controller", "criterion").values
            shown = np.log10(np.maximum(values, 10**-2.5))  # J = 0 (e.g. no unsharp frame) at the colour scale's end
            image = ax.imshow(shown, cmap="viridis_r", vmin=-2.5, vmax=0.5, aspect="auto")
            for (i, j), v in np.ndenumerate(values):
                ax.text(j, i, f"{v:.3g}", ha="center", va="center", fontsize=7, color="w" if v < 0.1 else "k")
            ax.set_xticks(range(ds.criterion.size), ds.criterion.values, rotation=35, ha="right", fontsize=8)
            ax.set_yticks(range(ds.controller.size), ds.controller.values, fontsize=8)
            ax.set_title(f"{'mean' if name == 'J_mean' else 'worst'} J, K = {k:g} N/m ({damper} damper)", fontsize=9)
    fig.colorbar(image, ax=axes, label="log10 J (J = 1: rigid mount)", shrink=0.6)
    return fig


def boxplot_figure(ds: xr.Dataset, criteria=("los_std", "blur_p95", "displacement_std"), damper: str = "ideal"):
    """Box plots of J over the evaluation scenarios per controller, one row per criterion, one column per K."""
    ks = ds.stiffness.values
    evaluation = ds.J.where(ds.set == "evaluation", drop=True).sel(damper=damper)
    fig, axes = plt.subplots(
        len(criteria),
        ks.size,
        figsize=(min(16.0, 6 * ks.size), min(11.5, 3.2 * len(criteria))),
        squeeze=False,
        constrained_layout=True,
    )
    names = [str(c) for c in ds.controller.values]
    for col, k in enumerate(ks):
        for row, criterion in enumerate(criteria):
            ax = axes[row, col]
            data = [evaluation.sel(stiffness=k, criterion=criterion, controller=c).values for c in names]
            ax.boxplot([d[np.isfinite(d)] for d in data], showfliers=True, medianprops={"color": "k", "lw": 1.5})
            ax.set_xticks(range(1, len(names) + 1), names, rotation=35, ha="right", fontsize=8)
            ax.set_yscale("log")
            ax.set_ylabel(f"J {criterion} (1; rigid = 1)")
            ax.set_title(f"K = {k:g} N/m, {evaluation.scenario.size} evaluation scenarios", fontsize=9)
    return fig


def ranking(ds: xr.Dataset, stiffness: float, criterion: str, damper: str) -> str:
    """The best two controllers on a criterion's evaluation mean J; for a frame-phase criterion, whether the lead
    exceeds the spread over the frame clock's phase (the leader's highest-phase mean below the runner-up's lowest)."""
    at = {"stiffness": stiffness, "damper": damper}
    mean = ds.J_mean.sel(criterion=criterion, **at).to_series().drop("rigid", errors="ignore").dropna().sort_values()
    if mean.size < 2:
        return f"{criterion}: fewer than two controllers"
    first, second = mean.index[:2]
    text = f"{criterion}: {first} {mean.iloc[0]:.3g} < {second} {mean.iloc[1]:.3g}"
    if "phased" in ds.dims and criterion in ds.phased.values:
        high = float(ds.J_high_mean.sel(phased=criterion, controller=first, **at))
        low = float(ds.J_low_mean.sel(phased=criterion, controller=second, **at))
        verdict = "beyond the frame-phase spread" if high < low else "within the frame-phase spread: no ranking"
        text += f" ({first} up to {high:.3g}, {second} from {low:.3g}: {verdict})"
    return text


def markdown_table(ds: xr.Dataset, damper: str = "ideal", criteria=None) -> str:
    """The README table: mean / worst J per controller and criterion over the evaluation set, per stiffness; a
    frame-phase criterion also gives [lowest - highest phase] means; then the leader per criterion (`ranking`)."""
    criteria = list(ds.criterion.values) if criteria is None else list(criteria)
    phased = list(ds.phased.values) if "phased" in ds.dims else []
    lines = []
    for k in ds.stiffness.values:
        lines += [
            f"K = {k:g} N/m, {damper} damper (mean / worst J over the evaluation set; J = 1: rigid; "
            "[..]: the frame-phase spread of the mean; '-': not run, see tuned_on)",
            "",
            "| controller | " + " | ".join(criteria) + " |",
            "|---" * (len(criteria) + 1) + "|",
        ]
        for c in ds.controller.values:
            cells = []
            for x in criteria:
                at = {"controller": c, "stiffness": k, "damper": damper}
                cell = f"{float(ds.J_mean.sel(criterion=x, **at)):.3g} / {float(ds.J_worst.sel(criterion=x, **at)):.3g}"
                if x in phased:
                    low, high = (float(ds[v].sel(phased=x, **at)) for v in ("J_low_mean", "J_high_mean"))
                    cell += f" [{low:.3g}-{high:.3g}]"
                cells.append(cell)
            lines.append(f"| {c} | " + " | ".join(cells) + " |")
        lines += ["", *(f"- {ranking(ds, k, x, damper)}" for x in criteria), ""]
    if "tuned_on" in ds.coords:
        tuned = {
            str(c): sorted({str(v) for v in ds.tuned_on.sel(controller=c).values} - {""}) for c in ds.controller.values
        }
        lines += [
            "Tuned on (per criterion family): " + "; ".join(f"{c}: {', '.join(v)}" for c, v in tuned.items() if v),
            "",
        ]
    return "\n".join(lines)
