"""Platform inputs: mono-frequency sines and the study's cases from a helicopter run or a measured flight.

A case takes the first `duration` seconds of a helicopter run's motion at its mount point (or of a measured
flight's, `uavdamp.read_flight_log`, from the case's window_s start), removes the slow rigid-body drift with a zero-
phase Butterworth high-pass (in the vacuum runs the free fuselage wobbles at about 1 Hz; the rotor's vibration lies
at 7-8 Hz; a flight log comes band-passed by its reader and is not filtered again), and scales it so that a reading
of its y and z amplitude equals the case's `amplitude` (paper: 1.3 mm). `motion: planar` keeps the paper's input,
the y and z translation only; `full` keeps all of it: the x translation and the rotation too, both scaled by the
common factor (the one of the larger y/z reading: choice, one factor keeps the rigid body's motion consistent).
Readings: "peak", the largest |displacement|; "dominant", the amplitude of the dominant spectral line in the band
(the paper's inputs are mono-frequency sines of a given amplitude). Scalings: "per_axis", each axis to the amplitude
(the helicopter's Y/Z ratio is lost); "common", one factor for both axes, set by the axis with the larger reading
(choice: the amplitude is the input's, whichever axis carries it), which keeps the helicopter's Y/Z ratio;
"measured", no scaling (a flight log's motion as flown).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import xarray as xr

from uavdamp.contract import AXES, MOUNT_AXES, MountMotion  # the axes a case scales and reads; the mount's
from uavdamp.settings import require, setting
from uavdamp.signals import spectrum
from uavdamp.signals.tracking import TrackerOptions

READINGS = ("peak", "dominant")
SCALINGS = ("per_axis", "common", "measured")
MOTIONS = ("planar", "full")


@dataclass(frozen=True, kw_only=True)
class Case:
    """One input case of the study (``study.cases.NAME``): a helicopter run at a mount point (`run`, `mount`) or a
    measured flight (`flight_log`, a name of the ``flight_logs`` section, from `window_s`), scaled to `amplitude`
    (m) as read, or taken as measured (amplitude_scaling: measured, no amplitude_m). A key set to null counts as
    absent (how a profile merged over config.yaml turns a helicopter case into a flight-log one)."""

    run: str | None = setting(default=None)  # helicopter run: balanced | imbalanced | both_rotors | hover | forward
    mount: str | None = setting(default=None)  # the mount point (helicopter.mount_points_m) of a helicopter case
    flight_log: str | None = setting(default=None)  # a measured flight: a name of the flight_logs section
    stated: str | None = setting("source", default=None)  # a stated source: a name of the sources section
    window_s: tuple[float, ...] | None = setting(default=None, length=2)  # s, where in the log the case starts
    amplitude: float | None = setting("amplitude_m", default=None)  # m
    amplitude_reading: str | None = setting(default=None)  # peak | dominant (not with measured)
    amplitude_scaling: str = setting()  # per_axis | common | measured
    motion: str = setting()  # planar (y, z translation: the paper's) | full (x, y, z translation and rotation)
    description: str = setting(default="")

    def validate(self, where: str) -> None:
        one = sum(bool(k) for k in (self.run, self.flight_log, self.stated)) == 1
        require(one, where, "needs exactly one source: run (a helicopter run), flight_log or source (sources.NAME)")
        if self.stated:
            require(not self.mount and self.window_s is None, where, "a stated source has no mount and no window")
            ok = self.amplitude_scaling in ("measured", "common")
            rule = "must be measured or common for a stated source: per_axis would change its ratios between axes"
            require(ok, f"{where}.amplitude_scaling", f"{rule}, got {self.amplitude_scaling!r}")
        elif self.run:
            require(bool(self.mount), f"{where}.mount", "a helicopter case needs its mount point")
            require(self.window_s is None, f"{where}.window_s", "only a flight_log case has a window")
        else:
            require(not self.mount, f"{where}.mount", "a flight_log case is at its log's mount (flight_logs.NAME)")
            if self.window_s is not None:
                start, end = self.window_s
                require(0 <= start < end, f"{where}.window_s", f"needs 0 <= start < end, got {list(self.window_s)}")
        if self.amplitude_scaling != "measured":
            ok = self.amplitude is not None and self.amplitude > 0
            rule = f"must be > 0 unless amplitude_scaling is measured, got {self.amplitude}"
            require(ok, f"{where}.amplitude_m", rule)
        else:
            rule = f"is not used with amplitude_scaling: measured (set it to null), got {self.amplitude}"
            require(self.amplitude is None, f"{where}.amplitude_m", rule)
        checked = (("amplitude_scaling", SCALINGS), ("motion", MOTIONS))
        if self.amplitude_scaling != "measured":
            checked += (("amplitude_reading", READINGS),)
        for key, choices in checked:
            value = getattr(self, key)
            require(value in choices, f"{where}.{key}", f"must be one of {list(choices)}, got {value!r}")

    @property
    def source(self) -> str:
        """Where the case's motion comes from, as the error messages name it."""
        if self.stated:
            return f"stated source {self.stated!r}"
        return f"helicopter run {self.run!r}" if self.run else f"flight log {self.flight_log!r}"


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
    from scipy.signal import butter, sosfiltfilt

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


