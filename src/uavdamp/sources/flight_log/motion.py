"""A flight log's IMU -> the mount's motion (`read_flight_log`), after every check of the package."""

from __future__ import annotations

import hashlib
import warnings
from pathlib import Path

import numpy as np
import xarray as xr

from uavdamp.signals import inertial
from uavdamp.sources.flight_log import airborne, aliasing, checks, spectra
from uavdamp.sources.flight_log.ardupilot import read_dataflash
from uavdamp.sources.flight_log.formats import FORMAT_NAMES, detect_format, read_csv
from uavdamp.sources.flight_log.px4 import read_ulog
from uavdamp.sources.flight_log.records import AXES, POLICIES, FlightLogError, ImuRecord

READERS = {"ulog": read_ulog, "dataflash": read_dataflash, "csv": read_csv}


def read_record(path) -> tuple[str, ImuRecord]:
    """(format, record) of a log, its samples and timestamps checked (`checks.check_record`)."""
    path = Path(path)
    fmt = detect_format(path)
    record = READERS[fmt](path)
    checks.check_record(path, record)
    return fmt, record


def _checked_band(band_hz) -> tuple[float, float]:
    low, high = (float(v) for v in band_hz)
    if not 0 < low < high:
        raise ValueError(f"band_hz: need 0 < low < high, got {band_hz}")
    return low, high


def _policy(name: str, value: str) -> str:
    if value not in POLICIES:
        raise ValueError(f"{name}: one of {list(POLICIES)}, got {value!r}")
    return value


def _apply(path, policy: str, problems: list[str], fix: str) -> str:
    """Refuse (FlightLogError naming them and the fix) or warn; the problems as one string ("none")."""
    if not problems:
        return "none"
    text = "; ".join(problems)
    if policy == "refuse":
        raise FlightLogError(path, f"{text}; {fix}")
    warnings.warn(f"{path}: {text} (recorded)", stacklevel=3)
    return text


