"""The payload table's figure (`uavdamp.study.payload_table`): what the six-axis isolator's best damping depends on
for the gimbal, and what scheduling it by frequency could buy."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from uavdamp.plots.style import number, plain_log_ticks  # noqa: E402

DOF_TITLES = {"x": "mount x (fore-aft)", "y": "mount y", "z": "mount z", "rx": "mount roll", "ry": "mount pitch"}
DOF_TITLES["rz"] = "mount yaw"
BAND_COLORS = ("0.85", "#dbe9f6", "#f6e3db")


def _shade_bands(ax, table: xr.Dataset) -> None:
    for k, band in enumerate(table.band.values):
        low, high = float(table.band_low.sel(band=band)), float(table.band_high.sel(band=band))
        ax.axvspan(low, high, color=BAND_COLORS[k % len(BAND_COLORS)], alpha=0.6, lw=0, zorder=0)


def table_figure(table: xr.Dataset, default_stiffness: float) -> Figure:
    """Per mount DOF with a line of sight (columns): top, the best C (N s/m) against the sine's frequency per
    element stiffness K (colour; the default K thick, its rigid-body modes as ticks); bottom, the line of sight at
    the band's best constant C over that at the best C (1: scheduling C by frequency buys nothing), per band
    (shaded). The titles give the default K's scheduling gain per band."""
    dofs = [str(d) for d in table.dof.values if np.isfinite(table.scheduling_gain.sel(dof=d)).any()]
    fig = Figure(figsize=(4.6 * max(len(dofs), 1), 7.4), layout="constrained")
    axes = fig.subplots(2, max(len(dofs), 1), sharex=True, squeeze=False)
    f, ks = table.freq.values, table.stiffness.values
    colors = matplotlib.colormaps["viridis"](np.linspace(0.0, 0.85, ks.size))
    for col, dof in enumerate(dofs):
        top, bottom = axes[0, col], axes[1, col]
        for ax in (top, bottom):
            _shade_bands(ax, table)
        for j, k in enumerate(ks):
            width = 2.6 if np.isclose(k, default_stiffness) else 1.2
            label = f"K = {number(k)} N/m per element (z)"
            top.step(
                f, table.damping_opt.sel(dof=dof, stiffness=k), where="mid", color=colors[j], lw=width, label=label
            )
            for band in table.band.values:
                ratio = table.criterion_best_constant.sel(dof=dof, stiffness=k, band=band) / table.criterion_opt.sel(
                    dof=dof, stiffness=k
                )
                bottom.plot(f, ratio, color=colors[j], lw=width)
        if default_stiffness in ks:
            for mode in table.mode_frequency.sel(stiffness=default_stiffness).values:
                top.axvline(mode, ymin=0.93, ymax=1.0, color="k", lw=1.5)
        gains = ", ".join(
            f"{band} {float(table.scheduling_gain.sel(dof=dof, stiffness=default_stiffness, band=band)):.2f}"
            for band in table.band.values
        )
        top.set_title(f"{DOF_TITLES.get(dof, dof)}\nscheduling gain, default K:\n{gains}", fontsize=10)
        top.set(yscale="log", ylabel="best C per element (N s/m)")
        bottom.set(yscale="log", xlabel="frequency of the mount's sine (Hz)")
        bottom.set_ylabel("LOS, band's best constant C / best C")
        for ax in (top, bottom):
            ax.set_xscale("log")
            ax.grid(True, which="both", alpha=0.3)
            plain_log_ticks(ax, "x")
        plain_log_ticks(bottom, "y")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside right upper", fontsize=8, title="element stiffness")
    bands = "; ".join(
        f"{b}: {number(float(table.band_low.sel(band=b)))}-{number(float(table.band_high.sel(band=b)))} Hz"
        for b in table.band.values
    )
    fig.suptitle(
        "Gimbal on the six-axis isolator: the best damping per mount sine (steady state, closed form)\n"
        f"bands shaded ({bands}); ticks: the default K's rigid-body modes",
        fontsize=11,
    )
    return fig
