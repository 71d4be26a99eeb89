"""Real flight logs -> the camera mount's motion: PX4 ULog, ArduPilot DataFlash and a plain CSV.

`read_flight_log` reads one inertial measurement unit (IMU), turns its axes into uavdamp's (x forward,
y left, z up; the logs' FRD y and z negated), resamples it onto a uniform grid at the log's median rate
(cubic spline), moves the acceleration from the IMU to the mount by rigid-body kinematics, and integrates
acceleration and body rates in a band (`uavdamp.inertial.band_integrate`) to the mount's displacement and
small-angle rotation. Formats, told apart by content (the file's extension, if .ulg, .bin or .csv, must agree):

- PX4 ULog: topic `sensor_combined` instance 0 (`gyro_rad[0..2]` rad s-1, `accelerometer_m_s2[0..2]`
  m s-2, `timestamp` us, accelerometer sample time = timestamp + `accelerometer_timestamp_relative`). The
  high-rate `sensor_accel_fifo` / `sensor_gyro_fifo` topics are not read (the shipped logs have none).
- ArduPilot DataFlash (.bin): `IMU` messages of instance I = 0 (`TimeUS` us, `GyrX/Y/Z` rad s-1,
  `AccX/Y/Z` m s-2), read with pymavlink's DataFlash reader (what `mavutil.mavlink_connection` opens a
  .bin with).
- CSV: '#' comment lines, then the header `time_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,gyro_x_rad_s,gyro_y_rad_s,
  gyro_z_rad_s` (any column order; others ignored), one sample per line; time in s, vectors in the
  autopilots' FRD body axes (x forward, y right, z down), as PX4 and ArduPilot log them.

Refused with `FlightLogError` (a ValueError naming the file): an unknown or mislabelled format, a
truncated file, a missing topic/message/column, non-finite values, timestamps that do not increase, a
window outside the log, a median sample rate below 2 f_high, any sample interval in the window longer
than 1 / (2 f_high) (half the period of the band's top frequency: across such a gap a sine at f_high is
not sampled twice per period), and a window shorter than `inertial.min_duration_s(band_hz)` = 8 / f_low.
"""

from __future__ import annotations

import hashlib
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from uavdamp import inertial
from uavdamp.settings import require, setting

ULOG_MAGIC = b"ULog\x01\x12\x35"
DATAFLASH_HEAD = b"\xa3\x95"
CSV_COLUMNS = ("time_s", "acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2", "gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s")
FORMAT_NAMES = {"ulog": "PX4 ULog", "dataflash": "ArduPilot DataFlash", "csv": "uavdamp CSV"}
EXTENSIONS = {".ulg": "ulog", ".bin": "dataflash", ".csv": "csv"}
AXES = ("x", "y", "z")
RELATIVE_TIMESTAMP_INVALID = 2**31 - 1  # PX4 sensor_combined: no accelerometer sample with this gyro sample


@dataclass(frozen=True)
class FlightLogSource:
    """One measured flight of the config (``flight_logs.NAME``): what `read_flight_log` is called with."""

    path: str = setting()  # the log file, relative to the working directory (the repository's root)
    band_hz: tuple[float, ...] = setting(length=2)  # Hz, the integration band
    window_s: tuple[float, ...] | None = setting(default=None, length=2)  # s of the log's clock; None: all of it
    imu_to_mount_m: tuple[float, ...] = setting(default=(0.0, 0.0, 0.0), length=3)  # m, mount minus IMU, body axes
    upsample: int = setting(default=1)  # the output every log interval / upsample (read_flight_log)
    description: str = setting(default="")

    def validate(self, where: str) -> None:
        low, high = self.band_hz
        require(0 < low < high, f"{where}.band_hz", f"needs 0 < low < high, got {list(self.band_hz)}")
        require(self.upsample >= 1, f"{where}.upsample", f"must be >= 1, got {self.upsample}")
        if self.window_s is not None:
            ok = 0 <= self.window_s[0] < self.window_s[1]
            require(ok, f"{where}.window_s", f"needs 0 <= start < end, got {list(self.window_s)}")


