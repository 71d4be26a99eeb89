"""The paper's loop on the payload: the six-axis isolator's damping scheduled from the tracked input through the
payload table (`uavdamp.study.payload_table`).

Every ``update_period_s`` (the paper's 0.5 s), from the last ``window_s`` of the mount's motion up to then
(causal), each DOF's dominant line in the table's frequency range is found (`uavdamp.signals.spectrum.
dominant_frequency_causal`: Hann peak refined by a sine fit, the segment's straight line removed) and its
amplitude fitted (least squares of a sine at that frequency beside a straight line). The law then takes the C of
the table's damping grid that minimises the predicted criterion, sum over the DOFs of (criterion(DOF, f, K, C) x
a / A)^2, the table's criterion interpolated linearly in log frequency at the config's element stiffness K, a the
line's amplitude and A the table's input amplitude (the loop is linear: the lines add in power, as sines of
different frequencies do). Before the first estimate (a whole ``window_s`` of record) the damper holds
``initial_damping_n_s_m`` (choice). All elements take the same C, held until the next update (the run exact for
the held C: `uavdamp.platform.six_axis_run.run`). The law chooses among the table's dampings at which the isolator
settles (its slowest 1/e decay time, the table's ``decay_time``) within ``max_decay_time_s``: the steady state the
table assumes is reached within an update period at them, and a lightly damped rocking mode is not left ringing
(a 7 Hz line on the mount's x and pitch: at 1 N s/m, decay time 2.1 s, the line of sight over 16-20 s is the table's
steady state within 3 %; at 0.1 N s/m, 22 s, more than twice it: tests/test_payload_schedule.py).

What it leaves out, as the paper's does: the lines besides each DOF's dominant one, the cross terms of lines that
share a frequency across DOFs, and the isolator's start-up transient (the table is steady state).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import xarray as xr

from uavdamp.contract import MountMotion
from uavdamp.platform.six_axis import DOFS, SixAxisIsolator
from uavdamp.platform.six_axis_run import run
from uavdamp.settings import require, setting
from uavdamp.signals.spectrum import causal_segment, dominant_frequency_causal


@dataclass(frozen=True)
class ScheduleSection:
    """The scheduled law's timing (``payload.schedule``)."""

    update_period: float = setting("update_period_s", default=0.5)  # s, the paper's "new C values every 0.5 s"
    window: float = setting("window_s", default=1.0)  # s, of mount motion each estimate reads (the study's)
    initial_damping: float = setting("initial_damping_n_s_m", default=10.0)  # N s m-1, before the first estimate
    # s, a C is eligible when the isolator's slowest decay time at it is at most this (the steady state the table
    # assumes is then reached within it; choice: the update period)
    max_decay_time: float = setting("max_decay_time_s", default=0.5)

    def validate(self, where: str) -> None:
        require(self.update_period > 0, f"{where}.update_period_s", f"must be > 0, got {self.update_period}")
        require(self.window > 0, f"{where}.window_s", f"must be > 0, got {self.window}")
        ok = self.initial_damping >= 0
        require(ok, f"{where}.initial_damping_n_s_m", f"must be >= 0, got {self.initial_damping}")
        require(self.max_decay_time > 0, f"{where}.max_decay_time_s", f"must be > 0, got {self.max_decay_time}")


class Table(NamedTuple):
    """The payload table at one element stiffness, its dampings those eligible: freq (nf,) Hz, damping (nc,)
    N s m-1, criterion (6, nf, nc) rad, amplitude (6,) m or rad (the table's input sine per DOF of `DOFS`)."""

    freq: np.ndarray
    damping: np.ndarray
    criterion: np.ndarray
    amplitude: np.ndarray

    @classmethod
    def of(cls, table: xr.Dataset, stiffness: float, max_decay_time: float = math.inf) -> Table:
        """`table` (``payload/table.nc``) at element z stiffness `stiffness` N m-1 (one of its values; ValueError
        naming payload.table.stiffness_n_m otherwise), keeping the dampings whose ``decay_time`` is at most
        max_decay_time s (none: ValueError naming payload.schedule.max_decay_time_s); a DOF without a line of
        sight has criterion 0."""
        ks = table.stiffness.values
        if not np.any(np.isclose(ks, stiffness, rtol=1e-9)):
            raise ValueError(
                f"payload.table.stiffness_n_m: must hold the six-axis isolator's z stiffness {stiffness} N m-1 "
                f"(payload.six_axis.stiffness_n_m) for the scheduled law, got {ks.tolist()}"
            )
        at_k = table.sel(stiffness=ks[np.isclose(ks, stiffness, rtol=1e-9)][0])
        eligible = at_k.decay_time.values <= max_decay_time
        if not eligible.any():
            shortest = float(at_k.decay_time.min())
            raise ValueError(
                f"payload.schedule.max_decay_time_s: {max_decay_time} s leaves no damping of the payload table "
                f"(the isolator's shortest decay time at K = {stiffness} N m-1 is {shortest:.3g} s)"
            )
        part = at_k.criterion.sel(dof=list(DOFS)).isel(damping=np.flatnonzero(eligible))
        amplitude = np.array([table.attrs["translation_amplitude_m"]] * 3 + [table.attrs["rotation_amplitude_rad"]] * 3)
        crit = part.transpose("dof", "freq", "damping").values
        return cls(table.freq.values, part.damping.values, crit, amplitude)


