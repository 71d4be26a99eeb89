"""Inertial-sensor arrays: axis convention, resampling, rigid-body lever arm, band-pass integration.

Pure array functions (no file I/O) behind `uavdamp.sources.flight_log.read_flight_log`. Vectors are (3, n) arrays,
rows x, y, z. uavdamp's body axes are x forward, y left, z up (FLU); PX4 and ArduPilot log FRD (x forward,
y right, z down), so `frd_to_flu` negates y and z, for accelerations and angular rates alike (a rotation
of pi about x, which keeps right-handedness).

Band-pass integration (`band_integrate`), in the frequency domain: the record loses its mean (the
accelerometer measures specific force, gravity included; its constant part, and everything else below
the band, is set to zero), is multiplied by a Tukey window whose cosine ends last `taper_s` = 2 / f_low
each, and its spectrum (one FFT of the whole record) is divided by (i 2 pi f)^order inside [f_low, f_high]
and set to zero outside (an ideal band, no transition band). Samples within `edge_s` = 3 / f_low of either
end are not to be trusted: the taper attenuates them and the ideal band rings there (a 10.3 Hz sine, band
(2, 40) Hz: 99 % error in the first 0.25 s, 15 % at 0.75-1 s, 0.25 % at 1-1.25 s, 0.06 % at 1.25-1.5 s).
Inside, on 9 s at 200 Hz with band (2, 40) Hz, a sine at least f_low from both band edges comes back
within 0.5 % of its amplitude (measured, worst phase: 0.25 % at 4 Hz, 0.09 % or less from 6 to 35 Hz,
0.11 % at 38 Hz; nearer the edges 1.1 % at 3 Hz and 0.9 % at 39 Hz); a sine at least f_low outside the
band leaves at most 0.13 % of its own displacement amplitude. Strong content below the band leaks in
through the taper: a 0.3 m s-2 swing at 0.4 Hz adds 2.5 um (5e-5 of its own 47 mm displacement).
"""

from __future__ import annotations

import numpy as np
from scipy.fft import irfft, rfft, rfftfreq

TAPER_PERIODS = 2.0  # length of each cosine end of the taper, in periods of the band's low edge
EDGE_PERIODS = 3.0  # samples this many low-edge periods from either end are untrusted
MIN_INTERIOR_PERIODS = 2.0  # the trusted interior must hold at least this many low-edge periods
FRAME = "body axes x forward, y left, z up (FLU), right-handed"
SIGN = (
    "converted from the log's FRD body axes (x forward, y right, z down): y -> -y, z -> -z, for accelerations and "
    "angular rates alike"
)


def frd_to_flu(vectors: np.ndarray) -> np.ndarray:
    """(3, n) vectors in FRD body axes (x forward, y right, z down) -> FLU (x forward, y left, z up)."""
    vectors = np.asarray(vectors, dtype=float)
    return vectors * np.array([1.0, -1.0, -1.0]).reshape((3,) + (1,) * (vectors.ndim - 1))


def interval_stats(time_s: np.ndarray) -> dict[str, float]:
    """Median sample interval (s) and its jitter: std of (interval - median) / median and max of its absolute
    value (fractions)."""
    steps = np.diff(np.asarray(time_s, dtype=float))
    median = float(np.median(steps))
    rel = (steps - median) / median
    return {"median_s": median, "jitter_std": float(np.std(rel)), "jitter_max": float(np.max(np.abs(rel)))}


def uniform_grid(start_s: float, end_s: float, dt: float) -> np.ndarray:
    """start_s, start_s + dt, ... up to end_s (to 1e-9 dt), s."""
    n = int(np.floor((end_s - start_s) / dt + 1e-9)) + 1
    return start_s + dt * np.arange(n)


