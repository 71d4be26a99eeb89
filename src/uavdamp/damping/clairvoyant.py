"""A clairvoyant damping scheduler: piecewise-constant C per update period, chosen knowing the whole input.

It bounds what a scheduler that changes C every update period P (the paper's 0.5 s) could reach on a scenario,
but only over the schedules it explores: a beam search (width `beam_width`) over `candidates` C per period on
the linear plant (`uavdamp.platform.linear_plant.LinearPlant`, exact for its linearisation), plus every constant
schedule among the candidates. It is not a global optimum: a schedule the beam pruned, or a C between candidates, may do
better. The criterion is named (`OBJECTIVES`), one of `uavdamp.camera.criteria` that is the square root of the summed
variances (1/N, whole run) of output rows of the plant: "displacement_std" = sqrt(var y + var z) of the camera
displacement (the study's criterion) or "los_std" = sqrt(var yaw + var pitch). Partial runs are ranked by the same
expression over the samples so far (a heuristic: the variance of a prefix).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from uavdamp.platform.linear_plant import OUTPUTS
from uavdamp.platform.statespace import lift, propagate

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
class _Node:
    values: tuple
    state: np.ndarray
    s1: np.ndarray  # per row: sum of the output so far
    s2: np.ndarray  # per row: sum of its square
    n: int

    def cost(self) -> float:
        mean = self.s1 / self.n
        return float(np.sqrt(max(float(np.sum(self.s2 / self.n - mean**2)), 0.0)))


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

    def extend(node: _Node, c: float, start: int) -> _Node:
        end = min(start + per_update, steps)
        states = propagate(maps[c], node.state, u[start:end], slope[start:end], lifts.get(c))
        last = end + 1 if end == steps else end  # the final grid point belongs to the last period
        out = states[: last - start] @ out_map[0].T + u[start:last] @ out_map[1].T + rate[start:last] @ out_map[2].T
        return _Node(
            node.values + (c,),
            states[end - start],
            node.s1 + out.sum(axis=0),
            node.s2 + (out**2).sum(axis=0),
            node.n + out.shape[0],
        )

    root = _Node((), plant.model.initial_state(u[0], slope[0]), np.zeros(len(rows)), np.zeros(len(rows)), 0)
    beam = [root]
    for start in starts:
        children = [extend(node, c, start) for node in beam for c in candidates]
        children.sort(key=lambda n: (n.cost(), n.values))
        beam = children[:beam_width]
    constant_costs = []
    for c in candidates:
        node = root
        for start in starts:
            node = extend(node, c, start)
        constant_costs.append(node.cost())
    best = beam[0]
    k = int(np.argmin(constant_costs))
    if constant_costs[k] < best.cost():
        values, cost = np.full(len(starts), candidates[k]), float(constant_costs[k])
    else:
        values, cost = np.asarray(best.values), best.cost()
    if not math.isfinite(cost):
        raise ValueError("clairvoyant: non-finite criterion")
    return ClairvoyantSchedule(values, cost, candidates, np.asarray(constant_costs), criterion)
