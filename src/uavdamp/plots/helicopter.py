"""Fuselage vibration figure: the analogue of the paper's Fig. 3, plus the spectra."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402


def fuselage_vibration_figure(ds: xr.Dataset, window_s: float = 5.0, mount: str | None = None):
    """Z and Y displacement of `mount` (default: the first mount point) over the first `window_s` seconds
    (imbalanced: solid blue, balanced: dotted red, as in the paper's Fig. 3) and their amplitude spectra."""
    mount = str(ds.mount.values[0]) if mount is None else mount
    fig, axes = plt.subplots(2, 2, figsize=(11, 6.5), constrained_layout=True)
    ds = ds.sel(mount=mount).rename(mount_displacement="displacement")
    early = ds.sel(time=slice(0.0, window_s))
    for row, axis in enumerate(("z", "y")):
        ax = axes[row, 0]
        ax.plot(
            early.time,
            1e3 * early.displacement.sel(rotor="imbalanced", axis=axis),
            "b-",
            lw=0.8,
            label="imbalanced rotor",
        )
        ax.plot(
            early.time, 1e3 * early.displacement.sel(rotor="balanced", axis=axis), "r:", lw=1.5, label="balanced rotor"
        )
        ax.set(
            xlabel="time (s)",
            ylabel=f"{axis.upper()} displacement (mm)",
            title=f"({'ab'[row]}) fuselage vibration, {axis.upper()} axis",
        )
        ax.legend(loc="upper right", fontsize=8)
        ax = axes[row, 1]
        spec = ds.amplitude_spectrum.sel(rotor="imbalanced", axis=axis)
        ax.semilogy(ds.omega, 1e3 * spec, "b-", lw=0.8, label="imbalanced, vacuum")
        dominant = float(ds.dominant_omega.sel(rotor="imbalanced", axis=axis))
        ax.axvline(dominant, color="k", ls="--", lw=0.8, label=f"dominant {dominant:.2f} rad/s")
        if "hover" in ds.rotor.values:  # the flight run: trimmed hover with aerodynamics, gravity and pilot
            hover = ds.amplitude_spectrum.sel(rotor="hover", axis=axis)
            line = float(ds.dominant_omega.sel(rotor="hover", axis=axis))
            ax.semilogy(ds.omega, 1e3 * hover, "g-", lw=0.8, label=f"imbalanced, trimmed hover (dominant {line:.2f})")
        ax.set(
            xlim=(0, 120),
            xlabel="angular frequency (rad/s)",
            ylabel="amplitude (mm)",
            title=f"{axis.upper()} spectrum, imbalanced rotor, {float(ds.time[-1]):.0f} s record",
        )
        ax.legend(loc="upper right", fontsize=8)
    return fig


FAMILY_COLOURS = {"flap": "tab:blue", "lag": "tab:orange", "feather": "tab:green"}


def campbell_figure(ds: xr.Dataset, marks: dict[str, float] | None = None, max_harmonic: int = 4):
    """Campbell diagram: fixed-frame modal frequencies (rad/s) against rotor speed, with n/rev lines.

    Colour by the mode's dominant coordinate family at the nominal speed (flap, lag, feather, else fuselage);
    line width grows with the MAC of each match. `marks` (label -> rad/s) are drawn at the nominal speed
    (default: the paper's fuselage peaks Y 44.04 and Z 50.58 rad/s).
    """
    marks = {"paper Y peak 44.04": 44.04, "paper Z peak 50.58": 50.58} if marks is None else marks
    fig, ax = plt.subplots(figsize=(9, 6.5), constrained_layout=True)
    speed = ds.rotor_speed.values
    for n in range(1, max_harmonic + 1):
        ax.plot(speed, n * speed, color="0.6", lw=0.8, ls="--")
        ax.annotate(f"{n}/rev", (speed[-1], n * speed[-1]), fontsize=8, color="0.4")
    for mode in ds.mode.values:
        freq = ds.frequency.sel(mode=mode).values
        if np.all(freq == 0):
            continue  # rigid-body modes
        label = str(ds.mode_label.values[mode])
        colour = FAMILY_COLOURS.get(label.split()[0], "k")
        ax.plot(speed, freq, color=colour, lw=1.2)
        ax.annotate(label, (speed[-1], freq[-1]), fontsize=7, color=colour, xytext=(3, 0), textcoords="offset points")
    nominal = float(ds.attrs["nominal_rotor_speed_rad_s"])
    ax.axvline(nominal, color="k", lw=0.6, ls=":")
    for text, value in marks.items():
        ax.plot(nominal, value, "r*", ms=9)
        ax.annotate(text, (nominal, value), fontsize=8, color="r", xytext=(-110, 4), textcoords="offset points")
    ax.set(
        xlabel="main rotor speed (rad/s)",
        ylabel="modal frequency, fixed frame (rad/s)",
        ylim=(0, 1.05 * float(ds.frequency.max())),
        xlim=(0, 1.12 * speed[-1]),
        title="Campbell diagram, balanced rotor, multiblade coordinates",
    )
    handles = [plt.Line2D([], [], color=c, label=f) for f, c in {**FAMILY_COLOURS, "fuselage": "k"}.items()]
    ax.legend(handles=handles, loc="upper left", fontsize=8, title="largest share", title_fontsize=8)
    return fig


def sensitivity_figure(ds: xr.Dataset):
    """Dominant Y and Z frequencies (top) and line amplitudes (bottom, with Z's 1/rev line dashed) against each
    parameter changed."""
    parameters = [p for p in dict.fromkeys(ds.parameter.values.tolist()) if p != "baseline"]
    fig, axes = plt.subplots(
        2, len(parameters), figsize=(2.6 * len(parameters), 6), constrained_layout=True, squeeze=False
    )
    base = ds.isel(run=np.flatnonzero(ds.parameter.values == "baseline"))
    for col, parameter in enumerate(parameters):
        runs = ds.isel(run=np.flatnonzero(ds.parameter.values == parameter))
        runs = xr.concat([runs, base], dim="run").sortby(parameter)
        x = runs[parameter].values
        for axis, style in (("y", "o-"), ("z", "s-")):
            axes[0, col].plot(x, runs.dominant_omega.sel(axis=axis), style, ms=4, label=axis.upper())
            axes[1, col].semilogy(x, 1e3 * runs.dominant_amplitude.sel(axis=axis), style, ms=4, label=axis.upper())
        axes[1, col].semilogy(x, 1e3 * runs.rotor_line_amplitude.sel(axis="z"), "k--", lw=0.8, label="Z 1/rev line")
        for row in (0, 1):
            axes[row, col].axvline(float(base[parameter].values[0]), color="0.6", ls=":", lw=0.8)
        unit = ds[parameter].attrs["units"]
        axes[1, col].set_xlabel(f"{parameter}\n({unit})", fontsize=8)
    axes[0, 0].set_ylabel("dominant frequency (rad/s)")
    axes[1, 0].set_ylabel("line amplitude (mm)")
    axes[0, 0].legend(fontsize=8)
    axes[1, 0].legend(fontsize=8)
    fig.suptitle("Imbalanced rotor: dominant fuselage lines, one parameter changed at a time (dotted: config)")
    return fig
