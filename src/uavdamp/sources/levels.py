"""Vibration levels in the units the field states them: per line in g, in/s and m, and ArduPilot's VIBE.

Conventions (every amplitude here is 0-peak): a line of acceleration amplitude A (m s-2) at f (Hz) has velocity
amplitude A / (2 pi f) and displacement amplitude A / (2 pi f)^2. Track-and-balance readings are quoted as
velocity, in/s 0-peak (choice, the convention this module states for every in/s it returns; a meter reading
peak-to-peak would show twice the number). g is the standard acceleration of gravity (9.80665 m s-2, exact by
definition), the inch 0.0254 m (exact).

VIBE is the vibration metric ArduPilot logs (VIBE.VibeX/Y/Z, m s-2): per accelerometer axis, the sample less a
first-order low-pass of it at 5 Hz (the "vibration floor"), squared, low-passed at 2 Hz, square-rooted: a running
standard deviation of the accelerometer's content above about 5 Hz. Definition read from ArduPilot's source:
``libraries/AP_InertialSensor/AP_InertialSensor.cpp`` (``calc_vibration_and_clipping``, ``get_vibration_levels``),
``libraries/AP_InertialSensor/AP_InertialSensor.h`` (``AP_INERTIAL_SENSOR_ACCEL_VIBE_FLOOR_FILT_HZ`` = 5,
``AP_INERTIAL_SENSOR_ACCEL_VIBE_FILT_HZ`` = 2, both ``LowPassFilterVector3f``) and
``libraries/Filter/LowPassFilter.cpp`` (``DigitalLPF::apply``: y += alpha (x - y), alpha = dt / (dt + RC),
RC = 1 / (2 pi fc), the first sample taken as the initial output), github.com/ArduPilot/ardupilot. ArduPilot runs
it at the IMU's sample rate; here it runs at the signal's rate (the discrete filter's gain depends on dt). The
guidance (ardupilot.org, "Measuring Vibration"): below 30 m s-2 normally acceptable, above 60 m s-2 nearly always
problems with position or altitude hold; a well-mounted 3DR IRIS shows below 15 m s-2. Here VIBE is computed from
the mount's translational acceleration; an accelerometer off the rotation centre would add the rotation's
tangential acceleration (not included).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from uavdamp.contract import STANDARD_GRAVITY, XYZ
from uavdamp.signals import spectrum

G = STANDARD_GRAVITY  # m s-2 per g
INCH = 0.0254  # m per inch (exact)
AXES = XYZ  # the axes a level is stated on

VIBE_FLOOR_HZ = 5.0  # Hz, ArduPilot AP_INERTIAL_SENSOR_ACCEL_VIBE_FLOOR_FILT_HZ
VIBE_FILTER_HZ = 2.0  # Hz, ArduPilot AP_INERTIAL_SENSOR_ACCEL_VIBE_FILT_HZ
# m s-2, ArduPilot's guidance ("Measuring Vibration", ardupilot.org): good (a well-mounted IRIS), the upper limit of
# normally acceptable, and the level above which position/altitude hold nearly always has problems
VIBE_GUIDANCE_M_S2 = {"good": 15.0, "marginal": 30.0, "bad": 60.0}

# in/s 0-peak, hover lateral 1/rev track-and-balance limit, as quoted from the AH-64 maintenance manual
# TM 1-6625-724-13&P (not publicly distributed; the value was not re-read from the manual for this module), which
# also warns that 1.2 in/s may damage the aircraft
TRACK_AND_BALANCE_LIMIT_IN_S = 0.2
TRACK_AND_BALANCE_DAMAGE_IN_S = 1.2
TRACK_AND_BALANCE_SOURCE = "AH-64 maintenance manual TM 1-6625-724-13&P: hover, lateral, 1/rev, 0.2 in/s"


def velocity_amplitude(accel_m_s2, freq_hz):
    """Velocity amplitude (m s-1) of a sinusoidal line of acceleration amplitude `accel_m_s2` at `freq_hz`."""
    return np.asarray(accel_m_s2, dtype=float) / (2 * np.pi * np.asarray(freq_hz, dtype=float))


def displacement_amplitude(accel_m_s2, freq_hz):
    """Displacement amplitude (m) of a sinusoidal line of acceleration amplitude `accel_m_s2` at `freq_hz`."""
    return np.asarray(accel_m_s2, dtype=float) / (2 * np.pi * np.asarray(freq_hz, dtype=float)) ** 2


def line_level(accel_m_s2: float, freq_hz: float) -> dict[str, float]:
    """One line's level (all 0-peak): accel_g (g), velocity_in_s (in/s), displacement_m (m), displacement_mm."""
    if not freq_hz > 0:
        raise ValueError(f"freq_hz: a line needs a positive frequency, got {freq_hz}")
    d = float(displacement_amplitude(accel_m_s2, freq_hz))
    return {
        "accel_g": accel_m_s2 / G,
        "velocity_in_s": float(velocity_amplitude(accel_m_s2, freq_hz)) / INCH,
        "displacement_m": d,
        "displacement_mm": 1e3 * d,
    }


