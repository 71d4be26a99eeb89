"""Flight-log figure: power spectral densities of the mount's acceleration and angular rate (as PX4 Flight
Review shows them), from a dataset of `uavdamp.read_flight_log`."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

AXIS_COLOURS = {"x": "tab:red", "y": "tab:green", "z": "tab:blue"}
PANELS = (
    ("acceleration", "acceleration PSD ((m/s²)²/Hz)", "specific force at the mount (accelerometer, gravity included)"),
    ("angular_rate", "angular-rate PSD ((rad/s)²/Hz)", "body angular rate (gyroscope)"),
)


def welch_psd(signal: np.ndarray, sample_rate_hz: float, segment_s: float) -> tuple[np.ndarray, np.ndarray]:
    """One-sided Welch PSD (Hann segments of `segment_s` s or the record, half overlap, mean removed):
    (freq Hz, PSD in the signal's unit squared per Hz)."""
    from scipy.signal import welch

    nperseg = int(min(signal.size, round(segment_s * sample_rate_hz)))
    return welch(signal, fs=sample_rate_hz, nperseg=nperseg, detrend="constant", scaling="density")


def psd_limits(psd: np.ndarray, decades: float = 7.0) -> tuple[float, float]:
    """Log y-range: from the noise floor (the 1st percentile, halved) to three times the largest value,
    at most `decades` decades."""
    top = 3.0 * float(np.max(psd))
    return max(0.5 * float(np.percentile(psd, 1)), top * 10.0**-decades), top


def psd_figure(ds: xr.Dataset, segment_s: float = 2.0):
    """Acceleration and angular-rate PSDs per axis (Welch, `segment_s` s segments) of a `read_flight_log`
    dataset, log y-axis, the integration band shaded, the largest in-band line of each axis in the legend."""
    rate_hz = float(ds.attrs["sample_rate_hz"])  # the log's; the data may be upsampled (time_step_s)
    fs = 1.0 / float(ds.attrs.get("time_step_s", 1.0 / rate_hz))
    low, high = (float(v) for v in ds.attrs["band_hz"])
    fig, axes = plt.subplots(2, 1, figsize=(11, 7.5), constrained_layout=True, sharex=True)
    for ax, (name, ylabel, what) in zip(axes, PANELS, strict=True):
        shown = []
        for axis in ds.axis.values:
            freq, psd = welch_psd(ds[name].sel(axis=axis).values, fs, segment_s)
            freq, psd = freq[freq <= 0.5 * rate_hz], psd[freq <= 0.5 * rate_hz]  # up to the log's Nyquist
            freq, psd = freq[1:], psd[1:]  # the zero-frequency bin holds only the removed mean
            band = (freq >= low) & (freq <= high)
            peak = freq[band][np.argmax(psd[band])]
            ax.semilogy(freq, psd, color=AXIS_COLOURS[str(axis)], lw=1.0, label=f"{axis}: in-band peak {peak:.1f} Hz")
            shown.append(psd)
        ax.axvspan(low, high, color="0.85", zorder=0, label=f"band {low:g}-{high:g} Hz")
        ax.set(ylim=psd_limits(np.concatenate(shown)), ylabel=ylabel, title=what)
        ax.grid(True, which="major", color="0.9", lw=0.6)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    window = ds.attrs["log_window_s"]
    axes[-1].set(xlim=(0.0, 0.5 * rate_hz), xlabel="frequency (Hz)")
    fig.suptitle(
        f"{ds.attrs['log_file']}: {rate_hz:.1f} Hz, log time {window[0]:.2f}-{window[1]:.2f} s, "
        f"Welch {segment_s:g} s Hann segments; axes x forward, y left, z up"
    )
    return fig
