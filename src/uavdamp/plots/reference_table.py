"""Reference-table figures: optimal damping over (f_y, f_z) per stiffness, and how flat the criterion is."""

from __future__ import annotations

import math
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402
from matplotlib.patches import Patch, Rectangle  # noqa: E402

from uavdamp.plots.style import number, plain_log_ticks, stiffness_label  # noqa: E402

GAIN_LABEL = "scheduling gain (best constant C / optimal C)"
SPREAD_LABEL = "spread of optimal C (max/min)"


def _extent(table: xr.Dataset) -> list[float]:
    return [float(table.freq_z[0]), float(table.freq_z[-1]), float(table.freq_y[0]), float(table.freq_y[-1])]


def _tolerance(table: xr.Dataset) -> str:
    """The flat band's tolerance as its long_name states it ("5%"), else "the tolerance"."""
    found = re.search(r"within (\S+) of", table.damping_flat_max.attrs.get("long_name", ""))
    return found.group(1) if found else "the tolerance"


def _heatmaps(subfig, data: xr.DataArray, stiffness, norm, cmap: str, extent, colour_label: str, title: str):
    """One heatmap per stiffness on a near-square grid of shared axes, one colour bar; returns the images."""
    ncols = math.ceil(math.sqrt(len(stiffness)))
    nrows = math.ceil(len(stiffness) / ncols)
    axes = subfig.subplots(nrows, ncols, sharex=True, sharey=True, squeeze=False)
    images = []
    for i, ax in enumerate(axes.flat):
        if i >= len(stiffness):
            ax.set_axis_off()
            continue
        k = stiffness[i]
        images.append(
            ax.imshow(data.sel(stiffness=k).values, origin="lower", aspect="auto", extent=extent, norm=norm, cmap=cmap)
        )
        ax.set_title(stiffness_label(k), fontsize=9)
        ax.tick_params(labelsize=8)
        if i // ncols == nrows - 1 or i + ncols >= len(stiffness):
            ax.set_xlabel("f_z (Hz)", fontsize=8)
            ax.tick_params(labelbottom=True)
        if i % ncols == 0:
            ax.set_ylabel("f_y (Hz)", fontsize=8)
    plain_log_ticks(subfig.colorbar(images[-1], ax=axes, label=colour_label, shrink=0.8).ax)
    subfig.suptitle(title, fontsize=10)
    return images


# `optimum_at_grid_edge` flags (uavdamp.reference_table.criteria.EDGE_ATTRS) -> hatch and legend entry
EDGE_HATCHES = {
    1: ("\\\\\\\\", "at the C grid's lowest value: a bound, not an optimum"),
    2: ("////", "at the C grid's highest value: a bound, not an optimum"),
    3: ("xx", "at the damper's own bound (a grid edge)"),
}


def _mark_grid_edges(images, flags: xr.DataArray, stiffness) -> list[Patch]:
    """Hatch each cell of the optimal-C `images` (one per stiffness) whose optimum lies on an edge of the C grid
    (black on light cells, white on dark ones); returns the legend handles of the flags found."""
    found = set()
    for image, k in zip(images, stiffness, strict=True):
        x0, x1, y0, y1 = image.get_extent()
        values, colours = flags.sel(stiffness=k).values, image.to_rgba(image.get_array())
        width, height = (x1 - x0) / values.shape[1], (y1 - y0) / values.shape[0]
        for (i, j), flag in np.ndenumerate(values):
            if int(flag) not in EDGE_HATCHES:
                continue
            found.add(int(flag))
            light = float(np.dot(colours[i, j, :3], (0.299, 0.587, 0.114))) > 0.5
            cell = Rectangle((x0 + j * width, y0 + i * height), width, height, fill=False, lw=0)
            cell.set(hatch=EDGE_HATCHES[int(flag)][0], edgecolor="k" if light else "w")
            image.axes.add_patch(cell)
    return [Patch(fc="0.75", ec="k", hatch=EDGE_HATCHES[f][0], label=EDGE_HATCHES[f][1]) for f in sorted(found)]