class FlightLogError(ValueError):
    """A flight log that cannot be used; the message names the file and what is wrong."""

    def __init__(self, path, problem: str):
        super().__init__(f"{path}: {problem}")


@dataclass(frozen=True)
class ImuRecord:
    """One IMU's samples as logged: times (s, log clock), FRD vectors (3, n), and where they came from."""

    time_s: np.ndarray  # angular-rate sample times
    acc_time_s: np.ndarray  # acceleration sample times (equal to time_s unless the log says otherwise)
    acceleration: np.ndarray  # m s-2, specific force, FRD
    angular_rate: np.ndarray  # rad s-1, FRD
    messages: str
    clipped: np.ndarray | None = None  # True where the log flags accelerometer clipping


def detect_format(path: Path) -> str:
    """The format, "ulog", "dataflash" or "csv", from the file's first bytes; FlightLogError if none fits or
    if a known extension (.ulg, .bin, .csv) disagrees."""
    with open(path, "rb") as f:
        head = f.read(4096)
    if head.startswith(ULOG_MAGIC):
        found = "ulog"
    elif head.startswith(DATAFLASH_HEAD):
        found = "dataflash"
    elif _csv_header(head) is not None:
        found = "csv"
    else:
        raise FlightLogError(
            path,
            f"not a PX4 ULog (magic {ULOG_MAGIC!r}), ArduPilot DataFlash (0xA3 0x95) or CSV "
            f"with the header {','.join(CSV_COLUMNS)}; first bytes {head[:16]!r}",
        )
    expected = EXTENSIONS.get(path.suffix.lower())
    if expected is not None and expected != found:
        raise FlightLogError(
            path, f"named {path.suffix} ({FORMAT_NAMES[expected]}) but its content is {FORMAT_NAMES[found]}"
        )
    return found


def _csv_header(head: bytes) -> list[str] | None:
    """The column names of the first non-comment line if the bytes are text and it names time_s, else None."""
    try:
        lines = head.decode("utf-8").splitlines()
    except UnicodeDecodeError:
        return None
    for line in lines:
        if line.strip() and not line.lstrip().startswith("#"):
            names = [name.strip() for name in line.split(",")]
            return names if "time_s" in names else None
    return None


def ulog_truncation(path: Path) -> str | None:
    """None if the ULog's message stream (after the 16-byte header: uint16 size, uint8 type, payload) ends
    exactly at the end of the file, else what is cut. (A file cut on a message boundary passes: ULog has no
    end marker.)"""
    data = Path(path).read_bytes()
    if len(data) < 16:
        return f"truncated: {len(data)} bytes, shorter than the 16-byte ULog header"
    offset = start = 16
    while offset + 3 <= len(data):
        start = offset
        offset += 3 + struct.unpack_from("<H", data, offset)[0]
    if offset != len(data):
        return f"truncated: the message at byte {start} needs {offset - len(data)} more bytes than the file has"
    return None


def read_ulog(path: Path) -> ImuRecord:
    """sensor_combined instance 0 of a PX4 ULog (module docstring)."""
    from pyulog import ULog

    cut = ulog_truncation(path)
    if cut is not None:
        raise FlightLogError(path, cut)
    try:
        ulog = ULog(str(path), ["sensor_combined"])
    except Exception as exc:  # pyulog raises several types on malformed input
        raise FlightLogError(path, f"pyulog cannot parse it ({exc})") from exc
    if ulog.file_corruption:
        raise FlightLogError(path, "pyulog reports file corruption")
    found = [d for d in ulog.data_list if d.name == "sensor_combined" and d.multi_id == 0]
    if not found:
        raise FlightLogError(path, "no sensor_combined topic (instance 0) in the log")
    data = found[0].data
    columns = [f"gyro_rad[{k}]" for k in range(3)] + [f"accelerometer_m_s2[{k}]" for k in range(3)]
    missing = [c for c in ["timestamp", *columns] if c not in data]
    if missing:
        raise FlightLogError(path, f"sensor_combined lacks the fields {missing}")
    time_us = data["timestamp"].astype(np.int64)
    rel_us = data.get("accelerometer_timestamp_relative", np.zeros_like(time_us)).astype(np.int64)
    if np.any(rel_us == RELATIVE_TIMESTAMP_INVALID):
        raise FlightLogError(path, "sensor_combined marks accelerometer samples invalid (relative timestamp INT32_MAX)")
    clipping = data.get("accelerometer_clipping")
    return ImuRecord(
        time_s=1e-6 * time_us,
        acc_time_s=1e-6 * (time_us + rel_us),
        acceleration=np.array([data[c] for c in columns[3:]], dtype=float),
        angular_rate=np.array([data[c] for c in columns[:3]], dtype=float),
        messages="sensor_combined (instance 0): timestamp, accelerometer_timestamp_relative, gyro_rad[0..2], "
        "accelerometer_m_s2[0..2]",
        clipped=None if clipping is None else clipping != 0,
    )


