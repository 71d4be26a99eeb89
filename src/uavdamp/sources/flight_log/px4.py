"""PX4 ULog (read with pyulog): the highest-rate IMU stream, the gyro FFT's peaks, the land detector.

IMU streams, instance 0: of the pairs the log holds, the one at the highest rate (the slower of its two streams
counts; a tie goes to the first listed): `sensor_accel_fifo` / `sensor_gyro_fifo` (the high-rate logging
profile: per message `samples` int16 values x[k], y[k], z[k] times `scale`, `dt` us apart, the newest at
`timestamp_sample`, as PX4's drivers fill them; full scale 32768 `scale`), `sensor_accel` / `sensor_gyro`
(x, y, z at `timestamp_sample`), then `sensor_combined` (`gyro_rad[0..2]`, `accelerometer_m_s2[0..2]` at `timestamp` +
`accelerometer_timestamp_relative`). All FRD, m s-2 and rad s-1.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from uavdamp.sources.flight_log.formats import ulog_truncation
from uavdamp.sources.flight_log.records import AXES, Evidence, FlightLogError, ImuRecord, Line, Stream

RELATIVE_TIMESTAMP_INVALID = 2**31 - 1  # PX4 sensor_combined: no accelerometer sample with this gyro sample
TOPICS = [
    "sensor_accel_fifo",
    "sensor_gyro_fifo",
    "sensor_accel",
    "sensor_gyro",
    "sensor_combined",
    "sensor_gyro_fft",
    "vehicle_angular_velocity",
    "vehicle_acceleration",
    "vehicle_land_detected",
    "vehicle_attitude",
    "vehicle_local_position",
    "actuator_controls_0",
    "actuator_motors",
    "esc_status",
]


def _topic(ulog, name: str):
    found = [d for d in ulog.data_list if d.name == name and d.multi_id == 0]
    return found[0].data if found else None


def _rate(time_s: np.ndarray) -> float:
    return 1.0 / float(np.median(np.diff(time_s))) if time_s.size > 2 else 0.0


def unpack_fifo(data) -> tuple[np.ndarray, np.ndarray, float]:
    """(times s, FRD values (3, n), full scale) of a sensor_accel_fifo / sensor_gyro_fifo topic."""
    n = data["samples"].astype(int)
    size = sum(1 for key in data if key.startswith("x["))
    k = np.arange(size)
    valid = k[None, :] < n[:, None]
    # the newest sample at timestamp_sample, the others dt us before it each
    t_us = data["timestamp_sample"][:, None] - (n[:, None] - 1 - k[None, :]) * data["dt"][:, None].astype(float)
    values = np.array(
        [np.column_stack([data[f"{ax}[{j}]"] for j in range(size)]) * data["scale"][:, None] for ax in AXES]
    )
    return 1e-6 * t_us[valid], values[:, valid], 32768.0 * float(np.max(data["scale"]))


def _pairs(ulog) -> list[dict]:
    """The candidate (accelerometer, gyroscope) stream pairs the log holds."""
    out = []
    acc_f, gyro_f = _topic(ulog, "sensor_accel_fifo"), _topic(ulog, "sensor_gyro_fifo")
    if acc_f is not None and gyro_f is not None:
        ta, va, ra = unpack_fifo(acc_f)
        tg, vg, rg = unpack_fifo(gyro_f)
        out.append({"acc": ("sensor_accel_fifo", ta, va), "gyro": ("sensor_gyro_fifo", tg, vg), "range": (ra, rg)})
    acc, gyro = _topic(ulog, "sensor_accel"), _topic(ulog, "sensor_gyro")
    if acc is not None and gyro is not None:
        out.append(
            {
                "acc": ("sensor_accel", 1e-6 * acc["timestamp_sample"], np.array([acc[a] for a in AXES], float)),
                "gyro": ("sensor_gyro", 1e-6 * gyro["timestamp_sample"], np.array([gyro[a] for a in AXES], float)),
            }
        )
    return out


def _combined(path: Path, data) -> dict:
    columns = [f"gyro_rad[{k}]" for k in range(3)] + [f"accelerometer_m_s2[{k}]" for k in range(3)]
    missing = [c for c in ["timestamp", *columns] if c not in data]
    if missing:
        raise FlightLogError(path, f"sensor_combined lacks the fields {missing}")
    time_us = data["timestamp"].astype(np.int64)
    rel_us = data.get("accelerometer_timestamp_relative", np.zeros_like(time_us)).astype(np.int64)
    if np.any(rel_us == RELATIVE_TIMESTAMP_INVALID):
        raise FlightLogError(path, "sensor_combined marks accelerometer samples invalid (relative timestamp INT32_MAX)")
    clipping = data.get("accelerometer_clipping")
    return {
        "acc": ("sensor_combined", 1e-6 * (time_us + rel_us), np.array([data[c] for c in columns[3:]], float)),
        "gyro": ("sensor_combined", 1e-6 * time_us, np.array([data[c] for c in columns[:3]], float)),
        "clipped": None if clipping is None else clipping != 0,
    }


def _choose(path: Path, ulog) -> tuple[dict, list[dict]]:
    """The pair at the highest rate (the slower of its two streams counts), and the others."""
    pairs = _pairs(ulog)
    combined = _topic(ulog, "sensor_combined")
    if combined is not None:
        pairs.append(_combined(path, combined))
    pairs = [p for p in pairs if p["acc"][1].size > 2 and p["gyro"][1].size > 2]
    if not pairs:
        raise FlightLogError(
            path,
            "no IMU topic (sensor_accel_fifo/sensor_gyro_fifo, sensor_accel/sensor_gyro or sensor_combined, "
            "instance 0) with samples in the log",
        )
    rates = [min(_rate(p["acc"][1]), _rate(p["gyro"][1])) for p in pairs]
    best = int(np.argmax(rates))
    return pairs[best], [p for i, p in enumerate(pairs) if i != best]


def fft_lines(data) -> list[Line]:
    """The strongest peak per message and axis of PX4's own gyro FFT (`sensor_gyro_fft`: peak_frequencies_x[0]
    ..., NaN or 0 where none)."""
    out = []
    for ax in AXES:
        key = f"peak_frequencies_{ax}[0]"
        if key not in data:
            continue
        for t, f in zip(1e-6 * data["timestamp"], data[key], strict=True):
            if np.isfinite(f) and f > 0:
                out.append(Line("sensor_gyro_fft", ax, float(f), float(t)))
    return out


def rotor_lines(data) -> list[Line]:
    """Each ESC's rotation rate (esc_status esc[k].esc_rpm / 60, Hz) where it turns."""
    out = []
    for key in [k for k in data if k.endswith(".esc_rpm")]:
        for t, rpm in zip(1e-6 * data["timestamp"], data[key], strict=True):
            if rpm > 0:
                out.append(Line("esc_status", key.split(".")[0], float(rpm) / 60.0, float(t), per_rev=True))
    return out


