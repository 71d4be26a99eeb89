"""A clairvoyant damping scheduler: piecewise-constant C per update period, chosen knowing the whole input.

It bounds what a scheduler that changes C every update period P (the paper's 0.5 s) could reach on a scenario,
but only over the schedules it explores: a beam search (width `beam_width`) over `candidates` C per period on
the linear plant (`uavdamp.platform.linear_plant.LinearPlant`, exact for its linearisation), plus every constant
schedule among the candidates. It is not a global optimum: a schedule the beam pruned, or a C between candidates, may do
better. The criterion is named (`OBJECTIVES`), one of `uavdamp.camera.criteria` that is the square root of the summed
variances (1/N, whole run) of output rows of the plant: "displacement_std" = sqrt(var y + var z) of the camera
displacement (the study's criterion) or "los_std" = sqrt(var yaw + var pitch). Partial runs are ranked by the same
expression over the samples so far (a heuristic: the variance of a prefix).

The plant is linear in a period's start state, so each candidate's period is run once from a zero state (its forced
response) and every schedule in the beam adds its own free response, C phi^k z0, all of them in one product: the
same sums as running each schedule on its own, to rounding (tests/test_clairvoyant.py checks an exhaustive beam and a
beam of one against runs of the plant).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from uavdamp.platform.linear_plant import OUTPUTS
from uavdamp.platform.statespace import free_response_rows, lift, propagate

OBJECTIVES = {"displacement_std": ("camera_y", "camera_z"), "los_std": ("yaw", "pitch")}  # name -> output rows
_BLOCK = 32


@dataclass(frozen=True)
class ClairvoyantSchedule:
    """The best schedule found: values (N s m-1, one per update period from t = 0), its cost (the criterion's
    units: m or rad), and the cost of every constant candidate (candidates, costs)."""

    values: np.ndarray
    cost: float
    candidates: np.ndarray
    constant_costs: np.ndarray
    criterion: str


@dataclass
class _Beam:
    """Partial schedules side by side: values (B, periods so far), states (B, ns) at the next period's start, and
    per schedule and output row the sums of the output so far (s1) and of its square (s2) over n samples."""

    values: np.ndarray
    states: np.ndarray
    s1: np.ndarray
    s2: np.ndarray
    n: int

    def costs(self) -> np.ndarray:
        mean = self.s1 / self.n
        return np.sqrt(np.maximum(np.sum(self.s2 / self.n - mean**2, axis=1), 0.0))


@dataclass(frozen=True)
class _Period:
    """One update period under one candidate C, from a zero start state: the states (len + 1, ns), the output rows
    (samples, rows); and from a start state z0 the outputs add free[k] @ z0 and the end state jump @ z0."""

    forced: np.ndarray
    out: np.ndarray
    free: np.ndarray
    jump: np.ndarray


def schedule(
    plant,
    time,
    mount,
    *,
    stiffness: float,
    candidates,
    update_period: float,
    beam_width: int,
    criterion: str = "displacement_std",
) -> ClairvoyantSchedule:
    """Beam search for the piecewise-constant C (per `update_period` s) minimising `criterion` on `plant`.

    Input as `LinearPlant.run` (time s, `MountMotion`); stiffness N m-1; candidates N s m-1 within the
    damper bounds. Returns the best of the beam's schedules and the constant ones (never worse than any
    constant candidate on its criterion).
    """
    if criterion not in OBJECTIVES:
        raise ValueError(f"criterion: unknown {criterion!r} (known: {sorted(OBJECTIVES)})")
    if beam_width < 1:
        raise ValueError(f"beam_width: must be >= 1, got {beam_width}")
    candidates = np.unique(np.asarray(candidates, dtype=float))
    if candidates.size < 1 or not all(plant.bounds.contains(c) for c in candidates):
        raise ValueError(f"candidates: need values within [{plant.bounds.c_min}, {plant.bounds.c_max}] N s m-1")
    h = plant.params.time_step
    per_update = int(round(update_period / h))
    if per_update < 1 or abs(per_update * h - update_period) > 1e-9 * update_period:
        raise ValueError(f"update_period ({update_period} s) must be a positive multiple of time_step ({h} s)")
    run = plant.prepare(time, mount)
    grid, u, slope, rate = run["time"], run["u"], run["slope"], run["rate"]
    rows = [OUTPUTS.index(r) for r in OBJECTIVES[criterion]]
    cont, _ = plant.step_map(stiffness, candidates[0])
    out_map = (cont.c[rows], cont.du[rows], cont.dv[rows])  # independent of C
    maps = {c: plant.step_map(stiffness, c)[1] for c in candidates}
    lifts = {c: lift(maps[c].phi, _BLOCK) for c in candidates} if per_update >= 2 * _BLOCK else {}
    steps = grid.size - 1
    starts = list(range(0, steps, per_update))
    free = {c: free_response_rows(out_map[0], maps[c].phi, per_update + 1) for c in candidates}  # rows' C phi^k
    jumps = {c: np.linalg.matrix_power(maps[c].phi, per_update) for c in candidates}  # a whole period's state map

    def period(c: float, start: int) -> _Period:
        """Candidate c over the period from grid step `start`, from a zero state (linear: any start adds free)."""
        end = min(start + per_update, steps)
        forced = propagate(maps[c], np.zeros(plant.model.n_states), u[start:end], slope[start:end], lifts.get(c))
        last = end + 1 if end == steps else end  # the final grid point belongs to the last period
        out = forced[: last - start] @ out_map[0].T + u[start:last] @ out_map[1].T + rate[start:last] @ out_map[2].T
        jump = jumps[c] if end - start == per_update else np.linalg.matrix_power(maps[c].phi, end - start)
        return _Period(forced, out, free[c][: last - start], jump)

    def extend(beam: _Beam, c: float, p: _Period) -> _Beam:
        """Every schedule of `beam` continued with C = c over period p."""
        out = np.einsum("krs,bs->bkr", p.free, beam.states) + p.out
        values = np.column_stack([beam.values, np.full(len(beam.values), c)])
        states = beam.states @ p.jump.T + p.forced[-1]
        s1, s2 = beam.s1 + out.sum(axis=1), beam.s2 + (out**2).sum(axis=1)
        return _Beam(values, states, s1, s2, beam.n + p.out.shape[0])

    z0 = plant.model.initial_state(u[0], slope[0])
    beam = _Beam(np.zeros((1, 0)), z0[None, :], np.zeros((1, len(rows))), np.zeros((1, len(rows))), 0)
    constants = [beam] * candidates.size  # every constant schedule, one per candidate
    for start in starts:
        periods = [period(c, start) for c in candidates]
        children = _concat([extend(beam, c, p) for c, p in zip(candidates, periods, strict=True)])
        order = np.lexsort((*children.values.T[::-1], children.costs()))  # by cost, then by the values in order
        beam = _take(children, order[:beam_width])
        constants = [extend(b, c, p) for b, c, p in zip(constants, candidates, periods, strict=True)]
    constant_costs = _concat(constants).costs()
    best_cost = float(beam.costs()[0])
    k = int(np.argmin(constant_costs))
    if constant_costs[k] < best_cost:
        values, cost = np.full(len(starts), candidates[k]), float(constant_costs[k])
    else:
        values, cost = beam.values[0], best_cost
    if not math.isfinite(cost):
        raise ValueError("clairvoyant: non-finite criterion")
    return ClairvoyantSchedule(values, cost, candidates, np.asarray(constant_costs), criterion)


def _concat(beams: list[_Beam]) -> _Beam:
    """The schedules of `beams` (all over the same periods) in one beam, in order."""
    fields = (np.concatenate([getattr(b, f) for b in beams]) for f in ("values", "states", "s1", "s2"))
    return _Beam(*fields, beams[0].n)


def _take(beam: _Beam, index: np.ndarray) -> _Beam:
    """The schedules `index` of `beam`."""
    return _Beam(beam.values[index], beam.states[index], beam.s1[index], beam.s2[index], beam.n)
