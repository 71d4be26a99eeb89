"""Small ULog files written by hand for the flight-log tests (ULog: 16-byte header, then messages of uint16
size, uint8 type, payload: 'B' flag bits, 'F' formats, 'A' subscriptions, 'D' data), read back with pyulog."""

from __future__ import annotations

import struct

import numpy as np

TYPES = {"uint64_t": "Q", "float": "f", "int16_t": "h", "uint8_t": "B", "uint32_t": "I", "int32_t": "i", "bool": "?"}


def _message(kind: str, payload: bytes) -> bytes:
    return struct.pack("<HB", len(payload), ord(kind)) + payload


def write_ulog(path, topics: dict[str, tuple[list[tuple[str, str]], dict[str, np.ndarray]]]) -> None:
    """topics: name -> ([(type, field)], {field: values per message}); a field "x[32]" of type int16_t takes
    values of shape (n, 32). Messages of all topics are written in timestamp order."""
    out = b"ULog\x01\x12\x35" + bytes([1]) + struct.pack("<Q", 0)
    out += _message("B", bytes(16) + bytes(24))
    rows = []
    for name, (fields, _) in topics.items():  # the definitions first, then the subscriptions and the data
        out += _message("F", (name + ":" + "".join(f"{t} {f};" for t, f in fields)).encode())
    for msg_id, name in enumerate(topics):
        out += _message("A", struct.pack("<BH", 0, msg_id) + name.encode())
    for msg_id, (fields, values) in enumerate(topics.values()):
        n = len(values["timestamp"])
        for i in range(n):
            payload = b""
            for t, f in fields:
                base, _, size = t.partition("[")
                value = values[f][i]
                if size:
                    count = int(size[:-1])
                    payload += struct.pack(f"<{count}{TYPES[base]}", *np.asarray(value).tolist())
                else:
                    payload += struct.pack(f"<{TYPES[base]}", value.item() if hasattr(value, "item") else value)
            rows.append((int(values["timestamp"][i]), msg_id, payload))
    for _, msg_id, payload in sorted(rows, key=lambda r: (r[0], r[1])):
        out += _message("D", struct.pack("<H", msg_id) + payload)
    with open(path, "wb") as f:
        f.write(out)


def combined(t_s: np.ndarray, acc_frd: np.ndarray, gyro_frd: np.ndarray):
    """A sensor_combined topic (gyro and accelerometer at the same times)."""
    fields = [("uint64_t", "timestamp"), ("float[3]", "gyro_rad"), ("float[3]", "accelerometer_m_s2")]
    return fields, {
        "timestamp": np.round(1e6 * t_s).astype(np.int64),
        "gyro_rad": gyro_frd.T,
        "accelerometer_m_s2": acc_frd.T,
    }


def fifo(t_s: np.ndarray, values_frd: np.ndarray, scale: float, per_message: int = 10):
    """A sensor_accel_fifo / sensor_gyro_fifo topic: `per_message` samples a message, the newest at
    timestamp_sample, int16 counts of `scale`."""
    n = t_s.size // per_message
    dt_us = 1e6 * float(np.median(np.diff(t_s)))
    counts = np.round(values_frd[:, : n * per_message] / scale).astype(int).reshape(3, n, per_message)
    pad = np.zeros((3, n, 32 - per_message), dtype=int)
    counts = np.concatenate([counts, pad], axis=2)
    stamp = np.round(1e6 * t_s[per_message - 1 : n * per_message : per_message]).astype(np.int64)
    fields = [
        ("uint64_t", "timestamp"),
        ("uint64_t", "timestamp_sample"),
        ("uint32_t", "device_id"),
        ("float", "dt"),
        ("float", "scale"),
        ("uint8_t", "samples"),
        ("int16_t[32]", "x"),
        ("int16_t[32]", "y"),
        ("int16_t[32]", "z"),
    ]
    values = {
        "timestamp": stamp,
        "timestamp_sample": stamp,
        "device_id": np.ones(n, int),
        "dt": np.full(n, dt_us),
        "scale": np.full(n, scale),
        "samples": np.full(n, per_message),
        "x": counts[0],
        "y": counts[1],
        "z": counts[2],
    }
    return fields, values


def gyro_fft(t_s: np.ndarray, peak_hz: float):
    """A sensor_gyro_fft topic whose strongest peak on x and y is peak_hz."""
    fields = [
        ("uint64_t", "timestamp"),
        ("float", "sensor_sample_rate_hz"),
        ("float[4]", "peak_frequencies_x"),
        ("float[4]", "peak_frequencies_y"),
        ("float[4]", "peak_frequencies_z"),
    ]
    n = t_s.size
    peaks = np.tile([peak_hz, 0.0, 0.0, 0.0], (n, 1))
    return fields, {
        "timestamp": np.round(1e6 * t_s).astype(np.int64),
        "sensor_sample_rate_hz": np.full(n, 1000.0),
        "peak_frequencies_x": peaks,
        "peak_frequencies_y": peaks,
        "peak_frequencies_z": 0 * peaks,
    }