def attitude_rates(ulog) -> Stream | None:
    """Body rates (FRD, rad s-1) between successive `vehicle_attitude` quaternions (q[0..3] = w, x, y, z,
    body to NED): the rotation vector of R_k^-1 R_k+1 over the interval, at its midpoint."""

    att = _topic(ulog, "vehicle_attitude")
    if att is None or "q[0]" not in att or att["timestamp"].size < 3:
        return None
    t = 1e-6 * att["timestamp"].astype(float)
    keep = np.flatnonzero(np.diff(t) > 0)
    q = np.array([att[f"q[{k}]"] for k in (1, 2, 3, 0)]).T
    rot = Rotation.from_quat(q)
    rates = (rot[keep].inv() * rot[keep + 1]).as_rotvec() / np.diff(t)[keep, None]
    return Stream("vehicle_attitude (quaternion differences)", 0.5 * (t[keep] + t[keep + 1]), rates.T)


def land_evidence(ulog) -> list[Evidence]:
    """Airborne where the land detector sets none of landed, maybe_landed, ground_contact; the altitude and
    the throttle as notes."""
    land = _topic(ulog, "vehicle_land_detected")
    if land is None:
        return []
    flags = [land[k].astype(bool) for k in ("landed", "maybe_landed", "ground_contact") if k in land]
    notes = []
    position = _topic(ulog, "vehicle_local_position")
    if position is not None and "z" in position:
        notes.append(f"local z {np.min(position['z']):.2f} to {np.max(position['z']):.2f} m (NED, down positive)")
    for name, key in (("actuator_controls_0", "control[3]"), ("actuator_motors", "control[0]")):
        throttle = _topic(ulog, name)
        if throttle is not None and key in throttle:
            notes.append(f"{name} {key} zero in {100 * np.mean(throttle[key] <= 0):.0f} % of its samples")
    return [
        Evidence(
            "vehicle_land_detected (none of landed, maybe_landed, ground_contact)",
            1e-6 * land["timestamp"],
            ~np.logical_or.reduce(flags),
            "; ".join(notes),
        )
    ]


