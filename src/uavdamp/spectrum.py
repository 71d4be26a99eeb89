"""Amplitude spectra and dominant frequencies of sampled signals."""

from __future__ import annotations

import numpy as np


def amplitude_spectrum(signal: np.ndarray, dt: float, *, zero_padding: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Single-sided amplitude spectrum with a Hann window: (freq_hz, amplitude in the signal's unit).

    The mean is removed first; the window's coherent gain is divided out, so a sine of amplitude A
    at a bin frequency shows a peak of A. `zero_padding` multiplies the FFT length (finer grid, not
    finer resolution).
    """
    x = np.asarray(signal, dtype=float)
    if x.ndim != 1 or x.size < 4:
        raise ValueError("signal: need a 1-D array of at least 4 samples")
    if not dt > 0:
        raise ValueError(f"dt: must be positive, got {dt}")
    if int(zero_padding) < 1:
        raise ValueError(f"zero_padding: must be >= 1, got {zero_padding}")
    window = np.hanning(x.size)
    n_fft = int(zero_padding) * x.size
    amp = np.abs(np.fft.rfft((x - x.mean()) * window, n_fft)) * 2.0 / window.sum()
    amp[0] /= 2.0
    return np.fft.rfftfreq(n_fft, dt), amp


def dominant_frequency(signal: np.ndarray, dt: float, *, min_freq_hz: float = 0.0, max_freq_hz: float = np.inf,
                       zero_padding: int = 8) -> float:
    """Frequency, Hz, of the largest spectral peak within [min_freq_hz, max_freq_hz].

    The peak is refined by a parabola through the log amplitudes of the three bins around it.
    Returns NaN if the band holds no bin or the signal is identically constant.
    """
    freq, amp = amplitude_spectrum(signal, dt, zero_padding=zero_padding)
    band = np.flatnonzero((freq >= min_freq_hz) & (freq <= max_freq_hz))
    if band.size == 0 or not np.any(amp[band] > 0):
        return float("nan")
    k = band[np.argmax(amp[band])]
    if 0 < k < freq.size - 1 and np.all(amp[k - 1:k + 2] > 0):
        a, b, c = np.log(amp[k - 1:k + 2])
        denom = a - 2 * b + c
        shift = 0.5 * (a - c) / denom if denom < 0 else 0.0
        return float(freq[k] + shift * (freq[1] - freq[0]))
    return float(freq[k])