def source_motion(source: xr.Dataset, case: Case, where: str) -> tuple[np.ndarray, xr.DataArray, xr.DataArray]:
    """(time s from 0, translation (axis, time) m, rotation (axis, time) rad) a case takes from its source: a
    helicopter run at the case's mount point, or a flight log (`uavdamp.read_flight_log`) inside the case's
    window_s (s of the log's clock; default: all the log can be trusted, edge_s in from either end)."""
    if case.stated:
        pass  # a stated source is taken whole, from its start
    elif case.run:
        if case.mount not in source.mount.values:
            known = list(source.mount.values)
            raise ValueError(f"{where}.mount: {case.mount!r} is not a mount point of the run ({known})")
        source = source.sel(mount=case.mount)
    else:
        first, last = (float(v) for v in source.attrs["log_window_s"])
        edge = float(source.attrs["edge_s"])
        start, end = case.window_s if case.window_s is not None else (first + edge, last - edge)
        if start < first + edge - 1e-9 or end > last - edge + 1e-9:
            raise ValueError(
                f"{where}.window_s: [{start}, {end}] s must lie within [{first + edge:.3f}, {last - edge:.3f}] s: "
                f"the log's window [{first:.3f}, {last:.3f}] s less edge_s = {edge:.3f} s at either end, where the "
                "band-limited integration is not to be trusted"
            )
        source = source.sel(time=slice(start - first - 1e-9, end - first + 1e-9))
    t = source.time.values
    return t - t[0], source.mount_displacement, source.mount_rotation


def case_input(
    source: xr.Dataset, case: Case, where: str, *, duration: float, highpass_hz: float, band_hz: tuple[float, float]
) -> tuple[np.ndarray, MountMotion, dict[str, tuple]]:
    """(time s, the scaled mount motion, {statistic: per-axis (y, z) values}) of one case from its source (a
    helicopter run or a flight log, `source_motion`)."""
    t, moved, turned = source_motion(source, case, where)
    dt = float(np.mean(np.diff(t)))
    keep = t < duration + dt - 1e-9  # up to the first sample at or after `duration` (a solver grid reaches it)
    if t[keep][-1] < duration - 1e-9:
        raise ValueError(f"study.duration_s: {duration} s is longer than the {case.source} ({t[-1]:.3f} s) of {where}")

    def filtered(values: np.ndarray) -> np.ndarray:  # a flight log comes band-passed by its reader
        return (high_pass(values, dt, highpass_hz) if case.run else values)[keep]

    raw = {axis: filtered(moved.sel(axis=axis).values) for axis in MOUNT_AXES}
    scaled = {a: raw[a] for a in AXES}
    if case.amplitude_scaling == "measured":
        factors, common = dict.fromkeys(AXES, 1.0), 1.0
    else:
        reading = {"amplitude": case.amplitude, "reading": case.amplitude_reading, "band_hz": band_hz}
        factors = scale_factors(scaled, dt, scaling=case.amplitude_scaling, **reading)
        common = scale_factors(scaled, dt, scaling="common", **reading)["y"]  # the larger reading's factor
    full = case.motion == "full"
    rotation = np.stack([filtered(turned.sel(axis=a).values) for a in MOUNT_AXES])
    translation = np.stack([common * raw["x"] * full, factors["y"] * raw["y"], factors["z"] * raw["z"]])
    motion = MountMotion(translation, common * rotation * full)
    rows = {"y": translation[1], "z": translation[2]}
    stats = {
        "scale": tuple(factors[a] for a in AXES),
        "dominant_freq": tuple(
            spectrum.dominant_frequency(rows[a], dt, min_freq_hz=band_hz[0], max_freq_hz=band_hz[1]) for a in AXES
        ),
        "dominant_amplitude": tuple(dominant_line_amplitude(rows[a], dt, *band_hz) for a in AXES),
        "spectral_width": tuple(spectral_width_hz(rows[a], dt, *band_hz) for a in AXES),
        "rotation_scale": common if full else 0.0,
    }
    return t[keep], motion, stats


