"""Damping strategies of the isolator, in the forms `PlatformSimulator.run` takes.

Every strategy is a `Strategy`: the mount ("rigid": no isolator, or "isolated"), the damping
argument of `PlatformSimulator.run` (None, a constant C in N s m-1, or a decision function
``decide(t_now, seen) -> C``) and the update period it needs (s; None: the platform's default).
All of them keep C within the same damper bounds [c_min, c_max] themselves (the simulator clips
too), and a decision function never returns NaN.

    rigid()                          no isolator (the base follows the fuselage)
    passive(c, bounds)               constant C (e.g. from the config)
    optimal_passive(criterion_of, candidates, bounds)
                                     the constant C minimising a criterion: grid, then bounded refinement
    AnfisDamping(model, stiffness, bounds, ...)
                                     the paper's semi-active ANFIS: tracked f_y, f_z and K -> C
    Skyhook(bounds, time_step)       Karnopp's on-off skyhook, called every solver step

A decision function keeps state (the ANFIS one records its decisions): use one object per run.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize_scalar

from uavdamp.platform import Seen
from uavdamp.spectrum import dominant_frequency_causal

MOUNTS = ("rigid", "isolated")


@dataclass(frozen=True)
class DamperBounds:
    """Damper bounds, N s m-1: c_min <= C <= c_max."""

    c_min: float
    c_max: float

    def __post_init__(self):
        if not (math.isfinite(self.c_min) and math.isfinite(self.c_max) and 0 <= self.c_min <= self.c_max):
            raise ValueError(f"damper bounds: need 0 <= c_min <= c_max, finite, got {self.c_min}, {self.c_max}")

    @classmethod
    def from_params(cls, params) -> DamperBounds:
        """The bounds of a `PlatformParams` (damping_min, damping_max)."""
        return cls(float(params.damping_min), float(params.damping_max))

    def clip(self, c: float) -> float:
        """C (N s m-1) clipped to the bounds."""
        return float(min(max(c, self.c_min), self.c_max))

    def contains(self, c: float) -> bool:
        return bool(self.c_min <= c <= self.c_max)


@dataclass(frozen=True)
class Strategy:
    """What one strategy hands to the simulator.

    name: label; mount: "rigid" or "isolated" (`PlatformSimulator(params, mount=...)`);
    damping: the `run` damping argument (None for rigid, C in N s m-1, or decide(t_now, seen));
    update_period: s, the `run` update_period (None: params.update_period).
    """

    name: str
    mount: str
    damping: float | Callable[[float, Seen], float] | None
    update_period: float | None = None

    def __post_init__(self):
        if self.mount not in MOUNTS:
            raise ValueError(f"mount must be one of {MOUNTS}, got {self.mount!r}")
        if (self.mount == "rigid") != (self.damping is None):
            raise ValueError("damping must be None for the rigid mount and given for the isolated one")


def rigid() -> Strategy:
    """No isolator: the platform base follows the fuselage."""
    return Strategy("rigid", "rigid", None)


def passive(c: float, bounds: DamperBounds, name: str = "passive") -> Strategy:
    """Constant damping C, N s m-1; ValueError if C is outside the bounds."""
    c = float(c)
    if not bounds.contains(c):
        raise ValueError(f"passive damping {c} N s m-1 is outside [{bounds.c_min}, {bounds.c_max}]")
    return Strategy(name, "isolated", c)


# ---------------------------------------------------------------------------- optimal passive


@dataclass
class OptimalPassive:
    """Result of `optimal_passive`: best C (N s m-1), its criterion, every (C, criterion) evaluated in order."""

    c: float
    criterion: float
    evaluations: list[tuple[float, float]]

    def strategy(self, name: str = "optimal_passive") -> Strategy:
        return Strategy(name, "isolated", self.c)


def optimal_passive(criterion_of: Callable[[float], float], candidates: Sequence[float], bounds: DamperBounds, *,
                    xatol_log: float = 0.01, maxiter: int = 20) -> OptimalPassive:
    """The constant C minimising criterion_of(C): the candidates first, then a bounded refinement.

    candidates: C values, N s m-1, > 0 and within the bounds (e.g. a log grid). The refinement is
    scipy's bounded Brent search (`minimize_scalar(method="bounded")`) in log C between the
    neighbours of the best candidate (the best one itself if it is at an end of the grid, then the
    search is between it and its one neighbour), to `xatol_log` in log C (0.01: 1 % in C) within
    `maxiter` evaluations. Deterministic; each C is evaluated once (cached). The result is the best
    of all evaluations. A non-finite criterion counts as +inf.
    """
    grid = np.unique(np.asarray(candidates, dtype=float))
    if grid.size < 2:
        raise ValueError("candidates: need at least 2 distinct values")
    if grid[0] <= 0 or not (bounds.contains(grid[0]) and bounds.contains(grid[-1])):
        raise ValueError(f"candidates must be > 0 and within [{bounds.c_min}, {bounds.c_max}] N s m-1")
    evaluations: list[tuple[float, float]] = []
    cache: dict[float, float] = {}

    def evaluate(c: float) -> float:
        c = bounds.clip(float(c))
        if c not in cache:
            value = float(criterion_of(c))
            cache[c] = value if math.isfinite(value) else math.inf
            evaluations.append((c, cache[c]))
        return cache[c]

    values = np.array([evaluate(c) for c in grid])
    k = int(np.argmin(values))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    minimize_scalar(lambda log_c: evaluate(math.exp(log_c)), bounds=(math.log(lo), math.log(hi)), method="bounded",
                    options={"xatol": xatol_log, "maxiter": maxiter})
    c_best, value_best = min(evaluations, key=lambda e: (e[1], e[0]))
    return OptimalPassive(c_best, value_best, evaluations)


# ---------------------------------------------------------------------------- ANFIS semi-active


@dataclass(frozen=True)
class Decision:
    """One ANFIS decision: time s, tracked freq_y_hz and freq_z_hz (NaN if none), damping N s m-1, note."""

    time: float
    freq_y_hz: float
    freq_z_hz: float
    damping: float
    note: str  # "anfis", "clipped", "initial: no frequency yet", "held: ..." (why the last C was kept)


@dataclass
class AnfisDamping:
    """The paper's semi-active controller (Figs. 8, 9): a decision function for `PlatformSimulator.run`.

    At each call (the simulator calls it at t = 0, P, 2P, ...; P = params.update_period, paper 0.5 s)
    the dominant frequencies f_y, f_z of the fuselage input seen so far are tracked by
    `dominant_frequency_causal` (the same numbers as `spectrum.track_dominant` with these options)
    and C = model.predict([[f_y, f_z, stiffness]]), clipped to the bounds. Until both frequencies are
    available (t = 0, and while less than min(window, min_cycles / min_freq_hz) s has been seen)
    c_initial is used. If tracking or the model gives a non-finite value, the previous C is kept.
    Every call is recorded in `decisions`; a call at a time not after the last recorded one (a new
    run) starts a new record.

    model: anything with predict(X (n, 3)) -> (n,) in N s m-1 (an `ANFIS`); stiffness: K, N m-1;
    c_initial: N s m-1, within the bounds; window: s; min_freq_hz, max_freq_hz: search band, Hz.
    """

    model: object
    stiffness: float
    bounds: DamperBounds
    c_initial: float
    window: float = 1.0
    min_freq_hz: float = 3.0
    max_freq_hz: float = 12.0
    zero_padding: int = 8
    min_cycles: float = 2.0
    decisions: list[Decision] = field(default_factory=list)

    def __post_init__(self):
        if not self.bounds.contains(self.c_initial):
            raise ValueError(f"c_initial {self.c_initial} N s m-1 is outside the damper bounds")
        if not (math.isfinite(self.stiffness) and self.stiffness > 0):
            raise ValueError(f"stiffness must be > 0, got {self.stiffness}")

    def track(self, time: np.ndarray, signal: np.ndarray, t_now: float) -> float:
        """Dominant frequency, Hz, of `signal` at t_now with this controller's options (NaN if none)."""
        return dominant_frequency_causal(time, signal, t_now, self.window, min_freq_hz=self.min_freq_hz,
                                         max_freq_hz=self.max_freq_hz, zero_padding=self.zero_padding,
                                         min_cycles=self.min_cycles)

    def __call__(self, t_now: float, seen: Seen) -> float:
        if self.decisions and t_now <= self.decisions[-1].time:
            self.decisions = []
        previous = self.decisions[-1].damping if self.decisions else float(self.c_initial)
        f_y = self.track(seen.time, seen.mount_y, t_now)
        f_z = self.track(seen.time, seen.mount_z, t_now)
        if not (math.isfinite(f_y) and math.isfinite(f_z)):
            started = any(not d.note.startswith("initial") for d in self.decisions)
            c, note = previous, ("held: no frequency tracked" if started else "initial: no frequency yet")
        else:
            raw = float(np.asarray(self.model.predict(np.array([[f_y, f_z, self.stiffness]]))).ravel()[0])
            if not math.isfinite(raw):
                c, note = previous, "held: model returned a non-finite C"
            else:
                c = self.bounds.clip(raw)
                note = "anfis" if c == raw else "clipped"
        self.decisions.append(Decision(float(t_now), f_y, f_z, c, note))
        return c

    def strategy(self, name: str = "anfis") -> Strategy:
        """The strategy (update period: the platform's default, paper 0.5 s)."""
        return Strategy(name, "isolated", self)


