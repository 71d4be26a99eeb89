"""What a record must satisfy before it becomes motion: samples and timestamps, the window and its sampling,
the units (gravity, the attitude's kinematics), the sensor's range, isolated spikes, gaps.

Units: the mean specific-force magnitude over the record must lie within GRAVITY_BOUNDS of g (a CSV in g reads
about 1 m s-2; choice of bounds: a vehicle's mean specific force is its weight's over any stretch it does not
climb or fall at g for). The gyro's scale against the accelerometer's tilt: a world-fixed direction (the
specific force low-passed at TILT_HZ, the vehicle at rest or slow) turns in the body axes as du/dt = -w x u,
so the least-squares scale s between du/dt and -w x u is 1 for rad s-1 and 1/57.3 for deg s-1; refused when
the direction turns at TILT_MIN_RATE or more (rms), the fit explains at least TILT_MIN_R2 of du/dt and s lies
outside TILT_SCALE_BOUNDS (in flight a multirotor's
accelerometer sees its thrust, not its tilt: the fit then explains little and the check abstains). Where the
log holds the autopilot's attitude (PX4 `vehicle_attitude`), the gyro's scale against the body rates of that
attitude, low-passed alike, must also lie in TILT_SCALE_BOUNDS when the fit explains TILT_MIN_R2 (in flight too).
Bad samples: beyond the sensor's full scale, or isolated spikes: a sample that differs from the median of
the five around it by more than SPIKE_K robust standard deviations (1.4826 x the median of those differences
magnitudes over the SPIKE_WINDOW samples around it) and more than SPIKE_FLOOR of the full scale, and by more
than 1 / ISOLATION times the spread (max - min) of its four neighbours (a sine's peak, or vibration near the
Nyquist frequency that makes every sample an extremum, stands within it; choices).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from uavdamp.signals import inertial
from uavdamp.sources.flight_log.records import AXES, G0, FlightLogError, ImuRecord

GRAVITY_BOUNDS = (0.5, 2.0)  # x g, the mean specific-force magnitude (choice)
TILT_HZ, TILT_MIN_R2, TILT_SCALE_BOUNDS, TILT_MIN_RATE = 2.0, 0.5, (0.2, 5.0), 0.01  # Hz, 1, 1, rad/s (choices)
SPIKE_K, SPIKE_FLOOR, SPIKE_WINDOW = 30.0, 0.01, 51  # robust sigmas; of the full scale; samples (choices)
ISOLATION = 0.5  # a spike stands out by more than 1 / ISOLATION times its four neighbours' spread (choice)
GAP_FACTOR = 1.5  # an interval longer than this many medians counts as a gap (dropped samples)


def check_record(path: Path, record: ImuRecord) -> None:
    """Enough finite samples with strictly increasing timestamps, else FlightLogError."""
    for t_name, v_name in (("time_s", "angular_rate"), ("acc_time_s", "acceleration")):
        t, v = getattr(record, t_name), getattr(record, v_name)
        if t.size < 4:
            raise FlightLogError(path, f"too few samples: {t.size} (need at least 4; {v_name})")
        if v.shape != (3, t.size):
            raise FlightLogError(path, f"{v_name} has shape {v.shape}, its times {t.size} samples")
    for name in ("time_s", "acc_time_s", "acceleration", "angular_rate"):
        if not np.all(np.isfinite(getattr(record, name))):
            raise FlightLogError(path, f"non-finite values in {name} ({record.messages})")
    for name in ("time_s", "acc_time_s"):
        t = getattr(record, name)
        bad = np.flatnonzero(np.diff(t) <= 0)
        if bad.size:
            i = int(bad[0])
            raise FlightLogError(
                path,
                f"timestamps do not increase: sample {i + 1} at {t[i + 1]:.6f} s follows "
                f"{t[i]:.6f} s ({bad.size} such steps; {name})",
            )


def in_window(path: Path, time_s: np.ndarray, window_s) -> np.ndarray:
    """Indices of the samples inside window_s = (start, end), log time s (None: the whole log)."""
    first, last = float(time_s[0]), float(time_s[-1])
    if window_s is None:
        return np.arange(time_s.size)
    start, end = (float(v) for v in window_s)
    if not (first <= start < end <= last):
        raise FlightLogError(
            path, f"window_s {start:g}-{end:g} s lies outside the log's {first:.6f}-{last:.6f} s (log time) or is empty"
        )
    return np.flatnonzero((time_s >= start) & (time_s <= end))


def check_sampling(path: Path, time_s: np.ndarray, band_hz: tuple[float, float]) -> dict[str, float]:
    """interval_stats of the window's samples, after refusing a slow rate, a gap or a short window."""
    low, high = band_hz
    if time_s.size < 4:
        raise FlightLogError(path, f"too few samples in the window: {time_s.size}")
    stats = inertial.interval_stats(time_s)
    rate = 1.0 / stats["median_s"]
    if rate < 2.0 * high:
        raise FlightLogError(path, f"median sample rate {rate:.4g} Hz is below twice the band's top {high:g} Hz")
    steps = np.diff(time_s)
    i = int(np.argmax(steps))
    if steps[i] > 0.5 / high:
        raise FlightLogError(
            path,
            f"gap of {1e3 * steps[i]:.4g} ms between the samples at {time_s[i]:.6f} and "
            f"{time_s[i + 1]:.6f} s (log time) is longer than half the period of the band's top "
            f"frequency {high:g} Hz ({500.0 / high:.4g} ms); choose window_s to avoid it",
        )
    span = time_s[-1] - time_s[0]
    if span < inertial.min_duration_s(band_hz):
        raise FlightLogError(
            path,
            f"too few samples: {time_s.size} over {span:.4g} s; the band's low edge "
            f"{low:g} Hz needs at least {inertial.min_duration_s(band_hz):.4g} s",
        )
    return stats


