"""Platform inputs: mono-frequency sines, resampling onto a solver grid, and the cases from the helicopter.

A case takes the first `duration` seconds of a helicopter run's mount-point displacement (y and z),
removes the free fuselage's slow rigid-body drift with a zero-phase Butterworth high-pass (there is
no aerodynamic restoring force in the model, so the fuselage wobbles at about 1 Hz; the rotor's
vibration lies at 7-8 Hz), and scales it so that a reading of its amplitude equals the case's
`amplitude` (paper: 1.3 mm). Readings: "peak", the largest |displacement|; "dominant", the amplitude
of the dominant spectral line in the band (the paper's inputs are mono-frequency sines of a given
amplitude). Scalings: "per_axis", each axis to the amplitude (the helicopter's Y/Z ratio is lost);
"common", one factor for both axes, set by the axis with the larger reading (choice: the amplitude
is the input's, whichever axis carries it), which keeps the helicopter's Y/Z ratio.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr
from scipy.signal import butter, sosfiltfilt

from uavdamp import spectrum
from uavdamp.settings import require, setting
from uavdamp.tracking import TrackerOptions

AXES = ("y", "z")
READINGS = ("peak", "dominant")
SCALINGS = ("per_axis", "common")


@dataclass(frozen=True)
class Case:
    """One input case of the study (``study.cases.NAME``): a helicopter run, scaled to `amplitude` (m) as read."""

    run: str = setting()  # helicopter run: balanced | imbalanced | both_rotors | hover | forward
    mount: str = setting()  # the mount point (helicopter.mount_points_m) whose motion the case takes
    amplitude: float = setting("amplitude_m")  # m
    amplitude_reading: str = setting()  # peak | dominant
    amplitude_scaling: str = setting()  # per_axis | common
    description: str = setting(default="")

    def validate(self, where: str) -> None:
        require(self.amplitude > 0, f"{where}.amplitude_m", f"must be > 0, got {self.amplitude}")
        for key, choices in (("amplitude_reading", READINGS), ("amplitude_scaling", SCALINGS)):
            value = getattr(self, key)
            require(value in choices, f"{where}.{key}", f"must be one of {list(choices)}, got {value!r}")


@dataclass(frozen=True, kw_only=True)
class ExcitationOptions:
    """The excitation stage's view of ``study``: the cases, the run length, the high-pass, the tracker's band."""

    cases: dict[str, Case] = setting()
    duration_s: float = setting()  # s, from the helicopter's start
    highpass_hz: float = setting()  # Hz
    tracking: TrackerOptions = setting()

    def validate(self) -> None:
        require(bool(self.cases), "study.cases", "needs at least one case")
        require(self.duration_s > 0, "study.duration_s", f"must be > 0, got {self.duration_s}")
        require(self.highpass_hz > 0, "study.highpass_hz", f"must be > 0, got {self.highpass_hz}")

    @property
    def band_hz(self) -> tuple[float, float]:
        """The tracker's band, Hz: where the dominant line is read."""
        return self.tracking.min_freq_hz, self.tracking.max_freq_hz


def high_pass(signal: np.ndarray, dt: float, cutoff_hz: float, order: int = 4) -> np.ndarray:
    """Zero-phase Butterworth high-pass of `signal` sampled every `dt` s (cutoff in Hz)."""
    if not 0 < cutoff_hz < 0.5 / dt:
        raise ValueError(f"highpass_hz: {cutoff_hz} Hz must lie between 0 and the Nyquist frequency {0.5 / dt} Hz")
    sos = butter(order, cutoff_hz, btype="highpass", fs=1.0 / dt, output="sos")
    return sosfiltfilt(sos, signal)


def spectral_width_hz(signal: np.ndarray, dt: float, min_freq_hz: float, max_freq_hz: float) -> float:
    """RMS width (Hz) of the power spectrum around its centroid within the band: how wide a spectrum is."""
    freq, amp = spectrum.amplitude_spectrum(signal, dt, zero_padding=4)
    band = (freq >= min_freq_hz) & (freq <= max_freq_hz)
    power = amp[band] ** 2
    centre = np.sum(freq[band] * power) / np.sum(power)
    return float(np.sqrt(np.sum((freq[band] - centre) ** 2 * power) / np.sum(power)))


