"""Vibration levels and lines of an accelerometer record: ArduPilot's VIBE and the strongest Welch PSD peaks."""

from __future__ import annotations

import numpy as np

from uavdamp.sources import levels


def vibe(time_s: np.ndarray, acceleration: np.ndarray) -> np.ndarray:
    """Per axis, m s-2: ArduPilot's VIBE of the logged samples (`uavdamp.sources.levels.vibe`: ArduPilot's own 5 Hz
    floor and 2 Hz filters) at their median interval; NaN for a record no longer than twice VIBE's settling."""
    dt = float(np.median(np.diff(time_s)))
    a = np.atleast_2d(np.asarray(acceleration, dtype=float))
    if a.shape[-1] * dt <= 2 * levels.vibe_settle_s():
        return np.full(a.shape[0], np.nan)
    return levels.vibe(a, dt)


def psd_peaks(time_s: np.ndarray, values: np.ndarray, band_hz=None, count: int = 3) -> list[list[tuple[float, float]]]:
    """Per axis, the `count` strongest Welch PSD peaks [(freq Hz, PSD units^2/Hz)] inside band_hz (default
    MIN 1 Hz to Nyquist), 1 s segments (the record's length if shorter)."""
    from scipy.signal import find_peaks, welch

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
