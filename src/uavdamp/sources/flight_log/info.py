"""What a log holds, in words: format, streams and rates, duration, airborne intervals, gaps, the vehicle's
lines and the strongest in-band accelerometer lines, so that a user can choose `window_s` and `band_hz`."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from uavdamp.sources.flight_log import airborne, aliasing, checks, spectra
from uavdamp.sources.flight_log.formats import FORMAT_NAMES
from uavdamp.sources.flight_log.motion import read_record
from uavdamp.sources.flight_log.records import AXES


def _rate(t: np.ndarray) -> float:
    return 1.0 / float(np.median(np.diff(t)))


def describe(path, band_hz=None, window_s=None, blades: int = 2) -> str:
    """The report `python -m uavdamp.sources.flight_log PATH` prints (module docstring); band_hz limits the PSD
    peaks (default 1 Hz to the Nyquist frequency), window_s the span examined (default all of it)."""
    path = Path(path)
    fmt, record = read_record(path)
    keep_a = checks.in_window(path, record.acc_time_s, window_s)
    keep_g = checks.in_window(path, record.time_s, window_s)
    t_a, t_g = record.acc_time_s[keep_a], record.time_s[keep_g]
    rate = min(_rate(t_a), _rate(t_g))
    span = (max(t_a[0], t_g[0]), min(t_a[-1], t_g[-1]))
    lines, folded = aliasing.check(record, span, rate, record.acc_stream, blades)
    spans = airborne.intervals(record)
    out = [
        f"{path.name}: {FORMAT_NAMES[fmt]}",
        f"accelerometer: {record.acc_stream}, {t_a.size} samples at {_rate(t_a):.1f} Hz "
        f"(Nyquist {0.5 * _rate(t_a):.1f} Hz)",
        f"gyroscope:     {record.gyro_stream}, {t_g.size} samples at {_rate(t_g):.1f} Hz",
        "other streams: " + (", ".join(f"{s.name} {_rate(s.time_s):.1f} Hz" for s in record.streams) or "none"),
        f"span: {span[0]:.3f}-{span[1]:.3f} s (log time), {span[1] - span[0]:.2f} s",
        "airborne: "
        + (
            "unknown (no land detector, altitude or throttle)"
            if spans is None
            else f"{airborne.seconds_in(spans, span):.2f} s: "
            + (", ".join(f"{s:.2f}-{e:.2f} s" for s, e in spans) or "none")
        ),
        f"  evidence: {airborne.summary(record)}",
    ]
    for name, t in (("accelerometer", t_a), ("gyroscope", t_g)):
        g = checks.gaps(t)
        out.append(
            f"gaps ({name}): {g['count']} intervals over 1.5 x the median, {g['dropped_samples']} samples "
            f"missing; longest {1e3 * g['longest_s']:.2f} ms at {g['longest_at_s']:.3f} s "
            f"(band_hz top below {0.5 / g['longest_s']:.1f} Hz)"
        )
    out.append(f"vehicle lines (the log's own): {aliasing.describe(lines)}")
    out += [f"  ALIASED: {text}" for text in folded]
    vibe = spectra.vibe(t_a, record.acceleration[:, keep_a])
    out.append(
        "VIBE (ArduPilot's filters), m/s2: " + ", ".join(f"{a} {v:.2f}" for a, v in zip(AXES, vibe, strict=True))
    )
    peaks = spectra.psd_peaks(t_a, record.acceleration[:, keep_a], band_hz)
    for axis, found in zip(AXES, peaks, strict=True):
        out.append(
            f"accelerometer {axis} PSD peaks: "
            + (", ".join(f"{f:.1f} Hz ({p:.3g} (m/s2)2/Hz)" for f, p in found) or "none")
        )
    out.append(
        f"bad samples (beyond full scale, isolated spikes): {len(checks.bad_samples(record, keep_a, keep_g))}"
        + (f"; corrupt DataFlash regions: {len(record.corrupt)}" if record.corrupt else "")
    )
    return "\n".join(out)