def read_flight_log(
    path,
    *,
    band_hz,
    window_s=None,
    imu_to_mount_m=(0.0, 0.0, 0.0),
    upsample: int = 1,
    on_aliasing: str = "refuse",
    on_ground: str = "refuse",
    on_bad_samples: str = "refuse",
    blades: int = 2,
) -> xr.Dataset:
    """Mount motion from a flight log's IMU (the package docstring): `mount_displacement` (axis, time), m, and
    `mount_rotation` (axis, time), rad (small-angle rotation vector: integrated body rates), in band_hz =
    (f_low, f_high), Hz, plus the resampled `acceleration` (specific force, gravity included; m s-2) and
    `angular_rate` (rad s-1) at the mount before the band-pass. Axes x forward, y left, z up.

    window_s: (start, end), s of the log's own clock, default the whole log; the grid starts at the first
    sample inside it (time 0) with the median interval. imu_to_mount_m: mount minus IMU position, m; a_mount =
    a_imu + dw/dt x r + w x (w x r). upsample: the output every median interval / upsample s (band-limited
    interpolation of the displacement and rotation). on_aliasing, on_ground, on_bad_samples: "refuse" (a
    FlightLogError) or "record" (a warning and the attributes) for a vehicle line above the stream's Nyquist
    frequency, a window not wholly airborne, and samples beyond the full scale, isolated spikes or corrupt
    DataFlash messages. blades: per rotor, for the blade-pass lines of logged rotor speeds (assumption: 2).
    """
    path = Path(path)
    band = _checked_band(band_hz)
    policies = {
        k: _policy(k, v)
        for k, v in (("on_aliasing", on_aliasing), ("on_ground", on_ground), ("on_bad_samples", on_bad_samples))
    }
    r_m = np.asarray(imu_to_mount_m, dtype=float)
    if r_m.shape != (3,) or not np.all(np.isfinite(r_m)):
        raise ValueError(f"imu_to_mount_m: need 3 finite numbers (m), got {imu_to_mount_m}")
    fmt, record = read_record(path)
    units = checks.check_units(path, record)
    keep_g, keep_a, stats, stats_a, (start, end) = _window(path, record, window_s, band)
    t_g, t_a = record.time_s[keep_g], record.acc_time_s[keep_a]
    rates = {"acc_rate_hz": 1.0 / stats_a["median_s"], "gyro_rate_hz": 1.0 / stats["median_s"]}
    used = min(rates.values())
    stream = (
        record.acc_stream if record.acc_stream == record.gyro_stream else f"{record.acc_stream}/{record.gyro_stream}"
    )
    lines, folded = aliasing.check(record, (start, end), used, stream, int(blades))
    found = {
        "aliasing": _apply(
            path,
            policies["on_aliasing"],
            folded,
            "read a higher-rate stream (PX4's high-rate "
            "logging profile, ArduPilot's batch sampler), or set on_aliasing: record",
        ),
    }
    spans = airborne.intervals(record)
    ground = airborne.ground_problem(spans, (start, end))
    found["on_ground"] = _apply(
        path,
        policies["on_ground"],
        [ground] if ground else [],
        "choose window_s inside an airborne interval, or set on_ground: record",
    )
    bad = checks.bad_samples(record, keep_a, keep_g)
    corrupt = [
        f"corrupt DataFlash data: {n} bytes skipped at byte {o} (a broken message header; its message is lost)"
        for o, n in record.corrupt
    ]
    problems = corrupt + [f["text"] for f in bad[:5]] + ([f"and {len(bad) - 5} more"] if len(bad) > 5 else [])
    found["bad_samples"] = _apply(
        path, policies["on_bad_samples"], problems, "set on_bad_samples: record to use the log as it is"
    )
    dt, up = min(stats["median_s"], stats_a["median_s"]), int(upsample)
    grid = inertial.uniform_grid(start, end, dt)  # log_span's
    fine = grid[0] + np.arange((grid.size - 1) * up + 1) * (dt / up)
    acc, rate = _at_mount(record, keep_a, keep_g, np.concatenate([grid, fine]), r_m)
    coarse = slice(0, grid.size)
    attrs = (
        _attributes(path, fmt, record, keep_g, grid, stats, band, r_m)
        | rates
        | units
        | {
            "upsample": up,
            "time_step_s": dt / up,
            "stream_nyquist_hz": 0.5 * used,
            "vehicle_lines": aliasing.describe(lines),
            "airborne_evidence": airborne.summary(record),
            "airborne_intervals": "unknown"
            if spans is None
            else (", ".join(f"{s:.3f}-{e:.3f} s" for s, e in spans) or "none"),
            "airborne_s_in_window": float("nan") if spans is None else airborne.seconds_in(spans, (start, end)),
            "bad_sample_count": len(bad),
            "dataflash_corrupt_regions": len(record.corrupt),
            "dataflash_skipped_bytes": int(sum(n for _, n in record.corrupt)),
            "vibe_m_s2": spectra.vibe(t_a, record.acceleration[:, keep_a]),
            "vibe": "ArduPilot's VIBE of the IMU's specific force per axis (FRD) in the window, m s-2 (NaN: too short)",
            **{f"problems_{k}": v for k, v in found.items()},
            **{f"policy_{k}": v for k, v in policies.items()},
            **_gap_attrs(t_a, t_g),
        }
    )
    return _dataset(
        fine - fine[0],
        acc[:, grid.size :],
        rate[:, grid.size :],
        inertial.band_integrate(acc[:, coarse], dt, band, 2, upsample=up),
        inertial.band_integrate(rate[:, coarse], dt, band, 1, upsample=up),
        attrs,
    )


def _window(path: Path, record: ImuRecord, window_s, band: tuple[float, float]):
    """(gyro mask, accelerometer mask, gyro sampling stats, accelerometer sampling stats, (start, end) s): the
    samples inside window_s (s of the log's clock; None: all), their sampling checked against band (Hz), and the
    span both streams cover."""
    keep_g = checks.in_window(path, record.time_s, window_s)
    keep_a = checks.in_window(path, record.acc_time_s, window_s)
    stats = checks.check_sampling(path, record.time_s[keep_g], band)
    stats_a = checks.check_sampling(path, record.acc_time_s[keep_a], band)
    t_g, t_a = record.time_s[keep_g], record.acc_time_s[keep_a]
    start, end = float(t_g[0]), float(t_g[-1])
    if record.acc_stream != record.gyro_stream:  # two streams: the span both cover
        start, end = max(start, float(t_a[0])), min(end, float(t_a[-1]))
    return keep_g, keep_a, stats, stats_a, (start, end)