def reference_table_figure(table: xr.Dataset):
    """The table of one criterion and window at a glance, on a laptop screen.

    Top left: damping_opt heatmaps, one per stiffness (log colour). Top right: the flat band damping_flat_max /
    damping_flat_min (1 = sharp optimum; log colour). Bottom: the scheduling gain against K on its own linear
    axis (the key quantity: 1 = scheduling C by frequency buys nothing) and the spread of damping_opt on a log
    axis. The images come in the order (optimal C per K..., flat band per K...)."""
    stiffness = table.stiffness.values
    ncols = math.ceil(math.sqrt(stiffness.size))
    nrows = math.ceil(stiffness.size / ncols)
    fig = plt.figure(figsize=(min(15.5, 4.0 + 3.6 * ncols), 2.0 + 2.1 * nrows + 2.9), layout="constrained")
    top, bottom = fig.subfigures(2, 1, height_ratios=[2.0 + 2.1 * nrows, 2.9])
    left, right = top.subfigures(1, 2)
    c = table.damping_opt
    positive = c.values[np.isfinite(c.values) & (c.values > 0)]
    c_norm = LogNorm(vmin=float(positive.min()), vmax=float(positive.max())) if positive.size else None
    flat = table.damping_flat_max / table.damping_flat_min
    f_norm = LogNorm(vmin=1.0, vmax=max(float(flat.max()), 2.0))  # a colour bar from 1 to at least 2
    extent = _extent(table)
    what = f"{table.attrs.get('criterion', '')}, {table.attrs.get('window', '')} window".strip(", ")
    images = _heatmaps(
        left, c, stiffness, c_norm, "viridis", extent, "optimal C (N s/m)", f"optimal damping C ({what})"
    )
    if "optimum_at_grid_edge" in table:
        edges = _mark_grid_edges(images, table.optimum_at_grid_edge, stiffness)
        if edges:
            left.legend(
                handles=edges, loc="outside lower center", fontsize=7, title="hatched: optimal C", title_fontsize=7
            )
    _heatmaps(
        right,
        flat,
        stiffness,
        f_norm,
        "magma",
        extent,
        "C_max / C_min (1)",
        f"flat band: the C whose criterion is within {_tolerance(table)} of the optimum, C_max / C_min",
    )
    ax_gain, ax_spread = bottom.subplots(1, 2)
    ax_gain.semilogx(stiffness, table.scheduling_gain, "s-", color="tab:orange", label=GAIN_LABEL)
    ax_gain.axhline(1.0, color="k", lw=0.8, ls=":")
    best = int(np.nanargmax(table.scheduling_gain.values))
    ax_gain.annotate(
        f"{float(table.scheduling_gain[best]):.2f} at {stiffness_label(stiffness[best])}",
        (stiffness[best], float(table.scheduling_gain[best])),
        xytext=(8, -4) if best < stiffness.size - 1 else (-8, -4),
        textcoords="offset points",
        fontsize=8,
        va="top",
        ha="left" if best < stiffness.size - 1 else "right",
    )
    ax_gain.set(
        xlabel="isolator stiffness K (N/m)",
        ylabel="scheduling gain (1)",
        title="scheduling gain: criterion at the best constant C / at the optimal C (1: nothing to gain)",
    )
    ax_spread.loglog(stiffness, table.damping_opt_spread, "o-", color="tab:blue", label=SPREAD_LABEL)
    ax_spread.set(
        xlabel="isolator stiffness K (N/m)",
        ylabel="max / min of optimal C (1)",
        title="spread of the optimal C over the input frequencies",
    )
    for ax in (ax_gain, ax_spread):
        ax.title.set_fontsize(9)
        ax.grid(True, which="both", alpha=0.3)
        ax.set_xticks(stiffness, [number(k) for k in stiffness], fontsize=8, rotation=45 if stiffness.size > 6 else 0)
        ax.minorticks_off()
    plain_log_ticks(ax_spread)
    return fig


def criteria_figure(table: xr.Dataset):
    """Optimal C per criterion side by side: rows (criterion, window), columns stiffness; one log colour scale.

    Both windows are drawn (transient: from rest, the paper's; steady: after the start-up), since where the
    two disagree the start-up, not the steady response, sets the optimum. Each panel's title gives the
    scheduling gain of its criterion, window and K; the chosen one (table attrs) is marked."""
    criteria, windows, stiffness = (table[name].values for name in ("criterion", "window", "stiffness"))
    rows = [(str(c), str(w)) for c in criteria for w in windows]
    c = table.damping_opt
    finite = c.values[np.isfinite(c.values) & (c.values > 0)]
    norm = LogNorm(vmin=float(finite.min()), vmax=float(finite.max())) if finite.size else None
    extent = _extent(table)
    chosen = (table.attrs.get("criterion"), table.attrs.get("window"))
    size = (min(16.0, max(6.5, 2.2 + 1.55 * stiffness.size)), min(11.4, 1.1 + 1.7 * len(rows)))
    fig, axes = plt.subplots(
        len(rows), stiffness.size, figsize=size, squeeze=False, sharex=True, sharey=True, layout="constrained"
    )
    for i, (name, window) in enumerate(rows):
        part = table.sel(criterion=name, window=window)
        for j, k in enumerate(stiffness):
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
            title = f"gain {gain:.2f}"
            if i == 0:
                title = f"{stiffness_label(k)}\n" + title
            ax.set_title(title, fontsize=8)
            ax.tick_params(labelsize=7)
            if i == len(rows) - 1:
                ax.set_xlabel("f_z (Hz)", fontsize=8)
            if j == 0:
                mark = " (learnt)" if (name, window) == chosen else ""
                ax.set_ylabel(f"{name}\n{window}{mark}\nf_y (Hz)", fontsize=8)
    plain_log_ticks(fig.colorbar(im, ax=axes, label="optimal constant C (N s/m)", shrink=0.6).ax)
    fig.suptitle("Optimal damping per criterion and window\n(gain: scheduling gain, best constant C / optimal C)")
    return fig
