"""Airborne seconds: the intervals the log's own evidence calls airborne, and the window against them.

PX4: the land detector (`vehicle_land_detected`) airborne where none of landed, maybe_landed and
ground_contact is set (each message holds until the next); ArduPilot: CTUN's throttle out and altitude
(`uavdamp.sources.flight_log.ardupilot`); a CSV has no such evidence (airborne: unknown, nothing refused). Where
several sources exist, airborne is where all of them say so.
"""

from __future__ import annotations

import numpy as np

from uavdamp.sources.flight_log.records import ImuRecord, step_intervals


def intervals(record: ImuRecord) -> list[tuple[float, float]] | None:
    """The airborne intervals (s, log clock), or None when the log holds no evidence."""
    if not record.evidence:
        return None
    end = float(max(record.time_s[-1], record.acc_time_s[-1]))
    found = None
    for ev in record.evidence:
        mine = step_intervals(ev.time_s, ev.airborne, end)
        found = mine if found is None else _intersect(found, mine)
    return found


def _intersect(a, b) -> list[tuple[float, float]]:
    out = []
    for s1, e1 in a:
        for s2, e2 in b:
            start, end = max(s1, s2), min(e1, e2)
            if end > start:
                out.append((start, end))
    return out


def seconds_in(spans, window: tuple[float, float]) -> float:
    """Airborne seconds of `spans` inside the window."""
    return float(sum(max(0.0, min(e, window[1]) - max(s, window[0])) for s, e in spans))


def ground_problem(spans, window: tuple[float, float]) -> str | None:
    """None if the window lies in the air, else what part of it does not (with the airborne intervals)."""
    if spans is None:
        return None
    air = seconds_in(spans, window)
    span = window[1] - window[0]
    if air >= span - 1e-9:
        return None
    listed = ", ".join(f"{s:.2f}-{e:.2f} s" for s, e in spans) or "none"
    return (
        f"the window {window[0]:.3f}-{window[1]:.3f} s is airborne for {air:.2f} of its {span:.2f} s "
        f"(on the ground for {span - air:.2f} s); the log's airborne intervals: {listed}"
    )


def summary(record: ImuRecord) -> str:
    """The evidence in words (source and notes) for the attributes."""
    if not record.evidence:
        return "no airborne evidence in the log (land detector, altitude, throttle): unknown"
    return "; ".join(f"{ev.source}" + (f" ({ev.notes})" if ev.notes else "") for ev in record.evidence)


def as_array(spans) -> np.ndarray:
    """The intervals as an (n, 2) array for a netCDF attribute (flattened by the caller)."""
    return np.array(spans if spans else np.zeros((0, 2)), dtype=float).reshape(-1, 2)