_CASE_STATS = {
    "scale": ("1", "factor from the high-passed helicopter signal to the input"),
    "dominant_freq": ("Hz", "dominant frequency of the whole input"),
    "spectral_width": ("Hz", "RMS width of the input's power spectrum in the band"),
    "dominant_amplitude": ("m", "amplitude of the input's dominant line in the band"),
}


def cases_dataset(
    runs: dict[str, xr.Dataset], options: ExcitationOptions, logs: dict | None = None, stated: dict | None = None
) -> xr.Dataset:
    """The study's inputs: `mount_displacement` (case, mount_axis, time), m, and `mount_rotation` (case, mount_axis,
    time), rad (inertial frame, `uavdamp.contract.MountMotion`), one case per entry of `options.cases`, from the
    helicopter `runs`, the flight `logs` (name -> `uavdamp.read_flight_log` dataset) or the `stated` sources (name
    -> `uavdamp.sources.stated.generate` dataset), plus per case and axis (y, z) the scale applied, the dominant
    frequency, the dominant line's amplitude and the spectral width in the tracker's band (Hz), where the
    "dominant" reading looks for its line. Cases sampled at different rates are brought onto the finest one
    (`on_common_grid`); `sample_rate_hz` records each case's own. A run flown on an unconverged trim (its
    attribute trim_converged = 0) is flagged in the attribute ``warning``."""
    names, cases, logs, stated, flags = list(options.cases), [], logs or {}, stated or {}, []
    for name in names:
        case, where = options.cases[name], f"study.cases.{name}"
        if case.stated:
            sources, key, chosen = stated, "source", case.stated
        elif case.run:
            sources, key, chosen = runs, "run", case.run
        else:
            sources, key, chosen = logs, "flight_log", case.flight_log
        if chosen not in sources:
            raise ValueError(f"{where}.{key}: unknown {key.replace('_', ' ')} {chosen!r} (known: {sorted(sources)})")
        band = options.band_hz
        cases.append(
            case_input(
                sources[chosen], case, where, duration=options.duration_s, highpass_hz=options.highpass_hz, band_hz=band
            )
        )
        if case.run and int(sources[chosen].attrs.get("trim_converged", 1)) == 0:
            flags.append(f"{where}: run {chosen!r} flown on an unconverged trim: {sources[chosen].attrs['warning']}")
    time, motions, rates, drift = on_common_grid([(t, m) for t, m, _ in cases], names)
    ds = _cases_variables(options, names, time, motions, [s for _, _, s in cases])
    ds["sample_rate_hz"] = ("case", rates, {"units": "Hz", "long_name": "the case's own sampling rate (its source's)"})
    ds["grid_timing_error_s"] = (
        "case",
        drift,
        {"units": "s", "long_name": "timing error gathered over the record when brought onto the common grid"},
    )
    return ds.assign_attrs(warning="; ".join(flags)) if flags else ds


# the timing error a case may gather over its record when brought onto another grid, in periods of its Nyquist
# frequency (choice: 1e-4, a phase error below 6.3e-4 rad at any frequency it holds)
DRIFT_NYQUIST_PERIODS = 1e-4


def grid_ratio(step: float, finest: float, span_s: float) -> Fraction:
    """up / down (a Fraction) that brings a case sampled every `step` s onto the `finest` step: the simplest ratio
    (denominator up to 2^16) whose step mismatch, gathered over `span_s`, stays below DRIFT_NYQUIST_PERIODS of the
    case's Nyquist period 2 step. ValueError when none does (a rate ratio too irrational for 2^16)."""
    exact, allowed = step / finest, DRIFT_NYQUIST_PERIODS * 2 * step  # s: the timing error the record may gather
    for bits in range(6, 17):
        ratio = Fraction(exact).limit_denominator(2**bits)
        if abs(step / float(ratio) - finest) * span_s / finest <= allowed:
            return ratio
    raise ValueError(f"no ratio of denominator up to 65536 brings a {step:.6g} s step onto {finest:.6g} s")