def predicted(table: Table, lines: np.ndarray) -> np.ndarray:
    """(nc,) the predicted criterion squared, rad^2, for the dominant lines (6, 2): (frequency Hz, amplitude m or
    rad) per DOF; a DOF whose line is NaN or outside the table's frequencies adds nothing."""
    total = np.zeros(table.damping.size)
    log_f = np.log(table.freq)
    for d, (f, a) in enumerate(lines):
        if not (np.isfinite(f) and np.isfinite(a) and table.freq[0] <= f <= table.freq[-1]):
            continue
        per_c = np.array([np.interp(math.log(f), log_f, table.criterion[d, :, c]) for c in range(table.damping.size)])
        total += (per_c * a / table.amplitude[d]) ** 2
    return total


def choose(table: Table, lines: np.ndarray, fallback: float) -> float:
    """The table's C (N s m-1) of the least `predicted` criterion; `fallback` when no DOF has a line."""
    total = predicted(table, lines)
    return float(table.damping[int(np.argmin(total))]) if np.any(total > 0) else float(fallback)


def dominant_lines(time: np.ndarray, u: np.ndarray, t_now: float, window: float, band: tuple) -> np.ndarray:
    """(6, 2) per DOF of u (6, n) the dominant line (Hz, amplitude) in `band` (Hz) of the last `window` s up to
    t_now; NaN rows before a whole window of record or without a line."""
    out = np.full((6, 2), math.nan)
    for d in range(6):
        f = dominant_frequency_causal(
            time, u[d], t_now, window, min_freq_hz=band[0], max_freq_hz=band[1], min_cycles=math.inf
        )
        if not np.isfinite(f):
            continue
        segment, dt = causal_segment(time, u[d], t_now, window)
        s = np.arange(segment.size) * dt
        basis = np.column_stack([np.sin(2 * np.pi * f * s), np.cos(2 * np.pi * f * s), np.ones_like(s), s])
        coef = np.linalg.lstsq(basis, segment, rcond=None)[0]
        out[d] = f, math.hypot(coef[0], coef[1])
    return out


class Schedule(NamedTuple):
    """The law's decisions: update times (m,) s, C (m,) N s m-1, lines (m, 6, 2), and C per sample (n,)."""

    times: np.ndarray
    damping: np.ndarray
    lines: np.ndarray
    per_sample: np.ndarray


def schedule(time: np.ndarray, mount: MountMotion, table: Table, section: ScheduleSection) -> Schedule:
    """The scheduled C over `time` (s, from 0) for `mount` (module docstring)."""
    t = np.asarray(time, dtype=float)
    u = np.vstack([mount.translation, mount.rotation])
    times = np.arange(0.0, t[-1] + 1e-9, section.update_period)
    band = (float(table.freq[0]), float(table.freq[-1]))
    lines = np.stack([dominant_lines(t, u, tk, section.window, band) for tk in times])
    return replanned(Schedule(times, None, lines, None), time, lambda found, c: choose(table, found, c), section)


def replanned(plan: Schedule, time: np.ndarray, law, section: ScheduleSection) -> Schedule:
    """`plan`'s update times and lines with the C of `law` (lines (6, 2), fallback N s m-1) -> C N s m-1 at each
    update (fallback ``initial_damping_n_s_m``), held over `time` (s) until the next: another law on the same
    tracked lines (`uavdamp.study.payload_anfis.AnfisLaw`)."""
    damping = np.array([law(found, section.initial_damping) for found in plan.lines])
    t = np.asarray(time, dtype=float)
    held = np.searchsorted(plan.times, t + 1e-9 * section.update_period, side="right") - 1
    return Schedule(plan.times, damping, plan.lines, damping[held])


def scheduled_run(isolator: SixAxisIsolator, time: np.ndarray, mount: MountMotion, per_sample: np.ndarray):
    """`uavdamp.platform.six_axis_run.run` of `isolator` with every semi-active element at `per_sample` (n,)."""
    c = np.broadcast_to(np.asarray(per_sample, dtype=float), (len(isolator.semi_active), len(time)))
    return run(isolator, time, mount.translation, mount.rotation, c)
