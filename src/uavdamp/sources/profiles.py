"""Stated vibration sources: a sine-on-random helicopter source and a multirotor source at a stated VIBE level.

Both make a mount motion on a time grid from stated lines (frequency, acceleration amplitude in g 0-peak per axis
x, y, z of the inertial frame: x forward, y left, z up) and a random floor (one-sided acceleration PSD, g^2/Hz,
flat over a band), with a seeded `numpy.random.Generator`: a random phase per line and axis, the floor by random-
phase synthesis (every FFT bin of the band at the PSD's amplitude, uniform random phase; the record is periodic).
The displacement is the acceleration integrated twice in the frequency domain, d = -a / (2 pi f)^2, exact for the
lines (analytic) and per bin for the floor; `highpass_hz` states where that integration stops: a line or floor
below it is refused (the acceleration is then exactly the displacement's second derivative). Rotation lines are
optional (default none: a choice, the sources state translation only).

Helicopter: the shape is MIL-STD-810H Method 514.8's for helicopters (sine-on-random: lines at 1/rev, N/rev and
its harmonics, the tail rotor's lines, a broadband floor). The standard's tabulated line amplitudes and floor were
not available here, so every default level below is an assumption (`HELICOPTER_LEVELS` states each one and why);
none is the standard's. Multirotor: blade-pass lines (motor speed x blade count, per motor, with their
harmonics) and a floor, scaled so that ArduPilot's VIBE of the acceleration (`levels.vibe`) equals a stated level
(ArduPilot's guidance: 15 good, 30 marginal, 60 m s-2 bad, `levels.VIBE_GUIDANCE_M_S2`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from uavdamp.contract import MountMotion
from uavdamp.sources import levels as L

AXES = L.AXES


@dataclass(frozen=True)
class Line:
    """A sinusoidal line: `freq_hz` (Hz), acceleration amplitude per axis (x, y, z) in g 0-peak, and optionally a
    rotation amplitude per axis (rad 0-peak)."""

    name: str
    freq_hz: float
    accel_g: tuple[float, float, float]
    rotation_rad: tuple[float, float, float] = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Floor:
    """A random floor: one-sided acceleration PSD per axis (x, y, z), g^2/Hz, flat over `band_hz` (Hz)."""

    psd_g2_hz: tuple[float, float, float]
    band_hz: tuple[float, float]


# Default helicopter levels. Every value is an ASSUMPTION (no cited table); rationale per entry.
HELICOPTER_LEVELS = {
    # in/s 0-peak (x, y, z): a rotor at the hover lateral track-and-balance limit (levels.TRACK_AND_BALANCE_LIMIT_IN_S)
    # laterally, half of it fore-aft and a quarter vertically (assumption: a balanced, flyable rotor)
    "1/rev_in_s": (0.1, 0.2, 0.05),
    # g 0-peak (x, y, z) at N/rev: order of magnitude of a fuselage's N/rev (0.05-0.5 g), vertical largest (the
    # rotor's N/rev thrust), in-plane two thirds of it (assumption)
    "N/rev_g": (0.1, 0.1, 0.15),
    "2N/rev_g": (0.05, 0.05, 0.075),  # half of N/rev (assumption: harmonics decay)
    "3N/rev_g": (0.025, 0.025, 0.0375),  # a quarter of N/rev (assumption)
    "tail_1/rev_g": (0.01, 0.01, 0.01),  # g, tail-rotor imbalance (assumption)
    "tail_N/rev_g": (0.02, 0.05, 0.02),  # g, tail-rotor blade pass, lateral largest (tail thrust) (assumption)
    # floor: g^2/Hz per axis and band Hz (assumption: 0.03 g rms per axis, 5-100 Hz)
    "floor_g2_hz": (1e-5, 1e-5, 1e-5),
    "floor_band_hz": (5.0, 100.0),
}


def helicopter_lines(
    rotor_hz: float, blades: int, tail_hz: float | None = None, tail_blades: int = 2, levels=None
) -> tuple[Line, ...]:
    """The helicopter's lines: 1/rev, N/rev, 2N/rev, 3N/rev of the main rotor (rotor_hz Hz, `blades` blades) and
    the tail rotor's 1/rev and N/rev (tail_hz Hz, `tail_blades`; none if tail_hz is None), at `levels`
    (default `HELICOPTER_LEVELS`, all assumptions)."""
    lv = {**HELICOPTER_LEVELS, **(levels or {})}
    if not rotor_hz > 0 or blades < 1:
        raise ValueError(f"rotor_hz, blades: need rotor_hz > 0 and blades >= 1, got {rotor_hz}, {blades}")
    one = 2 * np.pi * rotor_hz * L.INCH / L.G  # g per in/s at 1/rev
    lines = [Line("1/rev", rotor_hz, tuple(v * one for v in lv["1/rev_in_s"]))]
    for k, key in ((1, "N/rev_g"), (2, "2N/rev_g"), (3, "3N/rev_g")):
        lines.append(Line(f"{k * blades}/rev", k * blades * rotor_hz, tuple(lv[key])))
    if tail_hz is not None:
        if not tail_hz > 0 or tail_blades < 1:
            raise ValueError(f"tail_hz, tail_blades: need > 0 and >= 1, got {tail_hz}, {tail_blades}")
        lines.append(Line("tail 1/rev", tail_hz, tuple(lv["tail_1/rev_g"])))
        lines.append(Line(f"tail {tail_blades}/rev", tail_blades * tail_hz, tuple(lv["tail_N/rev_g"])))
    return tuple(lines)


def helicopter_floor(levels=None) -> Floor:
    """The helicopter's random floor at `levels` (default `HELICOPTER_LEVELS`: an assumption)."""
    lv = {**HELICOPTER_LEVELS, **(levels or {})}
    return Floor(tuple(lv["floor_g2_hz"]), tuple(lv["floor_band_hz"]))


