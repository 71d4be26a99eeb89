"""Vibration levels and lines of an accelerometer record: a VIBE-like level and the strongest Welch PSD peaks."""

from __future__ import annotations

import numpy as np
from scipy.signal import butter, find_peaks, sosfiltfilt, welch

VIBE_HIGHPASS_HZ = 5.0  # ArduPilot's VIBE: accelerometer deviation from its 5 Hz low-pass (as approximated here)


def vibe_like(time_s: np.ndarray, acceleration: np.ndarray) -> np.ndarray:
    """Per axis, m s-2: the std of the acceleration above VIBE_HIGHPASS_HZ (2nd-order Butterworth high-pass,
    forward and backward), the quantity ArduPilot's VIBE estimates (choice of filter; its own is a 5 Hz
    low-pass floor and a 2 Hz mean of the squared difference)."""
    fs = 1.0 / float(np.median(np.diff(time_s)))
    sos = butter(2, VIBE_HIGHPASS_HZ, btype="highpass", fs=fs, output="sos")
    return np.std(sosfiltfilt(sos, acceleration, axis=-1), axis=-1)


def psd_peaks(time_s: np.ndarray, values: np.ndarray, band_hz=None, count: int = 3) -> list[list[tuple[float, float]]]:
    """Per axis, the `count` strongest Welch PSD peaks [(freq Hz, PSD units^2/Hz)] inside band_hz (default
    MIN 1 Hz to Nyquist), 1 s segments (the record's length if shorter)."""
    fs = 1.0 / float(np.median(np.diff(time_s)))
    low, high = band_hz if band_hz is not None else (1.0, 0.5 * fs)
    out = []
    for x in np.atleast_2d(values):
        f, p = welch(x, fs=fs, nperseg=min(x.size, max(16, int(round(fs)))))
        inside = (f >= low) & (f <= high)
        idx, _ = find_peaks(np.where(inside, p, 0.0))
        best = idx[np.argsort(p[idx])[::-1][:count]]
        out.append([(float(f[i]), float(p[i])) for i in best])
    return out