# ---------------------------------------------------------------------------- skyhook


@dataclass
class Skyhook:
    """Karnopp's on-off skyhook (Karnopp et al. 1974): C = c_max when the damper can act as a skyhook.

    One C serves both axes (as in the paper), so the two-axis rule is the power condition: with the
    damper force on the base F = -C v_rel (v_rel = base - mount velocity, (y, z)), F opposes the base's
    absolute velocity v_abs, F . v_abs < 0, exactly when v_abs . v_rel > 0. Then C = c_max, else c_min
    (ties: c_min). For one axis this is Karnopp's v_abs v_rel > 0 rule.

    It must be called every solver step: pass `update_period` (= time_step, s) to
    `PlatformSimulator.run`; `strategy()` does. The decision uses the state at t_now (`Seen`
    base_velocity and mount_velocity) and acts from t_now on. `switches` counts changes of C.
    """

    bounds: DamperBounds
    time_step: float
    switches: int = 0
    _last: float | None = None

    @property
    def update_period(self) -> float:
        """s, the period the simulator must call this at: the solver time step."""
        return self.time_step

    def decide(self, v_abs: np.ndarray, v_rel: np.ndarray) -> float:
        """C, N s m-1, for absolute base velocity and relative (base - mount) velocity, m s-1, (y, z)."""
        on = float(np.dot(v_abs, v_rel)) > 0.0
        return self.bounds.c_max if on else self.bounds.c_min

    def __call__(self, t_now: float, seen: Seen) -> float:
        v_abs = np.asarray(seen.base_velocity, dtype=float)
        c = self.decide(v_abs, v_abs - np.asarray(seen.mount_velocity, dtype=float))
        if t_now == 0.0:
            self.switches, self._last = 0, None
        if self._last is not None and c != self._last:
            self.switches += 1
        self._last = c
        return c

    def strategy(self, name: str = "skyhook") -> Strategy:
        return Strategy(name, "isolated", self, self.time_step)
