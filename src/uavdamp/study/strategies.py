"""Damping strategies by name: how the study builds a mount and a damping law for one case and stiffness.

A strategy factory takes a `Context` and returns a `Strategy`: the mount ("rigid" or "isolated"), the damping
law (`uavdamp.damping.laws`; None for the rigid mount) and `info`, named scalars worth keeping (stored by the study as
variables over (case, stiffness)). Factories are registered by name with `@register("name")`; the study's list
comes from the config (``study.strategies``). Adding a strategy is one factory, its registration and its tests.

    rigid            no isolator (the base follows the fuselage)
    passive          constant C from the config
    optimal_passive  the constant C minimising the criterion for this case: grid, then bounded refinement
    anfis            the paper's semi-active ANFIS: tracked f_y, f_z (study.tracking.method) and K -> C, every update
    skyhook          Karnopp's on-off skyhook between the damper bounds, every solver step

The benchmark's (`uavdamp.damping.semi_active`, `uavdamp.damping.clairvoyant`), with parameters from `Context.tuned`:
    passive_tuned    constant C = tuned["passive_damping"]
    table_lookup     the reference table (`Context.table`) interpolated at the tracked f_y, f_z and K, every update
    skyhook_on_off   Karnopp's on-off skyhook between c_min and tuned["skyhook_c_max"], every solver step
    skyhook_clipped  continuous clipped skyhook, gain tuned["skyhook_gain"], every solver step
    groundhook       continuous clipped groundhook, gain tuned["groundhook_gain"], every solver step
    hybrid           Ahmadian's hybrid, gain tuned["hybrid_gain"], alpha tuned["hybrid_alpha"], every solver step
    clipped_optimal  Dyke et al.'s clipped-optimal LQR (r_scale tuned["clipped_optimal_r_scale"]), every solver step
    clairvoyant      the beam-searched schedule of C per update period, knowing the case input (`Context.case_input`);
                     candidates: options.clairvoyant's log grid plus tuned["passive_damping"] when tuned
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from uavdamp import registry
from uavdamp.camera.criteria import CRITERIA
from uavdamp.contract import DamperBounds, clip
from uavdamp.damping import clairvoyant as cv
from uavdamp.damping import laws
from uavdamp.damping.semi_active import ClippedOptimal, Hybrid
from uavdamp.reference_table import TableLookup
from uavdamp.reference_table import criteria as criterion
from uavdamp.signals import tracking

REGISTRY: dict[str, Callable] = {}


@dataclass(frozen=True)
class Strategy:
    """What one strategy hands to a plant: mount, law, and named scalars {name: (value, units, long_name)}."""

    name: str
    mount: str
    law: object | None
    info: dict = field(default_factory=dict)


@dataclass
class Context:
    """What a strategy factory may use: the study's options, the platform, the model, K, and a trial run.

    run(strategy) -> response dataset simulates a strategy on this case and stiffness (for searches).
    """

    options: object  # uavdamp.study.comparison.StudyOptions
    params: object  # uavdamp.platform.PlatformParams
    model: object  # the trained table model: predict([[f_y Hz, f_z Hz, K N/m]]) -> C N s/m
    stiffness: float  # N m-1
    run: Callable
    tuned: dict = field(default_factory=dict)  # benchmark: tuned parameters at this K, {name: value}
    table: object | None = None  # benchmark: the reference table dataset (damping_opt over freq_y, freq_z, stiffness)
    case_input: tuple | None = None  # benchmark: (time s, MountMotion) of the case, for the clairvoyant
    linear: object | None = None  # benchmark: the isolated `LinearPlant` (its model for clipped-optimal and beams)

    @property
    def bounds(self) -> DamperBounds:
        return DamperBounds.from_params(self.params)


def register(name: str):
    """Register a strategy factory under `name` (decorator)."""
    return registry.add(REGISTRY, "strategy", name)


def describe(name: str) -> str:
    """One sentence on a registered strategy: its factory's docstring's first line (the name if it has none)."""
    doc = (REGISTRY[name].__doc__ or "").strip() if name in REGISTRY else ""
    return doc.splitlines()[0] if doc else name


def build(name: str, context: Context) -> Strategy:
    """The named strategy for this context; ValueError names an unknown strategy."""
    if name not in REGISTRY:
        raise ValueError(f"study.strategies: unknown strategy {name!r} (known: {sorted(REGISTRY)})")
    strategy = REGISTRY[name](context)
    return strategy if strategy.name == name else Strategy(name, strategy.mount, strategy.law, strategy.info)


@register("rigid")
def rigid(ctx: Context) -> Strategy:
    """No isolator: the camera platform's base follows the fuselage."""
    return Strategy("rigid", "rigid", None)


