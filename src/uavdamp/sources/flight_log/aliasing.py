"""The vehicle's lines as the log shows them, against the Nyquist frequency of the stream read.

A line above half the stream's rate folds back into the band as an alias, so the reader refuses the stream
(or, when asked, records it). The lines, over the window: the strongest peak per axis of PX4's own gyro FFT
(`sensor_gyro_fft`, which runs on the raw gyro at kHz rates; the median over its estimates); rotor rates
(ESC rpm) times the blade count; and the strongest Welch PSD peak per axis, above MIN_LINE_HZ, of any
higher-rate inertial stream of the same log above the read stream's Nyquist frequency, where it stands
PROMINENCE times above that stream's median PSD above MIN_LINE_HZ (choices).
"""

from __future__ import annotations

import numpy as np

from uavdamp.sources.flight_log.records import AXES, ImuRecord

MIN_LINE_HZ, PROMINENCE, FASTER = 5.0, 10.0, 1.2  # Hz; PSD ratio; a stream this much faster counts (choices)


def _in(time_s, window) -> np.ndarray:
    return (time_s >= window[0]) & (time_s <= window[1])


def logged_lines(record: ImuRecord, window: tuple[float, float], blades: int) -> list[dict]:
    """The fft and rotor lines in the window (all of the log's if none falls in it), one per source and axis:
    {source, axis, freq_hz (median), low_hz, high_hz (10 and 90 %), count}."""
    out = []
    for source in sorted({line.source for line in record.lines}):
        mine = [line for line in record.lines if line.source == source]
        inside = [line for line in mine if window[0] <= line.time_s <= window[1]] or mine
        for axis in sorted({line.axis for line in inside}):
            f = np.array([(blades if line.per_rev else 1) * line.freq_hz for line in inside if line.axis == axis])
            out.append(
                {
                    "source": source + (f" x {blades} blades" if inside[0].per_rev else ""),
                    "axis": axis,
                    "freq_hz": float(np.median(f)),
                    "low_hz": float(np.percentile(f, 10)),
                    "high_hz": float(np.percentile(f, 90)),
                    "count": int(f.size),
                }
            )
    return out


def stream_lines(record: ImuRecord, window: tuple[float, float], rate_hz: float) -> list[dict]:
    """Per axis of each stream FASTER times the rate read: its strongest PSD line above the Nyquist frequency of
    the rate read, if PROMINENCE times its median PSD above MIN_LINE_HZ."""
    from scipy.signal import welch

    out = []
    for stream in record.streams:
        keep = _in(stream.time_s, window)
        t = stream.time_s[keep]
        if t.size < 64:
            continue
        fs = 1.0 / float(np.median(np.diff(t)))
        if fs < FASTER * rate_hz:
            continue
        for k, axis in enumerate(AXES):
            f, p = welch(stream.values[k, keep], fs=fs, nperseg=min(t.size, int(fs)))
            floor = float(np.median(p[f >= MIN_LINE_HZ]))
            above = f > 0.5 * rate_hz
            if not np.any(above) or floor <= 0:
                continue
            i = int(np.argmax(np.where(above, p, 0.0)))
            ratio = float(p[i] / floor)
            if ratio >= PROMINENCE:
                out.append(
                    {
                        "source": f"{stream.name} at {fs:.1f} Hz",
                        "axis": axis,
                        "freq_hz": float(f[i]),
                        "low_hz": float(f[i]),
                        "high_hz": float(f[i]),
                        "count": 1,
                        "prominence": ratio,
                    }
                )
    return out


def aliased(lines: list[dict], rate_hz: float, stream: str) -> list[str]:
    """A sentence per line above the Nyquist frequency rate_hz / 2 of `stream`."""
    nyquist = 0.5 * rate_hz
    return [
        f"{line['source']} {line['axis']} line at {line['freq_hz']:.1f} Hz (10-90 % {line['low_hz']:.1f}-"
        f"{line['high_hz']:.1f} Hz over {line['count']} estimates) lies above the Nyquist frequency "
        f"{nyquist:.1f} Hz of {stream} sampled at {rate_hz:.1f} Hz"
        for line in lines
        if line["freq_hz"] > nyquist
    ]


def describe(lines: list[dict]) -> str:
    """One line of text per source and axis (for the attributes and the info command)."""
    return (
        "; ".join(
            f"{line['source']} {line['axis']}: {line['freq_hz']:.1f} Hz "
            f"(10-90 % {line['low_hz']:.1f}-{line['high_hz']:.1f})"
            for line in lines
        )
        or "none in the log"
    )


def check(record: ImuRecord, window, rate_hz: float, stream: str, blades: int) -> tuple[list[dict], list[str]]:
    """(the lines, the sentences of those above the Nyquist frequency)."""
    lines = logged_lines(record, window, blades) + stream_lines(record, window, rate_hz)
    return lines, aliased(lines, rate_hz, stream)