def resample(time_s: np.ndarray, values: np.ndarray, grid_s: np.ndarray, *, derivative: bool = False):
    """(3, n) `values` sampled at increasing `time_s` -> the interpolating cubic spline (not-a-knot) on
    `grid_s`; with derivative=True also its time derivative (unit s-1), as a pair.

    On uniform samples the spline's derivative at the knots is the fourth-order compact (Pade) central
    difference, gain 3 sin(x) / (x (2 + cos x)) at x = 2 pi f dt: -0.04 % at f = fs / 10, -1.7 % at fs / 5.
    """
    from scipy.interpolate import CubicSpline

    t0 = float(time_s[0])
    spline = CubicSpline(np.asarray(time_s, dtype=float) - t0, np.asarray(values, dtype=float), axis=1)
    on_grid = spline(np.asarray(grid_s, dtype=float) - t0)
    if not derivative:
        return on_grid
    return on_grid, spline.derivative()(np.asarray(grid_s, dtype=float) - t0)


def lever_arm(acceleration: np.ndarray, angular_rate: np.ndarray, angular_acceleration: np.ndarray, r_m) -> np.ndarray:
    """Acceleration (3, n), m s-2, at the point r_m (3,), m, from the IMU, of a rigid body whose IMU
    measures `acceleration` and whose body rates are `angular_rate` (rad s-1) and `angular_acceleration`
    (rad s-2), all in the same body axes: a + dw/dt x r + w x (w x r)."""
    r = np.asarray(r_m, dtype=float).reshape(3, 1) * np.ones((1, np.shape(acceleration)[1]))
    w = np.asarray(angular_rate, dtype=float)
    return (
        np.asarray(acceleration, dtype=float)
        + np.cross(angular_acceleration, r, axis=0)
        + np.cross(w, np.cross(w, r, axis=0), axis=0)
    )


def taper_s(band_hz: tuple[float, float]) -> float:
    """Length, s, of each cosine end of the integration's Tukey taper: TAPER_PERIODS / f_low."""
    return TAPER_PERIODS / float(band_hz[0])


def edge_s(band_hz: tuple[float, float]) -> float:
    """Untrusted length, s, at either end of an integrated record: EDGE_PERIODS / f_low."""
    return EDGE_PERIODS / float(band_hz[0])


def min_duration_s(band_hz: tuple[float, float]) -> float:
    """Shortest record, s, that `band_integrate` accepts: two edges and MIN_INTERIOR_PERIODS / f_low."""
    return 2.0 * edge_s(band_hz) + MIN_INTERIOR_PERIODS / float(band_hz[0])


def band_integrate(
    signal: np.ndarray, dt: float, band_hz: tuple[float, float], order: int, upsample: int = 1
) -> np.ndarray:
    """`signal` (..., n), sampled every `dt` s, integrated `order` times (1: rate -> angle, 2: acceleration
    -> displacement) in the frequency domain inside band_hz = (f_low, f_high), Hz, zero outside: X(f) =
    S(f) / (i 2 pi f)^order. Mean removed, Tukey taper of `taper_s(band_hz)` at each end, one FFT; trust
    only samples further than `edge_s(band_hz)` from either end (module docstring). `upsample` > 1 returns
    the result every dt / upsample s ((n - 1) upsample + 1 samples) by the zero-padded inverse FFT: exact
    band-limited interpolation, as the result has no content outside the band and tapers to 0 at the ends."""
    from scipy.signal.windows import tukey

    low, high = float(band_hz[0]), float(band_hz[1])
    x = np.asarray(signal, dtype=float)
    n = x.shape[-1]
    if not 0 < low < high <= 0.5 / dt:
        raise ValueError(f"band_hz: need 0 < low < high <= Nyquist {0.5 / dt:g} Hz, got {band_hz}")
    if n * dt < min_duration_s(band_hz):
        raise ValueError(
            f"signal: {n * dt:g} s is shorter than {min_duration_s(band_hz):g} s, needed for band {band_hz}"
        )
    x = (x - x.mean(axis=-1, keepdims=True)) * tukey(n, 2.0 * taper_s(band_hz) / (n * dt))
    freq = rfftfreq(n, dt)
    gain = np.zeros(freq.size, dtype=complex)
    inside = (freq >= low) & (freq <= high)
    gain[inside] = (1j * 2.0 * np.pi * freq[inside]) ** (-int(order))
    if int(upsample) < 1:
        raise ValueError(f"upsample: must be a whole number >= 1, got {upsample}")
    fine = irfft(rfft(x, axis=-1) * gain, n * int(upsample), axis=-1) * int(upsample)
    return fine[..., : (n - 1) * int(upsample) + 1]