@register("passive")
def passive(ctx: Context) -> Strategy:
    """A passive damper: constant C from the config (study.passive_damping_n_s_m)."""
    c = float(ctx.options.passive_damping)
    if not ctx.bounds.contains(c):
        raise ValueError(f"study.passive_damping_n_s_m: {c} is outside [{ctx.bounds.c_min}, {ctx.bounds.c_max}]")
    return Strategy("passive", "isolated", laws.Constant(c))


@register("optimal_passive")
def optimal_passive(ctx: Context) -> Strategy:
    """The best constant C for this case and K (a grid of C, then a bounded refinement)."""
    bounds = ctx.bounds
    candidates = np.geomspace(max(bounds.c_min, 1e-3), bounds.c_max, ctx.options.optimal_candidates)

    def cost(c: float) -> float:
        response = ctx.run(Strategy("trial", "isolated", laws.Constant(c)))
        return criterion.camera_criterion(response.camera_displacement, (0.0, math.inf))

    c_best, _ = best_constant(cost, candidates, bounds)
    info = {"optimal_damping": (c_best, "N s m-1", "best constant damping for the case (optimal_passive)")}
    return Strategy("optimal_passive", "isolated", laws.Constant(c_best), info)


@register("anfis")
def anfis(ctx: Context) -> Strategy:
    """The paper's semi-active ANFIS: C from the tracked f_y, f_z and K at every update."""
    o = ctx.options.tracking
    initial = ctx.model.predict([[o.initial_freq_hz, o.initial_freq_hz, ctx.stiffness]])[0]
    c_initial = clip(initial, ctx.bounds, 0.0)
    track = functools.partial(tracking.frequency_causal, options=o)
    info = {"anfis_initial_damping": (c_initial, "N s m-1", "ANFIS damping before the first frequency estimate")}
    return Strategy("anfis", "isolated", laws.AnfisLaw(ctx.model, ctx.stiffness, c_initial, track), info)


@register("skyhook")
def skyhook(ctx: Context) -> Strategy:
    """Karnopp's on-off skyhook between the damper bounds, switched every solver step."""
    return Strategy("skyhook", "isolated", laws.Skyhook(ctx.bounds.c_max, ctx.bounds.c_min, ctx.params.time_step))


def best_constant(
    cost: Callable[[float], float],
    candidates: Sequence[float],
    bounds: DamperBounds,
    *,
    xatol_log: float = 0.01,
    maxiter: int = 20,
    min_gain: float = 0.0,
) -> tuple[float, float]:
    """The constant C (N s m-1) minimising cost(C), and its cost: the candidates first, then a refinement.

    candidates: > 0 and within the bounds (e.g. a log grid). The refinement is scipy's bounded Brent search
    (`minimize_scalar(method="bounded")`) in log C between the neighbours of the best candidate, to `xatol_log`
    in log C (0.01: 1 % in C) within `maxiter` evaluations; it is skipped where the parabola through the best
    candidate and its two nearest neighbours (in log C) promises less than `min_gain` (in the cost's units) below
    the best candidate's cost (`parabola_gain`). Each C is evaluated once; a non-finite cost counts as +inf; among
    equal costs the smallest C wins.
    """
    from scipy.optimize import minimize_scalar

    grid = np.unique(np.asarray(candidates, dtype=float))
    if grid.size < 2:
        raise ValueError("candidates: need at least 2 distinct values")
    if grid[0] <= 0 or not (bounds.contains(grid[0]) and bounds.contains(grid[-1])):
        raise ValueError(f"candidates must be > 0 and within [{bounds.c_min}, {bounds.c_max}] N s m-1")
    cache: dict[float, float] = {}

    def evaluate(c: float) -> float:
        c = clip(c, bounds, math.nan)
        if c not in cache:
            value = float(cost(c))
            cache[c] = value if math.isfinite(value) else math.inf
        return cache[c]

    values = np.array([evaluate(c) for c in grid])
    k = int(np.argmin(values))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    first = min(max(k - 1, 0), max(grid.size - 3, 0))  # the best candidate's nearest three (two at a grid of two)
    three = slice(first, first + 3)
    if min_gain <= 0 or parabola_gain(np.log(grid[three]), values[three], math.log(lo), math.log(hi)) >= min_gain:
        minimize_scalar(
            lambda log_c: evaluate(math.exp(log_c)),
            bounds=(math.log(lo), math.log(hi)),
            method="bounded",
            options={"xatol": xatol_log, "maxiter": maxiter},
        )
    c_best, value_best = min(cache.items(), key=lambda e: (e[1], e[0]))
    return c_best, value_best


def parabola_gain(x: np.ndarray, y: np.ndarray, lo: float, hi: float) -> float:
    """min(y) minus the least value over [lo, hi] of the parabola through the three points (x, y); +inf where a y is
    not finite or fewer than three distinct x are given (nothing to predict from)."""
    if x.size < 3 or not np.all(np.isfinite(y)):
        return math.inf
    a, b, c = np.polyfit(x, y, 2)
    ends = [lo, hi] + ([-b / (2 * a)] if a > 0 and lo < -b / (2 * a) < hi else [])
    return float(np.min(y) - min(np.polyval((a, b, c), e) for e in ends))