def on_common_grid(cases: list[tuple[np.ndarray, MountMotion]], names: list[str]):
    """(time s, motions, each case's own rate Hz, each case's timing error s) with every case on the finest
    sampling among them: a coarser case is resampled band-limited (`scipy.signal.resample_poly` by `grid_ratio`;
    the timing error is what the ratio's mismatch gathers over the record, below DRIFT_NYQUIST_PERIODS of the
    case's Nyquist period), the same case sampled alike stays exactly as it was; all are cut to the shortest."""
    from scipy.signal import resample_poly

    steps = [float(np.mean(np.diff(t))) for t, _ in cases]
    finest = min(steps)
    out, drift = [], []
    for (t, motion), step, name in zip(cases, steps, names, strict=True):
        span = float(t[-1] - t[0])
        try:
            ratio = grid_ratio(step, finest, span)
        except ValueError as error:
            raise ValueError(f"study.cases.{name}: {error} (resample its source)") from None
        drift.append(abs(step / float(ratio) - finest) * span / finest)
        if ratio == 1:
            out.append(motion)
            continue
        up, down = ratio.numerator, ratio.denominator
        moved = [resample_poly(x, up, down, axis=1) for x in (motion.translation, motion.rotation)]
        out.append(MountMotion(*moved))
    n = min(m.translation.shape[1] for m in out)
    time = np.arange(n) * finest
    motions = [MountMotion(m.translation[:, :n], m.rotation[:, :n]) for m in out]
    return time, motions, [1.0 / s for s in steps], drift


def _cases_variables(options: ExcitationOptions, names, time, motions, stats) -> xr.Dataset:
    cases = [options.cases[n] for n in names]
    per_case = {
        "amplitude": (
            [math.nan if c.amplitude is None else c.amplitude for c in cases],
            "m",
            "input amplitude as read by amplitude_reading (NaN: as measured)",
        ),
        "amplitude_reading": ([c.amplitude_reading or "" for c in cases], "1", "reading: peak or dominant line"),
        "amplitude_scaling": ([c.amplitude_scaling for c in cases], "1", "scaling: per axis, one factor or none"),
        "motion": ([c.motion for c in cases], "1", "planar (y, z translation) or full (translation and rotation)"),
        "source": ([c.source for c in cases], "1", "helicopter run, flight log or stated source the case takes"),
        "mount": ([c.mount for c in cases], "1", "mount point of the helicopter run (empty: a flight log's mount)"),
        "rotation_scale": ([s["rotation_scale"] for s in stats], "1", "factor of the x translation and the rotation"),
        "description": ([c.description for c in cases], "1", "case description"),
    }
    frame = {"frame": "inertial: x forward, y left, z up (the fuselage axes at t = 0)"}
    data = {
        "mount_displacement": (
            ("case", "mount_axis", "time"),
            np.asarray([m.translation for m in motions]),
            {"units": "m", "long_name": "translation of the platform mount (input)", **frame},
        ),
        "mount_rotation": (
            ("case", "mount_axis", "time"),
            np.asarray([m.rotation for m in motions]),
            {"units": "rad", "long_name": "rotation vector of the platform mount (input)", **frame},
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
        "mount_axis": ("mount_axis", list(MOUNT_AXES), {"units": "1", "long_name": "mount axis (x forward, y, z up)"}),
        "time": ("time", time - time[0], {"units": "s", "long_name": "time"}),
    }
    return xr.Dataset(data, coords=coords, attrs={"highpass_hz": options.highpass_hz, "duration_s": options.duration_s})


def case_motion(cases: xr.Dataset, case: str) -> MountMotion:
    """The mount motion of one case of a `cases_dataset`."""
    one = cases.sel(case=case)
    return MountMotion(
        one.mount_displacement.transpose("mount_axis", "time").values,
        one.mount_rotation.transpose("mount_axis", "time").values,
    )


def sine_input(freq_y_hz: float, freq_z_hz: float, amplitude: float, duration: float, time_step: float):
    """Mono-frequency mount input: (time s, MountMotion) with y = A sin(2 pi f_y t), z likewise (A in m), no x
    translation and no rotation."""
    t = np.arange(int(round(duration / time_step)) + 1) * time_step
    y, z = (amplitude * np.sin(2 * np.pi * f * t) for f in (freq_y_hz, freq_z_hz))
    return t, MountMotion.planar(y, z)
