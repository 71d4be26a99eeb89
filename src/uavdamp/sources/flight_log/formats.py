"""Telling the formats apart by content, the ULog framing check, and the plain CSV reader."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from uavdamp.sources.flight_log.records import FlightLogError, ImuRecord

ULOG_MAGIC = b"ULog\x01\x12\x35"
DATAFLASH_HEAD = b"\xa3\x95"
CSV_COLUMNS = ("time_s", "acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2", "gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s")
FORMAT_NAMES = {"ulog": "PX4 ULog", "dataflash": "ArduPilot DataFlash", "csv": "uavdamp CSV"}
EXTENSIONS = {".ulg": "ulog", ".bin": "dataflash", ".csv": "csv"}


def detect_format(path: Path) -> str:
    """The format, "ulog", "dataflash" or "csv", from the file's first bytes; FlightLogError if none fits or
    if a known extension (.ulg, .bin, .csv) disagrees."""
    path = Path(path)
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


def read_csv(path: Path) -> ImuRecord:
    """'#' comment lines, then the header naming CSV_COLUMNS (any order, others ignored), one sample per line:
    time in s, vectors in FRD body axes (x forward, y right, z down), m s-2 and rad s-1."""
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
        acc_stream="CSV",
        gyro_stream="CSV",
    )