def dominant_line_amplitude(
    signal: np.ndarray, dt: float, min_freq_hz: float, max_freq_hz: float, *, zero_padding: int = 16
) -> float:
    """Amplitude (the signal's unit) of the largest line in [min_freq_hz, max_freq_hz] Hz: the peak of the
    Hann-windowed amplitude spectrum with the window's coherent gain divided out (`spectrum.amplitude_spectrum`),
    zero-padded `zero_padding` times so that the peak lies within 1 / (2 zero_padding) bin of the line (Hann
    scalloping loss there: 0.06 % at 16). Lines nearer than about 2 / record length blend."""
    freq, amp = spectrum.amplitude_spectrum(signal, dt, zero_padding=zero_padding)
    band = (freq >= min_freq_hz) & (freq <= max_freq_hz)
    if not np.any(band):
        raise ValueError(f"band_hz: [{min_freq_hz}, {max_freq_hz}] Hz holds no spectral bin")
    return float(np.max(amp[band]))


def amplitude_reading(signal: np.ndarray, dt: float, reading: str, band_hz: tuple[float, float]) -> float:
    """The signal's amplitude as `reading` reads it: "peak" (max |signal|) or "dominant"
    (`dominant_line_amplitude` in band_hz, Hz)."""
    if reading == "peak":
        return float(np.max(np.abs(signal)))
    return dominant_line_amplitude(signal, dt, *band_hz)


def scale_factors(
    raw: dict[str, np.ndarray], dt: float, *, amplitude: float, reading: str, scaling: str, band_hz: tuple[float, float]
) -> dict[str, float]:
    """Per axis, the factor that brings the high-passed `raw` signals (axis -> array) to `amplitude` under
    `reading`: "per_axis" scales every axis to it, "common" scales both by the factor of the larger reading."""
    readings = {axis: amplitude_reading(x, dt, reading, band_hz) for axis, x in raw.items()}
    if scaling == "common":
        common = amplitude / max(readings.values())
        return {axis: common for axis in raw}
    return {axis: amplitude / value for axis, value in readings.items()}


def case_input(
    run: xr.Dataset, case: Case, where: str, *, duration: float, highpass_hz: float, band_hz: tuple[float, float]
) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, tuple]]:
    """(time s, {axis: input m}, {statistic: per-axis values}) of one case from its helicopter run."""
    t = run.time.values
    keep = t <= duration + 1e-9
    if t[keep][-1] < duration - 1e-9:
        raise ValueError(f"study.duration_s: {duration} s is longer than the helicopter run ({t[-1]} s) of {where}")
    dt = float(np.mean(np.diff(t)))
    if case.mount not in run.mount.values:
        raise ValueError(f"{where}.mount: {case.mount!r} is not a mount point of the run ({list(run.mount.values)})")
    motion = run.mount_displacement.sel(mount=case.mount)
    raw = {axis: high_pass(motion.sel(axis=axis).values, dt, highpass_hz)[keep] for axis in AXES}
    factors = scale_factors(
        raw,
        dt,
        amplitude=case.amplitude,
        reading=case.amplitude_reading,
        scaling=case.amplitude_scaling,
        band_hz=band_hz,
    )
    rows = {axis: factors[axis] * raw[axis] for axis in AXES}
    stats = {
        "scale": tuple(factors[a] for a in AXES),
        "dominant_freq": tuple(
            spectrum.dominant_frequency(rows[a], dt, min_freq_hz=band_hz[0], max_freq_hz=band_hz[1]) for a in AXES
        ),
        "dominant_amplitude": tuple(dominant_line_amplitude(rows[a], dt, *band_hz) for a in AXES),
        "spectral_width": tuple(spectral_width_hz(rows[a], dt, *band_hz) for a in AXES),
    }
    return t[keep], rows, stats


_CASE_STATS = {
    "scale": ("1", "factor from the high-passed helicopter signal to the input"),
    "dominant_freq": ("Hz", "dominant frequency of the whole input"),
    "spectral_width": ("Hz", "RMS width of the input's power spectrum in the band"),
    "dominant_amplitude": ("m", "amplitude of the input's dominant line in the band"),
}