def _lowpass(x: np.ndarray, dt: float, cutoff_hz: float) -> np.ndarray:
    """ArduPilot's first-order low-pass along the last axis: y[k] = y[k-1] + alpha (x[k] - y[k-1]), y[0] = x[0]."""
    from scipy.signal import lfilter

    alpha = dt / (dt + 1.0 / (2 * np.pi * cutoff_hz))
    zi = (1 - alpha) * x[..., :1]  # so that y[0] = x[0], as the filter's first sample
    return lfilter([alpha], [1.0, alpha - 1.0], x, axis=-1, zi=zi)[0]


def vibe_series(accel_m_s2, dt: float) -> np.ndarray:
    """ArduPilot's VIBE (m s-2) at every sample of an accelerometer signal (..., n) sampled every dt s."""
    a = np.asarray(accel_m_s2, dtype=float)
    if not dt > 0 or 0.5 / dt <= VIBE_FLOOR_HZ:
        raise ValueError(f"dt: VIBE needs a sample rate above {2 * VIBE_FLOOR_HZ} Hz, got dt = {dt} s")
    squared = (a - _lowpass(a, dt, VIBE_FLOOR_HZ)) ** 2
    return np.sqrt(np.maximum(_lowpass(squared, dt, VIBE_FILTER_HZ), 0.0))


def vibe_settle_s() -> float:
    """s, the start of a record VIBE's scalar level leaves out: ten time constants of the 2 Hz filter (e^-10)."""
    return 10.0 / (2 * np.pi * VIBE_FILTER_HZ)


def vibe(accel_m_s2, dt: float) -> np.ndarray:
    """The steady VIBE level (m s-2) per leading index of accel (..., n): the square root of the time mean of the
    2 Hz-filtered squared residual after `vibe_settle_s` (the filter's unit DC gain makes it the mean square of
    the residual above the 5 Hz floor)."""
    a = np.asarray(accel_m_s2, dtype=float)
    skip = int(math.ceil(vibe_settle_s() / dt))
    if a.shape[-1] <= 2 * skip:
        need = 2 * vibe_settle_s()
        raise ValueError(f"accel: VIBE needs a record longer than {need:.2f} s, got {a.shape[-1] * dt} s")
    return np.sqrt(np.mean(vibe_series(a, dt)[..., skip:] ** 2, axis=-1))


def acceleration_from_displacement(displacement_m, dt: float) -> np.ndarray:
    """Acceleration (m s-2) of a displacement record (..., n): the second derivative of the local quartic through
    five samples (Savitzky-Golay, scipy.signal). Its gain at f is exact to (2 pi f dt)^4 / 90 relative (0.7 % at
    28 Hz sampled at 200 Hz); a line read by `line_levels` is converted exactly instead."""
    from scipy.signal import savgol_filter

    return savgol_filter(np.asarray(displacement_m, dtype=float), 5, 4, deriv=2, delta=dt, axis=-1, mode="interp")


def rotor_lines(rotor_hz: float, orders=(1, 2, 3, 4)) -> dict[str, float]:
    """{"k/rev": k x rotor_hz} for each order k: the main rotor's lines (N/rev: k = blade count)."""
    if not rotor_hz > 0:
        raise ValueError(f"rotor_hz: must be > 0, got {rotor_hz}")
    return {f"{k}/rev": k * rotor_hz for k in orders}


def _fit_amplitudes(x: np.ndarray, dt: float, freqs: np.ndarray) -> np.ndarray:
    """Amplitudes of the sines at `freqs` (Hz) fitted jointly by Hann-weighted least squares with a quadratic
    trend: exact for a record of those sines and a trend, and the weights taper the record's ends, so that a slow
    drift's leakage (a flight's trajectory, tens of micrometres at 28 Hz from a rectangular fit over 40 s) stays
    out of the weak lines (the window's sidelobes fall as f^-3)."""
    n = x.size
    t = (np.arange(n) - 0.5 * (n - 1)) * dt
    columns = [np.ones(n), t, t * t]
    for f in freqs:
        columns += [np.cos(2 * np.pi * f * t), np.sin(2 * np.pi * f * t)]
    root_w = np.sqrt(np.hanning(n + 2)[1:-1])  # Hann weights, none zero
    coef = np.linalg.lstsq(np.column_stack(columns) * root_w[:, None], x * root_w, rcond=None)[0]
    return np.hypot(coef[3::2], coef[4::2])