def _check(lines, floor: Floor | None, fs: float, highpass_hz: float) -> None:
    if not highpass_hz > 0:
        raise ValueError(f"highpass_hz: must be > 0, got {highpass_hz}")
    nyquist = 0.5 * fs
    for line in lines:
        if not highpass_hz <= line.freq_hz < nyquist:
            raise ValueError(
                f"lines[{line.name!r}].freq_hz: {line.freq_hz} Hz must lie in [highpass_hz, Nyquist) = "
                f"[{highpass_hz}, {nyquist}) Hz"
            )
    if floor is not None:
        lo, hi = floor.band_hz
        if not highpass_hz <= lo < hi < nyquist:
            raise ValueError(
                f"floor.band_hz: [{lo}, {hi}] Hz must satisfy highpass_hz ({highpass_hz}) <= low < high < Nyquist "
                f"({nyquist} Hz)"
            )
        if min(floor.psd_g2_hz) < 0:
            raise ValueError(f"floor.psd_g2_hz: must be >= 0, got {floor.psd_g2_hz}")


def _floor(floor: Floor, n: int, fs: float, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """(acceleration m s-2, displacement m), each (3, n): random-phase synthesis of the floor's PSD."""
    freq = np.fft.rfftfreq(n, 1.0 / fs)
    band = (freq >= floor.band_hz[0]) & (freq <= floor.band_hz[1])
    psd = np.asarray(floor.psd_g2_hz, dtype=float)[:, None] * L.G**2  # (m s-2)^2 / Hz
    # a cosine of amplitude c has variance c^2 / 2; a bin of width fs / n carries psd fs / n
    amplitude = np.sqrt(2 * psd * fs / n) * band  # (3, bins)
    phase = rng.uniform(0.0, 2 * np.pi, size=amplitude.shape)
    spectrum = 0.5 * n * amplitude * np.exp(1j * phase)
    omega2 = np.where(band, (2 * np.pi * freq) ** 2, 1.0)
    accel = np.fft.irfft(spectrum, n, axis=-1)
    disp = np.fft.irfft(-spectrum / omega2, n, axis=-1)
    return accel, disp


def sine_on_random(
    lines, floor: Floor | None, *, duration_s: float, sample_rate_hz: float, highpass_hz: float, seed: int
) -> xr.Dataset:
    """A sine-on-random mount motion: time (s, from 0, every 1 / sample_rate_hz to duration_s), mount_acceleration
    (m s-2), mount_displacement (m), mount_rotation (rad), each (mount_axis, time), and the stated levels: the
    lines' table (`levels.levels_dataset`: freq_hz, accel_g, velocity_in_s 0-peak, displacement_m), their rotation
    amplitudes and the floor's PSD and band. Seeded by `seed` (numpy Generator)."""
    lines = tuple(lines)
    _check(lines, floor, sample_rate_hz, highpass_hz)
    if not duration_s > 0:
        raise ValueError(f"duration_s: must be > 0, got {duration_s}")
    rng = np.random.default_rng(seed)
    n = int(round(duration_s * sample_rate_hz)) + 1
    t = np.arange(n) / sample_rate_hz
    accel, disp, rot = np.zeros((3, n)), np.zeros((3, n)), np.zeros((3, n))
    for line in lines:
        w = 2 * np.pi * line.freq_hz
        phase = rng.uniform(0.0, 2 * np.pi, size=(3, 1))
        wave = np.sin(w * t + phase)
        a = np.asarray(line.accel_g, dtype=float)[:, None] * L.G
        accel += a * wave
        disp -= a / w**2 * wave
        rot += np.asarray(line.rotation_rad, dtype=float)[:, None] * wave
    if floor is not None:
        floor_accel, floor_disp = _floor(floor, n, sample_rate_hz, rng)
        accel += floor_accel
        disp += floor_disp
    return _dataset(t, accel, disp, rot, lines, floor, highpass_hz, seed)


def _dataset(t, accel, disp, rot, lines, floor, highpass_hz, seed) -> xr.Dataset:
    table = L.levels_dataset(
        [line.name for line in lines],
        [line.freq_hz for line in lines],
        np.array([line.accel_g for line in lines]).T.reshape(3, len(lines)) * L.G,
    ).rename(axis="mount_axis")
    ds = xr.Dataset(coords={"time": ("time", t, {"units": "s", "long_name": "time from the start"})})
    frame = "inertial frame (x forward, y left, z up)"
    for name, values, units, what in (
        ("mount_acceleration", accel, "m s-2", "acceleration of the mount (input)"),
        ("mount_displacement", disp, "m", "translation of the mount (input)"),
        ("mount_rotation", rot, "rad", "rotation vector of the mount (input)"),
    ):
        ds[name] = (("mount_axis", "time"), values, {"units": units, "long_name": f"{what}, {frame}"})
    ds = ds.merge(table)
    ds["line_rotation_rad"] = (
        ("line", "mount_axis"),
        np.array([line.rotation_rad for line in lines]).reshape(len(lines), 3),
        {"units": "rad", "long_name": "rotation amplitude of the line (0-peak)"},
    )
    psd = floor.psd_g2_hz if floor is not None else (0.0, 0.0, 0.0)
    ds["floor_psd_g2_hz"] = ("mount_axis", np.asarray(psd, dtype=float), {"units": "g2 Hz-1", "long_name": "floor PSD"})
    ds.attrs.update(
        floor_band_hz=list(floor.band_hz) if floor is not None else [],
        highpass_hz=highpass_hz,
        seed=seed,
        levels="stated by the caller; the helicopter and multirotor defaults are assumptions (see the module)",
    )
    return ds


def mount_motion(source: xr.Dataset) -> MountMotion:
    """The source's mount motion (translation m, rotation rad; (3, n)) for a plant."""
    return MountMotion(source.mount_displacement.values, source.mount_rotation.values)


def helicopter_source(
    rotor_hz: float,
    blades: int,
    *,
    tail_hz: float | None = None,
    tail_blades: int = 2,
    levels=None,
    duration_s: float,
    sample_rate_hz: float,
    highpass_hz: float = 2.0,
    seed: int,
) -> xr.Dataset:
    """The sine-on-random helicopter source (`helicopter_lines`, `helicopter_floor`, all levels assumptions)."""
    lines = helicopter_lines(rotor_hz, blades, tail_hz, tail_blades, levels)
    ds = sine_on_random(
        lines,
        helicopter_floor(levels),
        duration_s=duration_s,
        sample_rate_hz=sample_rate_hz,
        highpass_hz=highpass_hz,
        seed=seed,
    )
    ds.attrs["source_kind"] = "helicopter sine-on-random (shape after MIL-STD-810H 514.8; levels: assumptions)"
    return ds


def multirotor_lines(
    motor_rpm: float,
    blades: int,
    motors: int,
    spread: float,
    harmonic_weights=(1.0, 0.5),
    axis_weights=(0.7, 0.7, 1.0),
) -> tuple[Line, ...]:
    """Blade-pass lines of `motors` motors at motor_rpm (rev/min) x (1 + spread u), u evenly spaced in [-1, 1]
    (choice), `blades` blades each: line k of motor i at k x rpm_i / 60 x blades Hz, amplitude (g) axis_weights x
    harmonic_weights[k-1] / sqrt(motors) before scaling (choices: relative levels only, the VIBE fixes the scale)."""
    if motor_rpm <= 0 or blades < 1 or motors < 1 or not 0 <= spread < 1:
        raise ValueError(
            f"motor_rpm, blades, motors, spread: need > 0, >= 1, >= 1, in [0, 1); got {motor_rpm}, {blades}, "
            f"{motors}, {spread}"
        )
    u = np.linspace(-1.0, 1.0, motors) if motors > 1 else np.zeros(1)
    lines = []
    for i, rpm in enumerate(motor_rpm * (1 + spread * u)):
        for k, weight in enumerate(harmonic_weights, start=1):
            amp = tuple(float(a * weight / np.sqrt(motors)) for a in axis_weights)
            lines.append(Line(f"motor {i + 1} {k}x blade pass", k * rpm / 60.0 * blades, amp))
    return tuple(lines)


def multirotor_source(
    vibe_m_s2: float,
    *,
    motor_rpm: float = 3000.0,
    blades: int = 2,
    motors: int = 4,
    spread: float = 0.05,
    harmonic_weights=(1.0, 0.5),
    axis_weights=(0.7, 0.7, 1.0),
    floor_share: float = 0.2,
    floor_band_hz=(20.0, 400.0),
    duration_s: float,
    sample_rate_hz: float = 1000.0,
    highpass_hz: float = 5.0,
    seed: int,
) -> xr.Dataset:
    """A multirotor mount motion whose VIBE (`levels.vibe`, largest axis) equals `vibe_m_s2` (m s-2).

    Lines: `multirotor_lines` (default 3000 rpm x 2 blades: 100 Hz blade pass, within the 70-140 Hz of a small
    quad, and 200 Hz). Floor: a share `floor_share` of each axis's variance (choice), flat over floor_band_hz.
    One factor scales lines and floor (the axes' ratios kept): VIBE is linear in it, so the level is met to
    round-off on this record. Defaults (rpm, weights, share, band, 1 kHz as an IMU rate) are choices."""
    if not vibe_m_s2 > 0 or not 0 <= floor_share < 1:
        raise ValueError(f"vibe_m_s2, floor_share: need > 0 and in [0, 1), got {vibe_m_s2}, {floor_share}")
    lines = multirotor_lines(motor_rpm, blades, motors, spread, harmonic_weights, axis_weights)
    line_var = 0.5 * np.sum(np.array([line.accel_g for line in lines]) ** 2, axis=0)  # g^2 per axis
    width = floor_band_hz[1] - floor_band_hz[0]
    psd = tuple(float(v) for v in line_var * floor_share / (1 - floor_share) / width)
    raw = sine_on_random(
        lines,
        Floor(psd, tuple(floor_band_hz)) if floor_share > 0 else None,
        duration_s=duration_s,
        sample_rate_hz=sample_rate_hz,
        highpass_hz=highpass_hz,
        seed=seed,
    )
    factor = vibe_m_s2 / float(np.max(L.vibe(raw.mount_acceleration.values, 1.0 / sample_rate_hz)))
    ds = raw.copy()
    scaled = ("mount_acceleration", "mount_displacement", "accel_m_s2", "accel_g", "velocity_in_s", "displacement_m")
    for name in scaled:
        ds[name] = raw[name].copy(data=raw[name].values * factor)
    ds["floor_psd_g2_hz"] = raw.floor_psd_g2_hz.copy(data=raw.floor_psd_g2_hz.values * factor**2)
    ds["vibe_m_s2"] = (
        "mount_axis",
        L.vibe(ds.mount_acceleration.values, 1.0 / sample_rate_hz),
        {"units": "m s-2", "long_name": "ArduPilot VIBE of the mount acceleration (steady level)"},
    )
    ds.attrs.update(source_kind="multirotor blade-pass lines and floor", stated_vibe_m_s2=vibe_m_s2)
    return ds
