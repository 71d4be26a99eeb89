"""Shared figure conventions: number labels, log axes clipped to what is physical, labels that do not collide.

Limits every figure keeps (tests/test_figures_readable.py checks them): at most MAX_WIDTH_PX x MAX_HEIGHT_PX at
the saved dpi (`uavdamp.io.save_figure`: 120), at most MAX_LEGEND_ENTRIES entries in any legend, legends outside
the data (beside the axes or in the figure's margin), units on every axis.

Time series (the study's camera figures, the fuselage vibration) show the first TIME_WINDOW_S seconds of their run,
from t = 0 (the runs start from rest, and the paper's figures read the start-up), or the whole run where it is
shorter; their time axis says which (`time_window_label`).
"""

from __future__ import annotations

import numpy as np
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

DPI = 120
MAX_WIDTH_PX = 2000
MAX_HEIGHT_PX = 1400
MAX_LEGEND_ENTRIES = 8
# spectra on a log axis are shown down to this fraction of their peak; below it lies numerical noise
SPECTRUM_DYNAMIC_RANGE = 1e-6
# s, the window every time-series figure shows: the first TIME_WINDOW_S s of its run
TIME_WINDOW_S = 2.0


def number(value: float) -> str:
    """A number as written by hand: 1000, 0.25, 3e+07 only beyond a million ("K = 1000 N/m", not 1e+03)."""
    value = float(value)
    if value != 0 and not 1e-3 <= abs(value) < 1e6:
        return f"{value:.3g}"
    return np.format_float_positional(value, precision=4, unique=True, fractional=False, trim="-")


def stiffness_label(k: float) -> str:
    """'K = 1000 N/m'."""
    return f"K = {number(k)} N/m"


def time_window_label(time, window_s: float = TIME_WINDOW_S) -> str:
    """The time axis label of a figure showing `time` (s, the whole run) up to `window_s`: which part it shows."""
    time = np.asarray(time, dtype=float)
    run = float(time[-1] - time[0]) if time.size else 0.0
    if window_s >= run:
        return f"time (s), the whole {number(run)} s run"
    return f"time (s), first {number(window_s)} s of the {number(run)} s run"


def plain_log_ticks(ax, axis: str = "y") -> None:
    """Tick labels of a log axis as plain numbers (0.1, 2, 40), not 4 x 10^0."""
    which = ax.yaxis if axis == "y" else ax.xaxis
    formatter = FuncFormatter(lambda v, _: number(float(f"{v:.2g}")))
    which.set_major_formatter(formatter)
    lo, hi = ax.get_ylim() if axis == "y" else ax.get_xlim()
    if lo > 0 and hi / lo < 100:  # few decades: label 2 and 5 between the powers of ten as well
        which.set_minor_locator(LogLocator(subs=(2.0, 5.0)))
        which.set_minor_formatter(formatter)
    else:
        which.set_minor_formatter(NullFormatter())


def clip_log_range(ax, values, dynamic_range: float = SPECTRUM_DYNAMIC_RANGE, axis: str = "y") -> None:
    """Limit a log axis to [dynamic_range x peak, 2 x peak] of the finite positive `values`."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v) & (v > 0)]
    if not v.size:
        return
    peak = float(v.max())
    limits = (peak * dynamic_range, 2.0 * peak)
    ax.set_ylim(*limits) if axis == "y" else ax.set_xlim(*limits)


def move_from_start(values: np.ndarray) -> np.ndarray:
    """Displacement relative to its value at t = 0 (last axis time).

    The study's inputs start at an offset (a high-passed record is not zero at t = 0) and the platform starts at
    rest at that offset, so the camera's value at t = 0 is the input's offset, not a response. A constant offset
    moves the whole platform rigidly, so value - value(t = 0) is the response to the input started from zero."""
    values = np.asarray(values, dtype=float)
    return values - values[..., :1]


def early_peak(time: np.ndarray, values: np.ndarray, early_s: float) -> tuple[float, float]:
    """(largest |value - value(t = 0)| for t <= early_s, its time), from the time series (not the start offset)."""
    time = np.asarray(time, dtype=float)
    move = np.abs(move_from_start(values))
    early = time <= early_s + 1e-9
    i = int(np.argmax(np.where(early, move, -np.inf)))
    return float(move[i]), float(time[i])


def spread_labels(positions, min_gap: float, lower: float | None = None, upper: float | None = None) -> np.ndarray:
    """Label positions moved apart by at least `min_gap` (same units), keeping their order and each as close to
    its own position as the gaps allow (a 1-D repulsion: sort, push up, then pull the whole run down)."""
    positions = np.asarray(positions, dtype=float)
    order = np.argsort(positions, kind="stable")
    placed = positions[order].copy()
    if lower is not None:
        placed[0] = max(placed[0], lower)
    for i in range(1, placed.size):
        placed[i] = max(placed[i], placed[i - 1] + min_gap)
    if upper is not None and placed.size and placed[-1] > upper:
        placed[-1] = upper
        for i in range(placed.size - 2, -1, -1):
            placed[i] = min(placed[i], placed[i + 1] - min_gap)
    # centre each run of touching labels on its own positions (pushing up alone drifts long runs upwards)
    start = 0
    for i in range(1, placed.size + 1):
        if i == placed.size or placed[i] - placed[i - 1] > min_gap + 1e-12:
            shift = np.mean(positions[order][start:i] - placed[start:i])
            low = placed[start - 1] + min_gap - placed[start] if start else -np.inf
            high = placed[i] - min_gap - placed[i - 1] if i < placed.size else np.inf
            if lower is not None:
                low = max(low, lower - placed[start])
            if upper is not None:
                high = min(high, upper - placed[i - 1])
            placed[start:i] += float(np.clip(shift, low, high)) if low <= high else 0.0
            start = i
    out = np.empty_like(placed)
    out[order] = placed
    return out