def imu_from_messages(messages, path) -> ImuRecord:
    """ImuRecord from DataFlash IMU message objects (attributes TimeUS, GyrX/Y/Z, AccX/Y/Z and, on logs
    with several IMUs in one message type, I); keeps instance 0 (messages without I count as instance 0)."""
    rows = [(m.TimeUS, m.GyrX, m.GyrY, m.GyrZ, m.AccX, m.AccY, m.AccZ) for m in messages if getattr(m, "I", 0) == 0]
    if not rows:
        raise FlightLogError(path, "no IMU messages of instance 0 in the log")
    table = np.array(rows, dtype=float).T
    return ImuRecord(
        time_s=1e-6 * table[0],
        acc_time_s=1e-6 * table[0],
        acceleration=table[4:7],
        angular_rate=table[1:4],
        messages="IMU (instance I = 0): TimeUS, GyrX, GyrY, GyrZ, AccX, AccY, AccZ",
    )


def read_dataflash(path: Path) -> ImuRecord:
    """IMU instance 0 of an ArduPilot DataFlash log (module docstring)."""
    from pymavlink.DFReader import DFReader_binary

    try:
        log = DFReader_binary(str(path))
        messages = []
        while (msg := log.recv_match(type="IMU")) is not None:
            messages.append(msg)
    except Exception as exc:  # pymavlink raises several types on malformed input
        raise FlightLogError(path, f"pymavlink cannot parse it ({exc})") from exc
    tail = bytes(log.data_map[log.offset :])
    if tail.strip(b"\x00").strip(b"\xff"):
        raise FlightLogError(path, f"truncated: {len(tail)} bytes after the last complete message at byte {log.offset}")
    return imu_from_messages(messages, path)


def read_csv(path: Path) -> ImuRecord:
    """The CSV of the module docstring (FRD axes)."""
    lines = Path(path).read_text(encoding="utf-8").splitlines()
    start = next(i for i, line in enumerate(lines) if line.strip() and not line.lstrip().startswith("#"))
    names = [name.strip() for name in lines[start].split(",")]
    missing = [c for c in CSV_COLUMNS if c not in names]
    if missing:
        raise FlightLogError(path, f"CSV lacks the columns {missing} (header: {names})")
    try:
        table = np.loadtxt(
            lines[start + 1 :], delimiter=",", comments="#", ndmin=2, usecols=[names.index(c) for c in CSV_COLUMNS]
        )
    except ValueError as exc:
        raise FlightLogError(path, f"CSV values are not all numbers ({exc})") from exc
    table = table.T
    return ImuRecord(
        time_s=table[0].copy(),
        acc_time_s=table[0].copy(),
        acceleration=table[1:4],
        angular_rate=table[4:7],
        messages="CSV columns: " + ",".join(CSV_COLUMNS),
    )


READERS = {"ulog": read_ulog, "dataflash": read_dataflash, "csv": read_csv}


def _check_record(path: Path, record: ImuRecord) -> None:
    """Enough finite samples with strictly increasing timestamps, else FlightLogError."""
    if record.time_s.size < 4:
        raise FlightLogError(path, f"too few samples: {record.time_s.size} (need at least 4)")
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


def _in_window(path: Path, time_s: np.ndarray, window_s) -> np.ndarray:
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


def _check_sampling(path: Path, time_s: np.ndarray, band_hz: tuple[float, float]) -> dict[str, float]:
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