def cases_dataset(runs: dict[str, xr.Dataset], options: ExcitationOptions) -> xr.Dataset:
    """The study's inputs: `mount_displacement` (case, axis, time), m, one case per entry of `options.cases`, plus
    per case and axis the scale applied, the dominant frequency, the dominant line's amplitude and the spectral
    width in the tracker's band (Hz), where the "dominant" reading looks for its line."""
    names, time, signals, stats = list(options.cases), None, [], []
    for name in names:
        case, where = options.cases[name], f"study.cases.{name}"
        if case.run not in runs:
            raise ValueError(f"{where}.run: unknown helicopter run {case.run!r} (known: {sorted(runs)})")
        t, rows, found = case_input(
            runs[case.run],
            case,
            where,
            duration=options.duration_s,
            highpass_hz=options.highpass_hz,
            band_hz=options.band_hz,
        )
        if time is not None and (time.size != t.size or not np.allclose(time, t)):
            raise ValueError("helicopter runs of different cases are sampled differently")
        time = t
        signals.append([rows[a] for a in AXES])
        stats.append(found)
    cases = [options.cases[n] for n in names]
    per_case = {
        "amplitude": ([c.amplitude for c in cases], "m", "input amplitude as read by amplitude_reading"),
        "amplitude_reading": (
            [c.amplitude_reading for c in cases],
            "1",
            "reading of the amplitude: peak or dominant line",
        ),
        "amplitude_scaling": (
            [c.amplitude_scaling for c in cases],
            "1",
            "scaling: per axis or one factor for both axes",
        ),
        "description": ([c.description for c in cases], "1", "case description"),
    }
    data = {
        "mount_displacement": (
            ("case", "axis", "time"),
            np.asarray(signals),
            {"units": "m", "long_name": "fuselage displacement at the platform mount (input)"},
        ),
        **{
            k: (("case", "axis"), [s[k] for s in stats], {"units": u, "long_name": n})
            for k, (u, n) in _CASE_STATS.items()
        },
        **{k: ("case", v, {"units": u, "long_name": n}) for k, (v, u, n) in per_case.items()},
    }
    coords = {
        "case": ("case", names, {"units": "1", "long_name": "input case"}),
        "axis": ("axis", list(AXES), {"units": "1", "long_name": "direction (y lateral, z up)"}),
        "time": ("time", time - time[0], {"units": "s", "long_name": "time"}),
    }
    return xr.Dataset(data, coords=coords, attrs={"highpass_hz": options.highpass_hz, "duration_s": options.duration_s})


def sine_input(freq_y_hz: float, freq_z_hz: float, amplitude: float, duration: float, time_step: float):
    """Mono-frequency mount input: (time s, y m, z m) with y = A sin(2 pi f_y t), z likewise; A in m."""
    t = np.arange(int(round(duration / time_step)) + 1) * time_step
    return t, amplitude * np.sin(2 * np.pi * freq_y_hz * t), amplitude * np.sin(2 * np.pi * freq_z_hz * t)


def on_grid(time, mount_y, mount_z, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Validated input resampled (linearly) onto the solver grid 0, h, 2h, ... <= time[-1] (s, m, m)."""
    time = np.asarray(time, dtype=float)
    mount_y = np.asarray(mount_y, dtype=float)
    mount_z = np.asarray(mount_z, dtype=float)
    if time.ndim != 1 or time.size < 2 or not np.all(np.diff(time) > 0):
        raise ValueError("time must be 1-D, increasing, with at least 2 samples")
    if abs(time[0]) > 1e-12:
        raise ValueError(f"time must start at 0 s, got {time[0]}")
    if mount_y.shape != time.shape or mount_z.shape != time.shape:
        raise ValueError("mount_y and mount_z must have the shape of time")
    if not (np.all(np.isfinite(mount_y)) and np.all(np.isfinite(mount_z))):
        raise ValueError("mount_y and mount_z must be finite")
    steps = int(math.floor(time[-1] / h + 1e-9))
    if steps < 1:
        raise ValueError(f"time must reach at least one time_step ({h} s)")
    grid = np.arange(steps + 1) * h
    return grid, np.interp(grid, time, mount_y), np.interp(grid, time, mount_z)
