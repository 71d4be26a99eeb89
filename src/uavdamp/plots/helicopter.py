"""Fuselage vibration figure: the analogue of the paper's Fig. 3, plus the spectra."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from uavdamp.plots.style import (  # noqa: E402
    SPECTRUM_DYNAMIC_RANGE,
    TIME_WINDOW_S,
    clip_log_range,
    number,
    spread_labels,
    time_window_label,
)

# line style per run of the vibration stage (the paper's Fig. 3: imbalanced solid blue, balanced dotted red)
RUN_STYLES = {
    "imbalanced": {"color": "b", "ls": "-", "lw": 0.8},
    "balanced": {"color": "r", "ls": ":", "lw": 1.5},
    "hover": {"color": "g", "ls": "-", "lw": 0.8},
    "forward": {"color": "tab:purple", "ls": "-", "lw": 0.8},
}
_OTHER_RUNS = ("tab:orange", "tab:brown", "tab:olive", "tab:cyan")
TIME_RUNS = ("imbalanced", "balanced")  # the time panels: the paper's Fig. 3 pair


def _run_style(ds: xr.Dataset, rotor: str) -> dict:
    if rotor in RUN_STYLES:
        return RUN_STYLES[rotor]
    others = [str(r) for r in ds.rotor.values if str(r) not in RUN_STYLES]
    return {"color": _OTHER_RUNS[others.index(rotor) % len(_OTHER_RUNS)], "ls": "-", "lw": 0.8}


def run_description(ds: xr.Dataset, rotor: str) -> str:
    """A run in words from the dataset itself: its `rotor` coordinate, then its flight condition (`flight`) and
    blade mass scale (`mass_imbalance_factor`) where the dataset holds them."""
    parts = []
    if "flight" in ds:
        flight = str(ds.flight.sel(rotor=rotor).values)
        parts.append("in vacuum" if flight == "vacuum" else f"{flight} flight")
    if "mass_imbalance_factor" in ds:
        factor = float(ds.mass_imbalance_factor.sel(rotor=rotor))
        parts.append("all blades equal" if factor == 1 else f"one blade at {factor:g} of its mass")
    return f"{rotor}\n({', '.join(parts)})" if parts else rotor


def _imbalanced_runs(ds: xr.Dataset) -> list[str]:
    """The runs with an imbalanced blade (`mass_imbalance_factor` != 1; without it, every run but "balanced"): the
    balanced rotor's motion is numerical noise, its spectrum too."""
    runs = [str(r) for r in ds.rotor.values]
    if "mass_imbalance_factor" in ds:
        return [r for r in runs if float(ds.mass_imbalance_factor.sel(rotor=r)) != 1]
    return [r for r in runs if r != "balanced"]


def _spectrum_panel(ax, ds: xr.Dataset, axis: str) -> None:
    """Amplitude spectra (mm) of the imbalanced runs on a clipped log axis; the imbalanced run's dominant line."""
    runs = _imbalanced_runs(ds)
    shown = []
    for rotor in runs:
        spec = 1e3 * ds.amplitude_spectrum.sel(rotor=rotor, axis=axis)
        ax.semilogy(ds.omega, spec, **_run_style(ds, rotor), label=run_description(ds, rotor))
        shown.append(spec.sel(omega=slice(0, 120)).values)
    dominant = float(ds.dominant_omega.sel(rotor="imbalanced", axis=axis))
    ax.axvline(dominant, color="k", ls="--", lw=0.8, label="dominant line (imbalanced)")
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
    clip_log_range(ax, np.concatenate(shown), SPECTRUM_DYNAMIC_RANGE)
    ax.set(xlim=(0, 120), xlabel="angular frequency (rad/s)", ylabel="amplitude (mm)")
    ax.set_title(f"{axis.upper()} spectrum of {', '.join(runs)} (whole {float(ds.time[-1]):g} s run)", fontsize=10)


def fuselage_vibration_figure(ds: xr.Dataset, window_s: float = TIME_WINDOW_S, mount: str | None = None):
    """Z and Y displacement of `mount` (default: the first mount point) over the first `window_s` of the runs
    (`style.TIME_WINDOW_S`; imbalanced: solid blue, balanced: dotted red, as in the paper's Fig. 3) and the
    amplitude spectra of the runs with an imbalanced blade, on a log axis from SPECTRUM_DYNAMIC_RANGE of the peak
    up (below lies numerical noise). One legend, beside the panels, naming every line drawn (`run_description`)."""
    mount = str(ds.mount.values[0]) if mount is None else mount
    ds = ds.sel(mount=mount).rename(mount_displacement="displacement")
    fig, axes = plt.subplots(2, 2, figsize=(12, 6.5), layout="constrained")
    early = ds.sel(time=slice(0.0, window_s))
    runs = [r for r in TIME_RUNS if r in ds.rotor.values]
    for row, axis in enumerate(("z", "y")):
        ax = axes[row, 0]
        for rotor in runs:
            move = 1e3 * early.displacement.sel(rotor=rotor, axis=axis)
            ax.plot(early.time, move, **_run_style(ds, rotor), label=run_description(ds, rotor))
        ax.set(xlabel=time_window_label(ds.time.values, window_s), ylabel=f"{axis.upper()} displacement (mm)")
        ax.set_title(f"({'ab'[row]}) {axis.upper()} axis, {' and '.join(runs)} rotor", fontsize=10)
        _spectrum_panel(axes[row, 1], ds, axis)
    handles = {}
    for ax in axes.flat:
        handles.update({label: h for h, label in zip(*ax.get_legend_handles_labels(), strict=True)})
    fig.legend(handles.values(), handles.keys(), loc="outside right upper", fontsize=8)
    position = ds.mount_position.values if "mount_position" in ds.coords else []
    where = f" ({', '.join(number(v) for v in position)}) m" if len(position) else ""
    fig.suptitle(f"Fuselage vibration at mount point {mount}{where}", fontsize=11)
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


