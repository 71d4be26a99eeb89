"""Damping laws: what C (N s m-1) to demand, given an `Observation` (see `uavdamp.contract`).

    Constant(c)                        a passive damper
    Schedule(values)                   value k from the k-th update on (the last one holds)
    AnfisLaw(model, stiffness, ...)    the paper's semi-active ANFIS: tracked f_y, f_z and K -> C
    Skyhook(c_on, c_off, time_step)    Karnopp's on-off skyhook, decided every solver step

A law returns a demand; the plant clips it to the damper bounds (`uavdamp.contract.clip`). A law with state
resets it in `reset()`, which the plant calls at the start of every run, so one object can serve many runs.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from uavdamp.contract import Observation

Tracker = Callable[[np.ndarray, np.ndarray, float], float]  # (time s, signal, t_now s) -> dominant frequency, Hz


class Constant:
    """A passive damper: C (N s m-1) at every update."""

    name = "constant"
    update_period = None

    def __init__(self, c: float):
        self.c = float(c)
        if not math.isfinite(self.c):
            raise ValueError(f"damping: must be finite, got {c}")

    def reset(self) -> None:
        pass

    def __call__(self, observation: Observation) -> float:
        return self.c


class Schedule:
    """Piecewise-constant damping: values[k] (N s m-1) from the k-th update (t = k P) on; the last one holds."""

    name = "schedule"

    def __init__(self, values: Sequence[float], update_period: float | None = None):
        self.values = np.asarray(values, dtype=float)
        if self.values.ndim != 1 or self.values.size == 0:
            raise ValueError("damping schedule must be a non-empty 1-D sequence")
        self.update_period = update_period
        self._k = 0

    def reset(self) -> None:
        self._k = 0

    def __call__(self, observation: Observation) -> float:
        c = self.values[min(self._k, self.values.size - 1)]
        self._k += 1
        return float(c)


class AnfisLaw:
    """The paper's semi-active controller (Figs. 8, 9): C = model.predict([[f_y, f_z, K]]) every update.

    At each call the dominant frequencies f_y, f_z of the fuselage input seen so far are found by `track`
    (time s, signal, t_now s) -> Hz, NaN while it has too little signal. Until both frequencies are available
    the law demands c_initial; if tracking or the model gives a non-finite value later, it holds its last
    demand. model: anything with predict(X (n, 3)) -> (n,) in N s m-1; stiffness: K, N m-1.
    """

    name = "anfis"
    update_period = None

    def __init__(self, model, stiffness: float, c_initial: float, track: Tracker):
        if not (math.isfinite(stiffness) and stiffness > 0):
            raise ValueError(f"stiffness must be > 0, got {stiffness}")
        self.model, self.stiffness, self.c_initial, self.track = model, float(stiffness), float(c_initial), track
        self._last = self.c_initial

    def reset(self) -> None:
        self._last = self.c_initial

    def __call__(self, observation: Observation) -> float:
        f_y = self.track(observation.time, observation.mount_y, observation.t_now)
        f_z = self.track(observation.time, observation.mount_z, observation.t_now)
        if math.isfinite(f_y) and math.isfinite(f_z):
            raw = float(np.asarray(self.model.predict(np.array([[f_y, f_z, self.stiffness]]))).ravel()[0])
            if math.isfinite(raw):
                self._last = raw
        return self._last


class Skyhook:
    """Karnopp's on-off skyhook (Karnopp et al. 1974): c_on when the damper can act as a skyhook, else c_off.

    One C serves both axes (as in the paper), so the two-axis rule is the power condition: with the damper
    force on the base F = -C v_rel (v_rel = base - mount velocity, (y, z)), F opposes the base's absolute
    velocity v_abs, F . v_abs < 0, exactly when v_abs . v_rel > 0 (ties: c_off). For one axis this is
    Karnopp's v_abs v_rel > 0 rule. Decided every solver step: update_period = time_step, s.
    """

    name = "skyhook"

    def __init__(self, c_on: float, c_off: float, time_step: float):
        self.c_on, self.c_off, self.update_period = float(c_on), float(c_off), float(time_step)

    def reset(self) -> None:
        pass

    def decide(self, v_abs: np.ndarray, v_rel: np.ndarray) -> float:
        """C, N s m-1, for absolute base velocity and relative (base - mount) velocity, m s-1, (y, z)."""
        return self.c_on if float(np.dot(v_abs, v_rel)) > 0.0 else self.c_off

    def decide_rows(self, v_abs: np.ndarray, v_rel: np.ndarray) -> np.ndarray:
        """`decide` for each row of (k, d) velocities (k dampers, each on its own velocities): (k,) N s m-1."""
        return np.where(np.einsum("ij,ij->i", v_abs, v_rel) > 0.0, self.c_on, self.c_off)

    @staticmethod
    def decide_batch(laws: list[Skyhook], v_abs: np.ndarray, v_rel: np.ndarray) -> np.ndarray:
        """`decide_rows` of laws[b] on the rows of (B, k, d) velocities b, all in one call: (B, k) N s m-1."""
        c_on, c_off = np.array([[law.c_on] for law in laws]), np.array([[law.c_off] for law in laws])
        return np.where(np.einsum("bij,bij->bi", v_abs, v_rel) > 0.0, c_on, c_off)

    def __call__(self, observation: Observation) -> float:
        return self.decide(np.asarray(observation.base_velocity), np.asarray(observation.stroke_rate))
