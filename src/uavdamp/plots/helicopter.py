"""Fuselage vibration figure: the analogue of the paper's Fig. 3, plus the spectra."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from uavdamp.plots.style import SPECTRUM_DYNAMIC_RANGE, clip_log_range, spread_labels  # noqa: E402


def fuselage_vibration_figure(ds: xr.Dataset, window_s: float = 5.0, mount: str | None = None):
    """Z and Y displacement of `mount` (default: the first mount point) over the first `window_s` seconds
    (imbalanced: solid blue, balanced: dotted red, as in the paper's Fig. 3) and their amplitude spectra, on a log
    axis from SPECTRUM_DYNAMIC_RANGE of the peak up (below lies numerical noise). One legend, beside the panels."""
    mount = str(ds.mount.values[0]) if mount is None else mount
    ds = ds.sel(mount=mount).rename(mount_displacement="displacement")
    fig, axes = plt.subplots(2, 2, figsize=(12, 6.5), layout="constrained")
    early = ds.sel(time=slice(0.0, window_s))
    for row, axis in enumerate(("z", "y")):
        ax = axes[row, 0]
        ax.plot(early.time, 1e3 * early.displacement.sel(rotor="imbalanced", axis=axis), "b-", lw=0.8)
        ax.plot(early.time, 1e3 * early.displacement.sel(rotor="balanced", axis=axis), "r:", lw=1.5)
        ax.set(
            xlabel="time (s)",
            ylabel=f"{axis.upper()} displacement (mm)",
            title=f"({'ab'[row]}) fuselage vibration, {axis.upper()} axis",
        )
        ax = axes[row, 1]
        spec = 1e3 * ds.amplitude_spectrum.sel(rotor="imbalanced", axis=axis)
        ax.semilogy(ds.omega, spec, "b-", lw=0.8)
        dominant = float(ds.dominant_omega.sel(rotor="imbalanced", axis=axis))
        ax.axvline(dominant, color="k", ls="--", lw=0.8, label=f"dominant {dominant:.2f} rad/s")
        ax.annotate(
            f"dominant\n{dominant:.2f} rad/s",
            (dominant, 1.0),
            xycoords=("data", "axes fraction"),
            xytext=(4, -4),
            textcoords="offset points",
            va="top",
            fontsize=8,
            bbox={"boxstyle": "round,pad=0.2", "fc": "w", "ec": "none", "alpha": 0.8},
        )
        shown = spec.sel(omega=slice(0, 120)).values
        if "hover" in ds.rotor.values:  # the flight run: trimmed hover with aerodynamics, gravity and pilot
            hover = 1e3 * ds.amplitude_spectrum.sel(rotor="hover", axis=axis)
            ax.semilogy(ds.omega, hover, "g-", lw=0.8)
            shown = np.concatenate([shown, hover.sel(omega=slice(0, 120)).values])
        clip_log_range(ax, shown, SPECTRUM_DYNAMIC_RANGE)
        ax.set(
            xlim=(0, 120),
            xlabel="angular frequency (rad/s)",
            ylabel="amplitude (mm)",
            title=f"{axis.upper()} spectrum, imbalanced rotor, {float(ds.time[-1]):.0f} s record",
        )
    handles = [
        Line2D([], [], color="b", lw=0.8, label="imbalanced rotor"),
        Line2D([], [], color="r", ls=":", lw=1.5, label="balanced rotor"),
        Line2D([], [], color="k", ls="--", lw=0.8, label="dominant line"),
    ]
    fig.legend(handles=handles, loc="outside right upper", fontsize=8)
    return fig


FAMILY_COLOURS = {"flap": "tab:blue", "lag": "tab:orange", "feather": "tab:green"}


def campbell_figure(ds: xr.Dataset, marks: dict[str, float] | None = None, max_harmonic: int = 4):
    """Campbell diagram: fixed-frame modal frequencies (rad/s) against rotor speed, with n/rev lines.

    Colour by the mode's dominant coordinate family at the nominal speed (flap, lag, feather, else fuselage).
    Mode labels sit in the right margin, moved apart so none overlaps another, with a leader line to the end of
    their curve. `marks` (label -> rad/s) are drawn at the nominal speed (default: the paper's fuselage peaks
    Y 44.04 and Z 50.58 rad/s) and named in the legend.
    """
    marks = {"paper Y peak 44.04": 44.04, "paper Z peak 50.58": 50.58} if marks is None else marks
    fig, ax = plt.subplots(figsize=(10.5, 7.0), layout="constrained")
    speed = ds.rotor_speed.values
    top = 1.05 * float(ds.frequency.max())
    for n in range(1, max_harmonic + 1):
        ax.plot(speed, n * speed, color="0.6", lw=0.8, ls="--")
        x = min(0.97 * speed[-1], 0.93 * top / n)
        ax.text(
            x,
            n * x,
            f"{n}/rev",
            fontsize=8,
            color="0.35",
            ha="center",
            va="center",
            bbox={"boxstyle": "round,pad=0.15", "fc": "w", "ec": "none"},
        )
    ends, labels, colours = [], [], []
    for mode in ds.mode.values:
        freq = ds.frequency.sel(mode=mode).values
        if np.all(freq == 0):
            continue  # rigid-body modes
        label = str(ds.mode_label.values[mode])
        colour = FAMILY_COLOURS.get(label.split()[0], "k")
        ax.plot(speed, freq, color=colour, lw=1.2)
        ends.append(float(freq[-1]))
        labels.append(label)
        colours.append(colour)
    gap = 0.032 * top  # about one line of 7.5-point text on this axis height
    placed = spread_labels(ends, gap, lower=0.0, upper=top)
    for end, y, label, colour in zip(ends, placed, labels, colours, strict=True):
        ax.annotate(
            label,
            xy=(speed[-1], end),
            xytext=(1.02, y),
            textcoords=("axes fraction", "data"),
            fontsize=7.5,
            color=colour,
            va="center",
            annotation_clip=False,
            arrowprops={"arrowstyle": "-", "color": colour, "lw": 0.5, "shrinkA": 0, "shrinkB": 0},
        )
    nominal = float(ds.attrs["nominal_rotor_speed_rad_s"])
    ax.axvline(nominal, color="k", lw=0.6, ls=":")
    for value in marks.values():
        ax.plot(nominal, value, "r*", ms=9)
    ax.set(
        xlabel="main rotor speed (rad/s)",
        ylabel="modal frequency, fixed frame (rad/s)",
        ylim=(0, top),
        xlim=(0, speed[-1]),
        title="Campbell diagram, balanced rotor, multiblade coordinates",
    )
    handles = [Line2D([], [], color=c, label=f) for f, c in {**FAMILY_COLOURS, "fuselage": "k"}.items()]
    handles.append(Line2D([], [], color="0.6", ls="--", lw=0.8, label="n/rev"))
    if marks:
        text = ", ".join(f"{value:g}" for value in marks.values())
        handles.append(Line2D([], [], color="r", marker="*", ls="none", ms=9, label=f"paper's peaks ({text} rad/s)"))
    fig.legend(
        handles=handles,
        loc="outside lower center",
        ncols=len(handles),
        fontsize=8,
        title="colour: largest share of the mode's energy",
        title_fontsize=8,
    )
    return fig


def sensitivity_figure(ds: xr.Dataset, ncols: int = 4):
    """Dominant Y and Z frequencies and line amplitudes (with Z's 1/rev line dashed) against each parameter
    changed: one pair of panels (frequency above, amplitude below) per parameter, `ncols` pairs a row, one legend."""
    parameters = [p for p in dict.fromkeys(ds.parameter.values.tolist()) if p != "baseline"]
    ncols = min(ncols, len(parameters))
    nrows = -(-len(parameters) // ncols)
    fig, axes = plt.subplots(
        2 * nrows,
        ncols,
        figsize=(3.3 * ncols + (0 if len(parameters) < nrows * ncols else 1.4), 4.6 * nrows + 0.6),
        layout="constrained",
        squeeze=False,
        height_ratios=[1, 1] * nrows,
    )
    base = ds.isel(run=np.flatnonzero(ds.parameter.values == "baseline"))
    for i, parameter in enumerate(parameters):
        top, bottom = axes[2 * (i // ncols), i % ncols], axes[2 * (i // ncols) + 1, i % ncols]
        runs = ds.isel(run=np.flatnonzero(ds.parameter.values == parameter))
        runs = xr.concat([runs, base], dim="run").sortby(parameter)
        x = runs[parameter].values
        for axis, style in (("y", "o-"), ("z", "s-")):
            top.plot(x, runs.dominant_omega.sel(axis=axis), style, ms=4, label=f"{axis.upper()} dominant line")
            bottom.semilogy(x, 1e3 * runs.dominant_amplitude.sel(axis=axis), style, ms=4)
        bottom.semilogy(x, 1e3 * runs.rotor_line_amplitude.sel(axis="z"), "k--", lw=0.8, label="Z 1/rev line")
        for ax in (top, bottom):
            ax.axvline(float(base[parameter].values[0]), color="0.6", ls=":", lw=0.8, label="config")
            ax.tick_params(labelsize=8)
        top.tick_params(labelbottom=False)
        unit = ds[parameter].attrs["units"]
        bottom.set_xlabel(f"{parameter} ({unit})", fontsize=8)
        top.set_title(parameter, fontsize=9)
        if i % ncols == 0:
            top.set_ylabel("dominant frequency\n(rad/s)", fontsize=8)
            bottom.set_ylabel("line amplitude (mm)", fontsize=8)
    for i in range(len(parameters), nrows * ncols):
        for ax in axes[2 * (i // ncols) : 2 * (i // ncols) + 2, i % ncols]:
            ax.set_axis_off()
    handles, labels = axes[0, 0].get_legend_handles_labels()
    more, more_labels = axes[1, 0].get_legend_handles_labels()
    keep = {label: h for h, label in zip(handles + more, labels + more_labels, strict=True)}
    if len(parameters) < nrows * ncols:  # in the first empty slot, else beside the panels
        axes[-2, -1].legend(keep.values(), keep.keys(), loc="upper left", fontsize=9)
    else:
        fig.legend(keep.values(), keep.keys(), loc="outside right upper", fontsize=8)
    fig.suptitle("Imbalanced rotor: dominant fuselage lines, one parameter changed at a time")
    return fig