# panel titles: a readable name and unit per parameter (`uavdamp.helicopter.sensitivity.PARAMETERS`); others: the key
PARAMETER_TITLES = {
    "lag_stiffness_n_m_rad": "lag hinge spring (N m/rad)",
    "lag_damping_n_m_s_rad": "lag damper (N m s/rad)",
    "hinge_offset_m": "flap and lag hinge offset (m)",
    "feather_stiffness_n_m_rad": "pitch-link (feather) spring (N m/rad)",
    "imbalance_mass_factor": "mass scale of the imbalanced blade (1)",
    "fuselage_inertia_scale": "scale of all fuselage inertias (1)",
    "fuselage_ixx_scale": "scale of the fuselage roll inertia Ixx (1)",
}
AXIS_STYLES = {"y": ("o", "C0"), "z": ("s", "C1")}


def _is_rotor_line(runs: xr.Dataset, axis: str) -> np.ndarray:
    """True where the dominant line of `axis` is the 1/rev line (its amplitude is the 1/rev line's)."""
    dominant, rotor = runs.dominant_amplitude.sel(axis=axis).values, runs.rotor_line_amplitude.sel(axis=axis).values
    return np.isclose(dominant, rotor, rtol=1e-9, atol=0.0)


def _points(ax, x, y, same: np.ndarray, axis: str) -> None:
    """Every (x, y) a marker, filled where the dominant line is the 1/rev line (`same`), hollow where another line
    wins; a line joins only consecutive 1/rev points (the one line known to be the same from point to point)."""
    marker, colour = AXIS_STYLES[axis]
    for rotor_line in (True, False):
        pick = same == rotor_line
        mfc = colour if rotor_line else "none"
        ax.plot(x[pick], y[pick], marker, ms=5, ls="none", color=colour, mfc=mfc, mew=1.2)
    start = 0
    for i in range(1, x.size + 1):
        if i == x.size or same[i] != same[start]:
            if same[start] and i - start > 1:
                ax.plot(x[start:i], y[start:i], "-", color=colour, lw=1.2)
            start = i


def _legend_handles() -> list:
    handles = [
        Line2D([], [], marker=m, color=c, label=f"{a.upper()} dominant line") for a, (m, c) in AXIS_STYLES.items()
    ]
    return handles + [
        Line2D([], [], marker="o", color="0.4", ls="none", label="filled: it is the 1/rev line"),
        Line2D([], [], marker="o", color="0.4", mfc="none", ls="none", label="hollow: another line"),
        Line2D([], [], color="k", ls="--", lw=0.8, label="Z 1/rev line"),
        Line2D([], [], color="0.6", ls=":", lw=0.8, label="config"),
    ]


def _sensitivity_pair(top, bottom, ds: xr.Dataset, base: xr.Dataset, parameter: str) -> None:
    """One parameter's dominant frequencies (top) and line amplitudes (bottom) against its values."""
    runs = ds.isel(run=np.flatnonzero(ds.parameter.values == parameter))
    runs = xr.concat([runs, base], dim="run").sortby(parameter)
    x = runs[parameter].values
    for axis in AXIS_STYLES:
        same = _is_rotor_line(runs, axis)
        _points(top, x, runs.dominant_omega.sel(axis=axis).values, same, axis)
        _points(bottom, x, 1e3 * runs.dominant_amplitude.sel(axis=axis).values, same, axis)
    bottom.semilogy(x, 1e3 * runs.rotor_line_amplitude.sel(axis="z"), "k--", lw=0.8)
    for ax in (top, bottom):
        ax.axvline(float(base[parameter].values[0]), color="0.6", ls=":", lw=0.8)
        ax.tick_params(labelsize=8)
    top.tick_params(labelbottom=False)
    bottom.set_xlabel(f"{parameter} ({ds[parameter].attrs['units']})", fontsize=8)
    top.set_title(PARAMETER_TITLES.get(parameter, parameter), fontsize=9)


def sensitivity_figure(ds: xr.Dataset, ncols: int = 4):
    """Dominant Y and Z frequencies and line amplitudes (with Z's 1/rev line dashed) against each parameter
    changed: one pair of panels (frequency above, amplitude below) per parameter, `ncols` pairs a row, one legend.
    Points are filled where the dominant line is the 1/rev line, hollow where another line wins; a line joins only
    consecutive 1/rev points. Panel titles: PARAMETER_TITLES (else the parameter's key)."""
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
        _sensitivity_pair(top, bottom, ds, base, parameter)
        if i % ncols == 0:
            top.set_ylabel("dominant frequency\n(rad/s)", fontsize=8)
            bottom.set_ylabel("line amplitude (mm)", fontsize=8)
    for i in range(len(parameters), nrows * ncols):
        for ax in axes[2 * (i // ncols) : 2 * (i // ncols) + 2, i % ncols]:
            ax.set_axis_off()
    if len(parameters) < nrows * ncols:  # in the first empty slot, else beside the panels
        axes[-2, -1].legend(handles=_legend_handles(), loc="upper left", fontsize=9)
    else:
        fig.legend(handles=_legend_handles(), loc="outside right upper", fontsize=8)
    fig.suptitle("Imbalanced rotor: dominant fuselage lines, one parameter changed at a time")
    return fig
