"""Fuselage vibration figure: the analogue of the paper's Fig. 3, plus the spectra."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import xarray as xr  # noqa: E402


def fuselage_vibration_figure(ds: xr.Dataset, window_s: float = 5.0):
    """Z and Y mount displacement over the first `window_s` seconds (imbalanced: solid blue,
    balanced: dotted red, as in the paper's Fig. 3) and their amplitude spectra."""
    fig, axes = plt.subplots(2, 2, figsize=(11, 6.5), constrained_layout=True)
    early = ds.sel(time=slice(0.0, window_s))
    for row, axis in enumerate(("z", "y")):
        ax = axes[row, 0]
        ax.plot(early.time, 1e3 * early.displacement.sel(rotor="imbalanced", axis=axis), "b-", lw=0.8,
                label="imbalanced rotor")
        ax.plot(early.time, 1e3 * early.displacement.sel(rotor="balanced", axis=axis), "r:", lw=1.5,
                label="balanced rotor")
        ax.set(xlabel="time (s)", ylabel=f"{axis.upper()} displacement (mm)",
               title=f"({'ab'[row]}) fuselage vibration, {axis.upper()} axis")
        ax.legend(loc="upper right", fontsize=8)
        ax = axes[row, 1]
        spec = ds.amplitude_spectrum.sel(rotor="imbalanced", axis=axis)
        ax.semilogy(ds.omega, 1e3 * spec, "b-", lw=0.8)
        dominant = float(ds.dominant_omega.sel(rotor="imbalanced", axis=axis))
        ax.axvline(dominant, color="k", ls="--", lw=0.8, label=f"dominant {dominant:.2f} rad/s")
        ax.set(xlim=(0, 120), xlabel="angular frequency (rad/s)", ylabel="amplitude (mm)",
               title=f"{axis.upper()} spectrum, imbalanced rotor, {float(ds.time[-1]):.0f} s record")
        ax.legend(loc="upper right", fontsize=8)
    return fig