def _checked_band(band_hz) -> tuple[float, float]:
    low, high = (float(v) for v in band_hz)
    if not 0 < low < high:
        raise ValueError(f"band_hz: need 0 < low < high, got {band_hz}")
    return low, high


def read_flight_log(path, *, band_hz, window_s=None, imu_to_mount_m=(0.0, 0.0, 0.0), upsample: int = 1) -> xr.Dataset:
    """Mount motion from a flight log's IMU (module docstring): `mount_displacement` (axis, time), m, and
    `mount_rotation` (axis, time), rad (small-angle rotation vector: integrated body rates), in band_hz =
    (f_low, f_high), Hz, plus the resampled `acceleration` (specific force, gravity included; m s-2) and
    `angular_rate` (rad s-1) at the mount before the band-pass. Axes x forward, y left, z up.

    window_s: (start, end), s of the log's own clock (PX4: since boot; as the CSV's time_s), default the
    whole log; the grid starts at the first sample inside it (time 0) with the median interval.
    imu_to_mount_m: mount minus IMU position, m, uavdamp body axes; a_mount = a_imu + dw/dt x r + w x (w x r),
    dw/dt the derivative of the rates' interpolating cubic spline (`inertial.resample`). Integrated values
    within `edge_s` (attribute) of either end are not to be trusted (`inertial.band_integrate`).
    upsample: the output every median interval / upsample s (the displacement and rotation by exact band-limited
    interpolation, `inertial.band_integrate`; acceleration and rate by the cubic spline), so that a solver's
    linear interpolation of the motion onto its finer grid does not filter it (at a quarter of the log's rate,
    linear interpolation of samples at the log's rate keeps only sinc^2(1/4) = 81 % of a line).
    """
    path = Path(path)
    band = _checked_band(band_hz)
    r_m = np.asarray(imu_to_mount_m, dtype=float)
    if r_m.shape != (3,) or not np.all(np.isfinite(r_m)):
        raise ValueError(f"imu_to_mount_m: need 3 finite numbers (m), got {imu_to_mount_m}")
    fmt = detect_format(path)
    record = READERS[fmt](path)
    _check_record(path, record)
    keep = _in_window(path, record.time_s, window_s)
    stats = _check_sampling(path, record.time_s[keep], band)
    _check_sampling(path, record.acc_time_s[keep], band)
    dt, up = stats["median_s"], int(upsample)
    grid = inertial.uniform_grid(record.time_s[keep][0], record.time_s[keep][-1], dt)
    fine = grid[0] + np.arange((grid.size - 1) * up + 1) * (dt / up)
    acc, rate = _at_mount(record, keep, np.concatenate([grid, fine]), r_m)
    coarse = slice(0, grid.size)
    attrs = _attributes(path, fmt, record, keep, grid, stats, band, r_m) | {"upsample": up, "time_step_s": dt / up}
    return _dataset(
        fine - fine[0],
        acc[:, grid.size :],
        rate[:, grid.size :],
        inertial.band_integrate(acc[:, coarse], dt, band, 2, upsample=up),
        inertial.band_integrate(rate[:, coarse], dt, band, 1, upsample=up),
        attrs,
    )


def _at_mount(record: ImuRecord, keep, times: np.ndarray, r_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Acceleration at the mount and body rates, FLU (3, n), at `times` (s, log clock) from the splines."""
    acc_imu = inertial.resample(record.acc_time_s[keep], inertial.frd_to_flu(record.acceleration[:, keep]), times)
    rate, rate_dot = inertial.resample(
        record.time_s[keep], inertial.frd_to_flu(record.angular_rate[:, keep]), times, derivative=True
    )
    return inertial.lever_arm(acc_imu, rate, rate_dot, r_m), rate


def _attributes(path: Path, fmt: str, record: ImuRecord, keep, grid, stats, band, r_m) -> dict:
    """The dataset's provenance and processing attributes (netCDF-compatible values)."""
    attrs = {
        "log_file": path.name,
        "log_sha256": hashlib.sha256(path.read_bytes()).hexdigest(),
        "log_format": FORMAT_NAMES[fmt],
        "log_messages": record.messages,
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
