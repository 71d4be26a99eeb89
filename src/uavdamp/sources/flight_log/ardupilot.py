"""ArduPilot DataFlash (.bin, read with pymavlink's DFReader): the batch sampler or IMU, corruption counted.

Every message is read in order, and the bytes pymavlink skips to find the next header (a broken header, a
flipped byte in one) are counted per region (`ImuRecord.corrupt`), not only printed. The IMU samples: the batch
sampler's ISBH / ISBD messages of instance 0 (header: type 0 accelerometer, 1 gyroscope, `mul`, `smp_cnt`,
`SampleUS` the first sample's time, `smp_rate` Hz; data: 32 int16 samples per axis per message, value =
raw / mul, the k-th sample of block `seqno` at SampleUS + (32 seqno + k) / smp_rate) when both sensors' batches
are there and run together without gaps (`continuous`), else `IMU` messages of instance I = 0 (`TimeUS` us,
`GyrX/Y/Z` rad s-1, `AccX/Y/Z` m s-2). Airborne
evidence: CTUN (`ThO` throttle out > 0.05 and `Alt` > 0.3 m above its first value; choice). Rotor lines: ESC
`RPM` / 60.
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import numpy as np

from uavdamp.sources.flight_log.records import Evidence, FlightLogError, ImuRecord, Line

CTUN_THROTTLE, CTUN_CLIMB_M = 0.05, 0.3  # choice: airborne above this throttle out and this height


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
        acc_stream="IMU",
        gyro_stream="IMU",
    )


def batches(headers, blocks) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """{sensor type: (times s, values (3, n))} of instance 0 from ISBH headers and ISBD blocks."""
    out = defaultdict(lambda: ([], []))
    for h in headers:
        if getattr(h, "instance", 0) != 0:
            continue
        data = sorted((b for b in blocks.get(h.N, [])), key=lambda b: b.seqno)
        if not data:
            continue
        values = np.hstack([np.array([b.x, b.y, b.z], dtype=float) for b in data]) / float(h.mul)
        index = np.concatenate([32 * b.seqno + np.arange(len(b.x)) for b in data])
        keep = index < h.smp_cnt
        times, vals = out[int(h.type)]
        times.append(1e-6 * h.SampleUS + index[keep] / float(h.smp_rate))
        vals.append(values[:, keep])
    return {k: (np.concatenate(t), np.hstack(v)) for k, (t, v) in out.items()}


def continuous(acc_s: np.ndarray, gyro_s: np.ndarray) -> bool:
    """True if both batch streams run without a gap (no interval over 1.5 median) over a common span: the
    batch sampler can also take the sensors in turns, and then the IMU messages are used."""
    a, g = np.sort(acc_s), np.sort(gyro_s)
    if a.size < 3 or g.size < 3:
        return False
    no_gap = all(np.max(np.diff(t)) < 1.5 * np.median(np.diff(t)) for t in (a, g))
    return no_gap and min(a[-1], g[-1]) - max(a[0], g[0]) > 0.5 * max(a[-1] - a[0], g[-1] - g[0])


def _scan(path: Path) -> tuple[dict[str, list], list[tuple[int, int]], int]:
    """The messages by type, the (offset, bytes) of each stretch pymavlink skipped, the end of the last message."""
    from pymavlink.DFReader import DFReader_binary

    wanted = {"IMU", "ISBH", "ISBD", "CTUN", "ESC"}
    found, corrupt = defaultdict(list), []
    try:
        log = DFReader_binary(str(path))
        log.rewind()
        end = log.offset
        while (msg := log.recv_msg()) is not None:
            start = log.offset - msg.fmt.len
            if start > end:
                corrupt.append((end, start - end))
            end = log.offset
            if msg.get_type() in wanted:
                found[msg.get_type()].append(msg)
    except Exception as exc:  # pymavlink raises several types on malformed input
        raise FlightLogError(path, f"pymavlink cannot parse it ({exc})") from exc
    tail = bytes(log.data_map[end:])
    if tail.strip(b"\x00").strip(b"\xff"):
        raise FlightLogError(path, f"truncated: {len(tail)} bytes after the last complete message at byte {end}")
    return found, corrupt, end


def _evidence(ctun) -> list[Evidence]:
    if not ctun or not all(hasattr(ctun[0], k) for k in ("ThO", "Alt")):
        return []
    t = 1e-6 * np.array([m.TimeUS for m in ctun], float)
    throttle, alt = (np.array([getattr(m, k) for m in ctun], float) for k in ("ThO", "Alt"))
    flying = (throttle > CTUN_THROTTLE) & (alt - alt[0] > CTUN_CLIMB_M)
    notes = f"CTUN Alt {alt.min():.2f} to {alt.max():.2f} m; ThO zero in {100 * np.mean(throttle <= 0):.0f} %"
    return [Evidence(f"CTUN (ThO > {CTUN_THROTTLE}, Alt > {CTUN_CLIMB_M} m above its first value)", t, flying, notes)]


def read_dataflash(path: Path) -> ImuRecord:
    """The highest-rate IMU samples of an ArduPilot DataFlash log (module docstring)."""
    found, corrupt, _ = _scan(path)
    blocks = defaultdict(list)
    for b in found["ISBD"]:
        blocks[b.N].append(b)
    sampled = batches(found["ISBH"], blocks)
    lines = [
        Line("ESC", f"ESC{getattr(m, 'Instance', 0)}", m.RPM / 60.0, 1e-6 * m.TimeUS, per_rev=True)
        for m in found["ESC"]
        if getattr(m, "RPM", 0) > 0
    ]
    extra = {"lines": tuple(lines), "evidence": tuple(_evidence(found["CTUN"])), "corrupt": tuple(corrupt)}
    if 0 in sampled and 1 in sampled and continuous(sampled[0][0], sampled[1][0]):
        (ta, va), (tg, vg) = sampled[0], sampled[1]
        oa, og = np.argsort(ta, kind="stable"), np.argsort(tg, kind="stable")
        return ImuRecord(
            time_s=tg[og],
            acc_time_s=ta[oa],
            acceleration=va[:, oa],
            angular_rate=vg[:, og],
            messages="ISBH/ISBD batch sampler (instance 0): x, y, z / mul at SampleUS + k / smp_rate",
            acc_stream="ISBD (type 0)",
            gyro_stream="ISBD (type 1)",
            **extra,
        )
    record = imu_from_messages(found["IMU"], path)
    return ImuRecord(**{**record.__dict__, **extra})