# ------------------------------------------------------------------------------------- the benchmark's


def _tuned(ctx: Context, key: str) -> float:
    if key not in ctx.tuned:
        raise ValueError(f"tuned parameter {key!r} missing (have: {sorted(ctx.tuned)}): tune the benchmark first")
    return float(ctx.tuned[key])


def _needs(ctx: Context, name: str, what: str):
    value = getattr(ctx, what)
    if value is None:
        raise ValueError(f"strategy {name!r} needs Context.{what}")
    return value


@register("passive_tuned")
def passive_tuned(ctx: Context) -> Strategy:
    """A constant C tuned on the tuning scenarios."""
    return Strategy("passive_tuned", "isolated", laws.Constant(_tuned(ctx, "passive_damping")))


@register("table_lookup")
def table_lookup(ctx: Context) -> Strategy:
    """The reference table interpolated at the tracked f_y, f_z and K at every update."""
    table = _needs(ctx, "table_lookup", "table")
    strategy = anfis(dataclasses.replace(ctx, model=TableLookup(table)))
    law = strategy.law
    law.name = "table_lookup"
    info = {"table_initial_damping": (law.c_initial, "N s m-1", "table lookup damping before the first estimate")}
    return Strategy("table_lookup", "isolated", law, info)


@register("skyhook_on_off")
def skyhook_on_off(ctx: Context) -> Strategy:
    """Karnopp's on-off skyhook between c_min and a tuned c_max, every solver step."""
    law = laws.Skyhook(_tuned(ctx, "skyhook_c_max"), ctx.bounds.c_min, ctx.params.time_step)
    return Strategy("skyhook_on_off", "isolated", law)


def _hybrid(ctx: Context, name: str, gain_key: str, alpha: float) -> Strategy:

    law = Hybrid(_tuned(ctx, gain_key), alpha, ctx.bounds, ctx.params.time_step, name=name)
    return Strategy(name, "isolated", law)


@register("skyhook_clipped")
def skyhook_clipped(ctx: Context) -> Strategy:
    """Continuous clipped skyhook with a tuned gain, every solver step."""
    return _hybrid(ctx, "skyhook_clipped", "skyhook_gain", 1.0)


@register("groundhook")
def groundhook(ctx: Context) -> Strategy:
    """Continuous clipped groundhook with a tuned gain, every solver step."""
    return _hybrid(ctx, "groundhook", "groundhook_gain", 0.0)


@register("hybrid")
def hybrid(ctx: Context) -> Strategy:
    """Ahmadian's hybrid skyhook-groundhook with a tuned gain and alpha, every solver step."""
    return _hybrid(ctx, "hybrid", "hybrid_gain", _tuned(ctx, "hybrid_alpha"))


@register("clipped_optimal")
def clipped_optimal(ctx: Context) -> Strategy:
    """Dyke et al.'s clipped-optimal LQR with a tuned force weight, every solver step."""

    plant = _needs(ctx, "clipped_optimal", "linear")
    law = ClippedOptimal(
        plant.model,
        ctx.stiffness,
        ctx.bounds,
        ctx.params.time_step,
        q_scale=_tuned(ctx, "clipped_optimal_q_scale"),
        r_scale=_tuned(ctx, "clipped_optimal_r_scale"),
    )
    return Strategy("clipped_optimal", "isolated", law)


@register("clairvoyant")
def clairvoyant(ctx: Context) -> Strategy:
    """A beam-searched schedule of C per update period knowing the whole input (a bound, not a law)."""

    plant, (time, mount) = _needs(ctx, "clairvoyant", "linear"), _needs(ctx, "clairvoyant", "case_input")
    o = getattr(ctx.options, "clairvoyant", None)
    if o is None:
        raise ValueError("strategy 'clairvoyant' needs options.clairvoyant (the benchmark's)")
    bounds = ctx.bounds
    candidates = np.geomspace(max(bounds.c_min, o.min_damping), bounds.c_max, o.n_candidates)
    if "passive_damping" in ctx.tuned:  # the tuned passive C is a candidate: the bound is never above it
        candidates = np.append(candidates, clip(ctx.tuned["passive_damping"], bounds, 0.0))
    period = ctx.params.update_period
    found = cv.schedule(
        plant,
        time,
        mount,
        stiffness=ctx.stiffness,
        candidates=candidates,
        update_period=period,
        beam_width=o.beam_width,
        criterion=getattr(o, "criterion", "displacement_std"),
    )
    units = CRITERIA[found.criterion].units
    info = {"clairvoyant_cost": (found.cost, units, f"clairvoyant schedule's {found.criterion}")}
    return Strategy("clairvoyant", "isolated", laws.Schedule(found.values, update_period=period), info)