def read_ulog(path: Path) -> ImuRecord:
    """The highest-rate IMU stream of a PX4 ULog (module docstring), with the log's lines and airborne evidence."""
    from pyulog import ULog

    cut = ulog_truncation(path)
    if cut is not None:
        raise FlightLogError(path, cut)
    try:
        ulog = ULog(str(path), TOPICS)
    except Exception as exc:  # pyulog raises several types on malformed input
        raise FlightLogError(path, f"pyulog cannot parse it ({exc})") from exc
    if ulog.file_corruption:
        raise FlightLogError(path, "pyulog reports file corruption")
    if _topic(ulog, "sensor_combined") is None and not _pairs(ulog):
        raise FlightLogError(path, "no sensor_combined topic (instance 0) in the log, nor a FIFO or sensor pair")
    pair, others = _choose(path, ulog)
    (acc_name, acc_t, acc), (gyro_name, gyro_t, gyro) = pair["acc"], pair["gyro"]
    streams = [
        Stream(p[k][0] + (" accelerometer" if k == "acc" else " gyroscope"), p[k][1], p[k][2])
        for p in others
        for k in ("acc", "gyro")
    ]
    for name in ("vehicle_angular_velocity", "vehicle_acceleration"):
        data = _topic(ulog, name)
        if data is not None and "xyz[0]" in data:
            streams.append(Stream(name, 1e-6 * data["timestamp"], np.array([data[f"xyz[{k}]"] for k in range(3)])))
    fft, esc = _topic(ulog, "sensor_gyro_fft"), _topic(ulog, "esc_status")
    lines = (fft_lines(fft) if fft is not None else []) + (rotor_lines(esc) if esc is not None else [])
    notes = {}
    if fft is not None and "sensor_sample_rate_hz" in fft:
        notes["gyro_fft_sample_rate_hz"] = sorted({round(float(r), 1) for r in fft["sensor_sample_rate_hz"]})
    full_scale = pair.get("range")
    extra = (
        {}
        if full_scale is None
        else {"acc_range_m_s2": full_scale[0], "gyro_range_rad_s": full_scale[1], "range_source": "FIFO scale x 32768"}
    )
    fields = "instance 0" + (": x[k], y[k], z[k] x scale, dt, samples, timestamp_sample" if full_scale else "")
    messages = (
        f"{acc_name} and {gyro_name} ({fields})"
        if acc_name != gyro_name
        else (
            "sensor_combined (instance 0): timestamp, accelerometer_timestamp_relative, gyro_rad[0..2], "
            "accelerometer_m_s2[0..2]"
        )
    )
    return ImuRecord(
        time_s=gyro_t,
        acc_time_s=acc_t,
        acceleration=acc,
        angular_rate=gyro,
        messages=messages,
        clipped=pair.get("clipped"),
        acc_stream=acc_name,
        gyro_stream=gyro_name,
        lines=tuple(lines),
        streams=tuple(s for s in streams if s.time_s.size > 2),
        evidence=tuple(land_evidence(ulog)),
        attitude_rates=attitude_rates(ulog),
        notes=notes,
        **extra,
    )