def gaps(time_s: np.ndarray) -> dict:
    """Intervals longer than GAP_FACTOR medians: their count, the samples they miss (interval / median - 1,
    rounded), the longest (s) and the time it starts (s)."""
    steps = np.diff(time_s)
    median = float(np.median(steps))
    long = steps > GAP_FACTOR * median
    i = int(np.argmax(steps))
    return {
        "count": int(np.count_nonzero(long)),
        "dropped_samples": int(np.sum(np.round(steps[long] / median) - 1)),
        "longest_s": float(steps[i]),
        "longest_at_s": float(time_s[i]),
    }


def check_units(path: Path, record: ImuRecord) -> dict[str, float]:
    """Refuse a record whose units cannot be SI (module docstring); the measured values."""
    magnitude = float(np.mean(np.linalg.norm(record.acceleration, axis=0)))
    low, high = GRAVITY_BOUNDS
    if not low * G0 <= magnitude <= high * G0:
        hint = " (accelerations in g? multiply by 9.80665)" if 0.5 <= magnitude <= 2.0 else ""
        raise FlightLogError(
            path,
            f"mean specific-force magnitude {magnitude:.4g} m/s2 is not within {low:g}-{high:g} g "
            f"({low * G0:.3g}-{high * G0:.3g} m/s2): the accelerometer is not in m/s2{hint} ({record.acc_stream})",
        )
    scale, r2 = tilt_scale(record)
    s_low, s_high = TILT_SCALE_BOUNDS
    if r2 >= TILT_MIN_R2 and not s_low <= scale <= s_high:
        hint = " (angular rates in deg/s? multiply by pi/180)" if 0.005 <= scale <= 0.05 else ""
        raise FlightLogError(
            path,
            f"the gyro turns the accelerometer's tilt {1 / scale:.3g} times as fast as the accelerometer shows "
            f"(scale {scale:.3g}, fit R2 {r2:.2f}; rad/s gives 1): the gyro is not in rad/s{hint} "
            f"({record.gyro_stream})",
        )
    att_scale, att_r2 = attitude_scale(record)
    if att_r2 >= TILT_MIN_R2 and not s_low <= att_scale <= s_high:
        hint = " (angular rates in deg/s? multiply by pi/180)" if 0.005 <= att_scale <= 0.05 else ""
        raise FlightLogError(
            path,
            f"the gyro reads {1 / att_scale:.3g} times the body rates of the logged attitude "
            f"({record.attitude_rates.name}; scale {att_scale:.3g}, fit R2 {att_r2:.2f}; rad/s gives 1): the gyro "
            f"is not in rad/s{hint} ({record.gyro_stream})",
        )
    return {
        "mean_specific_force_m_s2": magnitude,
        "gyro_tilt_scale": scale,
        "gyro_tilt_fit_r2": r2,
        "gyro_attitude_scale": att_scale,
        "gyro_attitude_fit_r2": att_r2,
    }