def log_span(path, *, band_hz, window_s=None, upsample: int = 1) -> tuple[float, float, float]:
    """(first, last, step) s: the first and last sample time (of the log's clock; attribute log_window_s) and the
    output step (attribute time_step_s) of the grid `read_flight_log` puts the log on for these arguments, read
    without integrating anything: what a config check needs to place a case's window before any job.
    FlightLogError as `read_flight_log` raises it."""
    path = Path(path)
    band = _checked_band(band_hz)
    _, record = read_record(path)
    _, _, stats, stats_a, (start, end) = _window(path, record, window_s, band)
    dt = min(stats["median_s"], stats_a["median_s"])
    grid = inertial.uniform_grid(start, end, dt)
    return float(grid[0]), float(grid[-1]), dt / int(upsample)


def _gap_attrs(t_acc: np.ndarray, t_gyro: np.ndarray) -> dict:
    out = {}
    for name, t in (("acc", t_acc), ("gyro", t_gyro)):
        for key, value in checks.gaps(t).items():
            out[f"{name}_gap_{key}"] = value
    return out


def _at_mount(record: ImuRecord, keep_a, keep_g, times: np.ndarray, r_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Acceleration at the mount and body rates, FLU (3, n), at `times` (s, log clock) from the splines."""
    acc_imu = inertial.resample(record.acc_time_s[keep_a], inertial.frd_to_flu(record.acceleration[:, keep_a]), times)
    rate, rate_dot = inertial.resample(
        record.time_s[keep_g], inertial.frd_to_flu(record.angular_rate[:, keep_g]), times, derivative=True
    )
    return inertial.lever_arm(acc_imu, rate, rate_dot, r_m), rate


def _attributes(path: Path, fmt: str, record: ImuRecord, keep, grid, stats, band, r_m) -> dict:
    """The dataset's provenance and processing attributes (netCDF-compatible values)."""
    attrs = {
        "log_file": path.name,
        "log_sha256": hashlib.sha256(path.read_bytes()).hexdigest(),
        "log_format": FORMAT_NAMES[fmt],
        "log_messages": record.messages,
        "acc_stream": record.acc_stream,
        "gyro_stream": record.gyro_stream,
        "full_scale_m_s2_rad_s": np.array([record.acc_range_m_s2, record.gyro_range_rad_s]),
        "full_scale_source": record.range_source,
        "log_time_span_s": np.array([record.time_s[0], record.time_s[-1]]),
        "log_window_s": np.array([grid[0], grid[-1]]),
        "sample_rate_hz": 1.0 / stats["median_s"],
        "interval_jitter_std": stats["jitter_std"],
        "interval_jitter_max": stats["jitter_max"],
        "interval_jitter": "std of (sample interval - median) / median in the window, and max of its absolute value",
        "band_hz": np.array(band),
        "edge_s": inertial.edge_s(band),
        "taper_s": inertial.taper_s(band),
        "imu_to_mount_m": r_m,
        "frame": inertial.FRAME,
        "sign": inertial.SIGN,
        "resampling": "cubic spline (not-a-knot) through the logged samples, evaluated on the uniform grid",
        "angular_acceleration": "time derivative of the angular rates' cubic spline (for the lever arm)",
        "integration": "mean removed, Tukey taper of taper_s per end, one FFT, divided by (i 2 pi f)^n in "
        "band_hz and zeroed outside; untrusted within edge_s of either end",
    }
    if record.clipped is not None:
        attrs["accelerometer_clipped_samples"] = int(np.count_nonzero(record.clipped[keep]))
    return attrs


def _dataset(time, acc, rate, displacement, rotation, attrs) -> xr.Dataset:
    def var(values, units, long_name):
        return (("axis", "time"), values, {"units": units, "long_name": long_name})

    return xr.Dataset(
        {
            "mount_displacement": var(
                displacement, "m", "mount displacement in band_hz (acceleration integrated twice)"
            ),
            "mount_rotation": var(
                rotation, "rad", "mount small-angle rotation vector in band_hz (body rates integrated)"
            ),
            "acceleration": var(acc, "m s-2", "specific force at the mount, gravity included, before the band-pass"),
            "angular_rate": var(rate, "rad s-1", "body angular rate (the same at every point), before the band-pass"),
        },
        coords={
            "axis": ("axis", list(AXES), {"units": "1", "long_name": "body axis (x forward, y left, z up)"}),
            "time": ("time", time, {"units": "s", "long_name": "time from the window start"}),
        },
        attrs=attrs,
    )
