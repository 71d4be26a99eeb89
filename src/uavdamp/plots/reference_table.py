"""Reference-table figures: optimal damping over (f_y, f_z) per stiffness, and how flat the criterion is."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402


def reference_table_figure(table: xr.Dataset):
    """Row 1: damping_opt heatmaps, one per stiffness. Row 2: flat band damping_flat_max /
    damping_flat_min (1 = sharp optimum). Right: spread of damping_opt and scheduling gain vs K."""
    stiffness = table.stiffness.values
    n = stiffness.size
    fig = plt.figure(figsize=(3.0 * n + 4.0, 6.5), constrained_layout=True)
    grid = fig.add_gridspec(2, n + 1, width_ratios=[1] * n + [1.4])
    c = table.damping_opt
    c_norm = LogNorm(vmin=float(c.min()), vmax=float(c.max())) if float(c.min()) > 0 else None
    flat = table.damping_flat_max / table.damping_flat_min
    f_norm = LogNorm(vmin=1.0, vmax=max(float(flat.max()), 1.01))
    extent = [float(table.freq_z[0]), float(table.freq_z[-1]), float(table.freq_y[0]), float(table.freq_y[-1])]
    for j, k in enumerate(stiffness):
        for row, (data, norm, label) in enumerate(
            ((c, c_norm, "optimal C (N s/m)"), (flat, f_norm, "flat band: C_max / C_min within tolerance"))
        ):
            ax = fig.add_subplot(grid[row, j])
            im = ax.imshow(
                data.sel(stiffness=k).values,
                origin="lower",
                aspect="auto",
                extent=extent,
                norm=norm,
                cmap="viridis" if row == 0 else "magma",
            )
            ax.set(xlabel="f_z (Hz)", ylabel="f_y (Hz)" if j == 0 else None, title=f"K = {k:.3g} N/m")
            if j == n - 1:
                fig.colorbar(im, ax=ax, label=label)
    ax = fig.add_subplot(grid[:, n])
    ax.semilogx(stiffness, table.damping_opt_spread, "o-", label="spread of optimal C (max/min)")
    ax.semilogx(stiffness, table.scheduling_gain, "s-", label="scheduling gain (best constant C / optimal C)")
    ax.axhline(1.0, color="k", lw=0.8, ls=":")
    ax.set(xlabel="isolator stiffness K (N/m)", ylabel="ratio (1)", title="where frequency-scheduled damping can help")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    return fig


def criteria_figure(table: xr.Dataset):
    """Optimal C per criterion side by side: columns (criterion, window), rows stiffness; one log colour scale.

    Both windows are drawn (transient: from rest, the paper's; steady: after the start-up), since where the
    two disagree the start-up, not the steady response, sets the optimum. Each panel's title gives the
    scheduling gain of its criterion, window and K; the chosen one (table attrs) is marked."""
    criteria, windows, stiffness = (table[name].values for name in ("criterion", "window", "stiffness"))
    columns = [(str(c), str(w)) for c in criteria for w in windows]
    c = table.damping_opt
    finite = c.values[np.isfinite(c.values) & (c.values > 0)]
    norm = LogNorm(vmin=float(finite.min()), vmax=float(finite.max())) if finite.size else None
    extent = [float(table.freq_z[0]), float(table.freq_z[-1]), float(table.freq_y[0]), float(table.freq_y[-1])]
    chosen = (table.attrs.get("criterion"), table.attrs.get("window"))
    size = (2.4 * len(columns) + 1.2, 2.0 * stiffness.size + 0.8)
    fig, axes = plt.subplots(
        stiffness.size, len(columns), figsize=size, squeeze=False, sharex=True, sharey=True, constrained_layout=True
    )
    for j, (name, window) in enumerate(columns):
        part = table.sel(criterion=name, window=window)
        for i, k in enumerate(stiffness):
            ax = axes[i, j]
            im = ax.imshow(
                part.damping_opt.sel(stiffness=k).values,
                origin="lower",
                aspect="auto",
                extent=extent,
                norm=norm,
                cmap="viridis",
            )
            gain = float(part.scheduling_gain.sel(stiffness=k))
            ax.set_title(f"K {k:.3g} N/m, gain {gain:.2f}", fontsize=7)
            ax.tick_params(labelsize=6)
            if i == 0:
                mark = " (learnt)" if (name, window) == chosen else ""
                ax.set_title(f"{name}, {window}{mark}\n" + ax.get_title(), fontsize=8)
            if i == stiffness.size - 1:
                ax.set_xlabel("f_z (Hz)", fontsize=7)
            if j == 0:
                ax.set_ylabel("f_y (Hz)", fontsize=7)
    fig.colorbar(im, ax=axes, label="optimal constant C (N s/m)", shrink=0.6)
    fig.suptitle("Optimal damping per criterion and window (gain: scheduling gain, best constant C / optimal C)")
    return fig
