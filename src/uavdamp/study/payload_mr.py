"""The MR damper on the payload's six-axis isolator: a Spencer damper (``payload.mr``) along every element's x, y
and z (`uavdamp.platform.six_axis_force`), each element's three under one command voltage, in four runs beside the
ideal dampers' laws (`uavdamp.study.payload_laws`):

    mr_off        held at 0 V: the damper as a passive element (its least damping, c_off of the range)
    mr_on         held at 2.25 V (`dampers.V_MAX`)
    mr_skyhook    on-off skyhook on the voltage: 2.25 V where Karnopp's rule asks for c_on, else 0 V, decided every
                  sample from the element's own velocities (`payload_laws.skyhook_schedule`); the damper's own
                  command filter (eta = 190 s-1) is its lag
    mr_scheduled  the scheduled law's C per sample (`uavdamp.study.payload_schedule`) as the voltage whose
                  equivalent damping at the reference stroke it is, clamped to the damper's range

The damper is the published one scaled to span ``payload.mr.damping_range_n_s_m`` at the reference stroke (8 Hz,
0.05 m/s: the benchmark's, `uavdamp.damping.actuation.MRSpec`); at the payload's strokes its damping differs (a
choice: the reference stroke is not the payload's, and an MR damper's equivalent damping depends on the stroke).
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np

from uavdamp.camera.criteria import window_mask
from uavdamp.contract import MountMotion
from uavdamp.damping.actuation import MRSpec
from uavdamp.damping.dampers import V_MAX
from uavdamp.settings import ConfigError
from uavdamp.study.payload_runs import mr_law_motions, six_axis_isolator

MR_LAWS = ("mr_off", "mr_on", "mr_skyhook", "mr_scheduled")


@cache
def _spec(c_range: tuple[float, float], max_substep: float) -> MRSpec:
    try:
        return MRSpec.build(c_range, max_substep)
    except ValueError as error:  # the range beyond the published damper's reach
        raise ConfigError(f"payload.mr.damping_range_n_s_m: {error}") from None


def spec(section) -> MRSpec:
    """The MR damper of ``payload.mr`` (built once per process: about 40 loop simulations)."""
    mr = section.mr
    return _spec(tuple(float(c) for c in mr.damping_range), float(mr.max_substep))


def mr_names(scheduled: bool) -> list[str]:
    """The MR runs' names: `MR_LAWS`, mr_scheduled only with the scheduled law."""
    return list(MR_LAWS[:3]) + ["mr_scheduled"] * scheduled


def mr_motions(section, t: np.ndarray, moved: MountMotion, skyhook, per_sample) -> tuple[list, list[dict]]:
    """(the payload's `BodyMotion` under each MR run of `mr_names`, and per run its ``on_fraction`` (the share of
    element-steps at 2.25 V, skyhook; NaN else), ``c_on`` (N s m-1, skyhook's: the damper's c_eq at 2.25 V) and
    ``damping_mean`` (N s m-1: the c_eq of a held voltage, the scheduled law's mean clamped C over the settled
    window)). skyhook: the callable schedule of 0 / 2.25 V (`payload_laws.skyhook_schedule` of a `Skyhook` between
    them); per_sample: the scheduled law's C (n,) N s m-1, or None."""
    damper = spec(section)
    n_semi = len(six_axis_isolator(section, 0.0).semi_active)
    c_lo, c_hi = float(damper.damping[0]), float(damper.damping[-1])
    schedules = [np.zeros(n_semi), np.full(n_semi, V_MAX), skyhook]
    nan = math.nan
    rows = [
        {"on_fraction": nan, "c_on": nan, "damping_mean": c_lo},
        {"on_fraction": nan, "c_on": nan, "damping_mean": c_hi},
        {"on_fraction": nan, "c_on": c_hi, "damping_mean": nan},
    ]
    if per_sample is not None:
        clamped = np.clip(per_sample, c_lo, c_hi)
        schedules.append(np.broadcast_to(damper.voltages(clamped), (n_semi, t.size)))
        mean = float(np.mean(clamped[window_mask(t, section.settle_s, section.duration_s)]))
        rows.append({"on_fraction": nan, "c_on": nan, "damping_mean": mean})
    bodies, applied = mr_law_motions(section, damper.params, damper.max_substep, schedules, t, moved)
    rows[2]["on_fraction"] = float(np.mean(applied[2][:-1] > 0.5 * V_MAX))
    return bodies, rows