def line_levels(
    signal, dt: float, lines_hz: dict[str, float], *, kind: str = "displacement", axes=AXES, locate: bool = True
) -> xr.Dataset:
    """Each line's level per axis in a translation (kind "displacement", m) or acceleration ("acceleration",
    m s-2) record (axis, n) sampled every dt s.

    A line's frequency is its nominal one (`lines_hz`, e.g. `rotor_lines`) or, with `locate`, the least-squares
    sine's nearest to it in the record (`spectrum.refine_by_sine_fit`, within +-0.5 / T, T the record length),
    read on the axis where the line is largest; then all lines' amplitudes are fitted jointly per axis (a quadratic
    trend removed, Hann-weighted: `_fit_amplitudes`) and converted exactly for a sine: a = (2 pi f)^2 d. Lines
    must lie below the Nyquist frequency and be resolved (apart by more than 2 / T)."""
    if kind not in ("displacement", "acceleration"):
        raise ValueError(f"kind: must be 'displacement' or 'acceleration', got {kind!r}")
    x = np.atleast_2d(np.asarray(signal, dtype=float))
    if x.shape[0] != len(axes):
        raise ValueError(f"signal: {x.shape[0]} rows for the axes {list(axes)}")
    names, nominal = list(lines_hz), np.array(list(lines_hz.values()), dtype=float)
    record_s = x.shape[1] * dt
    if np.any(nominal <= 0) or np.any(nominal >= 0.5 / dt):
        raise ValueError(f"lines_hz: {dict(lines_hz)} must lie in (0, {0.5 / dt}) Hz, the Nyquist frequency")
    if nominal.size > 1 and np.min(np.diff(np.sort(nominal))) <= 2.0 / record_s:
        raise ValueError(
            f"lines_hz: lines closer than 2 / T = {2 / record_s:.3g} Hz (the Hann weights' main lobe) are not resolved"
        )
    freqs = nominal.copy()
    if locate:
        rough = np.array([_fit_amplitudes(row, dt, nominal) for row in x])  # (axis, line)
        for i, f in enumerate(nominal):
            freqs[i] = spectrum.refine_by_sine_fit(x[int(np.argmax(rough[:, i]))], dt, f)
    amp = np.array([_fit_amplitudes(row, dt, freqs) for row in x])  # (axis, line)
    omega2 = (2 * np.pi * freqs) ** 2
    accel = amp * omega2 if kind == "displacement" else amp
    return levels_dataset(names, freqs, accel, axes)


def levels_dataset(names, freqs_hz, accel_m_s2, axes=AXES) -> xr.Dataset:
    """The levels table (line, axis) of lines `names` at `freqs_hz` with acceleration amplitudes (axis, line)."""
    freqs = np.asarray(freqs_hz, dtype=float)
    accel = np.asarray(accel_m_s2, dtype=float)
    ds = xr.Dataset(coords={"line": ("line", list(names)), "axis": ("axis", list(axes))})
    ds["line"].attrs = {"units": "1", "long_name": "vibration line (k/rev: k times the rotor frequency)"}
    ds["axis"].attrs = {"units": "1", "long_name": "translation axis, inertial frame (x forward, y left, z up)"}
    ds["freq_hz"] = ("line", freqs, {"units": "Hz", "long_name": "line frequency"})
    accel_t = accel.T  # (line, axis)
    velocity = accel_t / (2 * np.pi * freqs[:, None])
    table = {
        "accel_m_s2": (accel_t, "m s-2", "acceleration amplitude (0-peak)"),
        "accel_g": (accel_t / G, "g", "acceleration amplitude (0-peak), standard gravity 9.80665 m s-2"),
        "velocity_in_s": (velocity / INCH, "in s-1", "velocity amplitude (0-peak)"),
        "displacement_m": (velocity / (2 * np.pi * freqs[:, None]), "m", "displacement amplitude (0-peak)"),
    }
    for name, (values, units, long_name) in table.items():
        ds[name] = (("line", "axis"), values, {"units": units, "long_name": long_name})
    return ds


def track_and_balance(levels: xr.Dataset, *, line: str = "1/rev", axis: str = "y") -> xr.Dataset:
    """The levels' `line` on `axis` (default: the lateral 1/rev) against the hover track-and-balance limit
    (`TRACK_AND_BALANCE_LIMIT_IN_S`): its velocity (in/s 0-peak), the ratio to the limit and to the damage level."""
    if line not in levels.line.values:
        raise ValueError(f"line: {line!r} is not among the levels' lines {list(levels.line.values)}")
    velocity = float(levels.velocity_in_s.sel(line=line, axis=axis))
    return xr.Dataset(
        {
            "velocity_in_s": ((), velocity, {"units": "in s-1", "long_name": f"{line} velocity amplitude, {axis}"}),
            "limit_ratio": (
                (),
                velocity / TRACK_AND_BALANCE_LIMIT_IN_S,
                {"units": "1", "long_name": f"ratio to the track-and-balance limit ({TRACK_AND_BALANCE_SOURCE})"},
            ),
            "damage_ratio": (
                (),
                velocity / TRACK_AND_BALANCE_DAMAGE_IN_S,
                {"units": "1", "long_name": "ratio to the level the manual warns may damage the aircraft (1.2 in/s)"},
            ),
        }
    )