def attitude_scale(record: ImuRecord) -> tuple[float, float]:
    """(s, R2): the least-squares s in w_attitude = s w_gyro, both low-passed at TILT_HZ (at most a fifth of
    the attitude's rate) on the attitude's times; (nan, 0) without an attitude or when it barely turns."""
    from scipy.signal import butter, sosfiltfilt

    att = record.attitude_rates
    if att is None:
        return float("nan"), 0.0
    keep = (att.time_s >= record.time_s[0]) & (att.time_s <= record.time_s[-1])
    t = att.time_s[keep]
    if t.size < 32:
        return float("nan"), 0.0
    fs = 1.0 / float(np.median(np.diff(t)))
    sos = butter(2, min(TILT_HZ, 0.2 * fs), fs=fs, output="sos")
    w_att = sosfiltfilt(sos, att.values[:, keep], axis=1)
    w_gyro = sosfiltfilt(sos, np.array([np.interp(t, record.time_s, w) for w in record.angular_rate]), axis=1)
    gg = float(np.sum(w_gyro * w_gyro))
    if gg == 0.0 or np.sqrt(np.mean(w_att * w_att)) < TILT_MIN_RATE:
        return float("nan"), 0.0
    s = float(np.sum(w_att * w_gyro)) / gg
    return s, 1.0 - float(np.sum((w_att - s * w_gyro) ** 2)) / float(np.sum(w_att * w_att))


def tilt_scale(record: ImuRecord) -> tuple[float, float]:
    """(s, R2): the least-squares s in du/dt = -s w x u, u the specific force's direction low-passed at
    TILT_HZ, on the gyro's times where both streams run (module docstring); (nan, 0) if too short."""
    from scipy.signal import butter, sosfiltfilt

    t = record.time_s
    keep = (t >= record.acc_time_s[0]) & (t <= record.acc_time_s[-1])
    t = t[keep]
    rate = 1.0 / float(np.median(np.diff(t))) if t.size > 2 else 0.0
    if t.size < 64 or rate < 4 * TILT_HZ:
        return float("nan"), 0.0
    sos = butter(2, TILT_HZ, fs=rate, output="sos")
    acc = np.array([np.interp(t, record.acc_time_s, a) for a in record.acceleration])
    u = sosfiltfilt(sos, acc, axis=1)
    u /= np.linalg.norm(u, axis=0)
    w = sosfiltfilt(sos, record.angular_rate[:, keep], axis=1)
    du = np.gradient(u, t, axis=1)
    p = -np.cross(w, u, axis=0)
    pp = float(np.sum(p * p))
    if pp == 0.0 or np.sqrt(np.mean(du * du)) < TILT_MIN_RATE:  # the direction barely turns: no verdict
        return float("nan"), 0.0
    s = float(np.sum(du * p)) / pp
    return s, 1.0 - float(np.sum((du - s * p) ** 2)) / float(np.sum(du * du))


def bad_samples(record: ImuRecord, keep_acc: np.ndarray, keep_gyro: np.ndarray) -> list[dict]:
    """Samples of the window beyond the full scale or isolated spikes (module docstring), first first."""
    from scipy.ndimage import median_filter

    found = []
    streams = (
        ("acceleration", record.acc_time_s, record.acceleration, keep_acc, record.acc_range_m_s2, "m/s2"),
        ("angular_rate", record.time_s, record.angular_rate, keep_gyro, record.gyro_range_rad_s, "rad/s"),
    )
    for name, t, values, keep, full, unit in streams:
        for k, axis in enumerate(AXES):
            x = values[k]
            residual = x - median_filter(x, size=5, mode="nearest")
            mad = median_filter(np.abs(residual), size=SPIKE_WINDOW, mode="nearest")
            limit = np.maximum(SPIKE_K * 1.4826 * mad, SPIKE_FLOOR * full)
            for i in keep[np.abs(x[keep]) > full]:
                found.append(
                    _finding("beyond the full scale", name, axis, i, t, x, f"|{x[i]:.6g}| > {full:.4g} {unit}")
                )
            size = np.abs(residual)
            near = np.array([np.roll(x, s) for s in (-2, -1, 1, 2)])
            lone = size > (near.max(axis=0) - near.min(axis=0)) / ISOLATION  # far outside its neighbours' spread
            lone[:2] = lone[-2:] = False  # the ends have no two neighbours on each side
            for i in keep[(size[keep] > limit[keep]) & lone[keep] & (np.abs(x[keep]) <= full)]:
                found.append(
                    _finding(
                        "isolated spike",
                        name,
                        axis,
                        i,
                        t,
                        x,
                        f"{residual[i]:+.4g} {unit} from the median of the 5 around it, limit {limit[i]:.3g} {unit}",
                    )
                )
    return sorted(found, key=lambda f: f["time_s"])


def _finding(kind, name, axis, i, t, x, detail) -> dict:
    return {
        "kind": kind,
        "stream": name,
        "axis": axis,
        "index": int(i),
        "time_s": float(t[i]),
        "value": float(x[i]),
        "text": f"{kind}: {name} {axis} sample {int(i)} at {t[i]:.6f} s = {x[i]:.6g} ({detail})",
    }
