"""The benchmark's runs and tuning: each law under each damper model, tuned per criterion family on the tuning set.

    tune(inputs, params, options)  every tuned parameter per family (benchmark.tuning.criteria: one criterion per
                                   family, `uavdamp.camera.criteria.FAMILIES`) and stiffness, on the tuning
                                   scenarios only
    merge_tuned, tuned_at          the tuning jobs' datasets as one; the parameters at (K, criterion)
    register_tuned(key, ...)       a plug-in law's parameter, tuned like the built-in ones (from the plug-in's file)

Each parameter of a controller minimises the mean over the tuning scenarios of J[criterion] by
`strategies.best_constant` in its range (the hybrid's gain for each alpha), once per tuning criterion: the
log-spaced candidates, then a refinement only where the parabola through the best of them and its neighbours
promises at least `benchmark.tuning.min_gain` of J (the per-step laws' step error: finer is not resolved). Runs are
shared between the criteria (one run gives every J). A law decided every solver step is tuned, like it is run, with
the first of benchmark.per_step_dampers; every other law with the ideal damper.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr
from threadpoolctl import threadpool_limits

from uavdamp import registry
from uavdamp.benchmark import scoring
from uavdamp.benchmark.runner import Runner, case_of, plant_params
from uavdamp.contract import DamperBounds
from uavdamp.study import strategies

# tuned parameter -> (controller, its search range: a TuningOptions range's name or a plug-in's own (min, max), units)
TUNED = {
    "passive_damping": ("passive_tuned", "damping_range", "N s m-1"),
    "skyhook_c_max": ("skyhook_on_off", "damping_range", "N s m-1"),
    "skyhook_gain": ("skyhook_clipped", "gain_range", "N s m-1"),
    "groundhook_gain": ("groundhook", "gain_range", "N s m-1"),
    "hybrid_gain": ("hybrid", "gain_range", "N s m-1"),
    "clipped_optimal_r_scale": ("clipped_optimal", "r_scale_range", "N"),
}
_UNITS = {**{k: v[2] for k, v in TUNED.items()}, "hybrid_alpha": "1", "clipped_optimal_q_scale": "m"}
TUNED_CONTROLLERS = {v[0] for v in TUNED.values()}
RANGES = ("damping_range", "gain_range", "r_scale_range")  # the benchmark.tuning ranges a parameter is searched in


def register_tuned(key: str, controller: str, search, units: str) -> None:
    """Tune `key` (the name the strategy `controller`'s factory reads from ``ctx.tuned``) on the tuning scenarios, per
    tuning criterion and K, like the built-in parameters (`TUNED`). `search`: the name of a ``benchmark.tuning``
    range (`RANGES`) or the plug-in's own (min, max) with 0 < min < max, in `units` (searched on a log grid). A
    plug-in calls it from its own file; the tuned value reaches its factory in the benchmark's runs, and its search
    the budget's run count. ValueError names a key that is taken or not a safe name, or a bad range."""
    if isinstance(search, str):
        if search not in RANGES:
            raise ValueError(f"tuned parameter {key!r}: range {search!r} is not one of benchmark.tuning's {RANGES}")
    else:
        bounds = tuple(float(v) for v in search)
        if not (len(bounds) == 2 and 0 < bounds[0] < bounds[1] < math.inf):
            raise ValueError(f"tuned parameter {key!r}: range {tuple(search)} needs (min, max) with 0 < min < max")
        search = bounds
    registry.add(TUNED, "tuned parameter", key)((controller, search, units))
    _UNITS[key] = units
    TUNED_CONTROLLERS.add(controller)


def search_range(options, search) -> tuple[float, float]:
    """(min, max) of a `TUNED` entry's search range: benchmark.tuning's named range (`options`), or its own."""
    return tuple(getattr(options, search)) if isinstance(search, str) else search


def tune(inputs: dict[str, xr.Dataset], params, options, mr=None) -> xr.Dataset:
    """Tuned parameters per (tuning criterion, stiffness) from the tuning scenarios `inputs` ({name: input dataset})
    only (module docstring), on the plant of `plant_params`."""
    o, runner = options.tuning, Runner(plant_params(params, options), options, mr=mr)
    cases = [case_of(ds) for ds in inputs.values()]
    out = {}
    with threadpool_limits(1):
        for stiffness in options.stiffness:
            rigid = [
                scoring.response_metrics(
                    runner.rigid.run(*c, stiffness=stiffness), options.camera, options.frame_phases
                )
                for c in cases
            ]
            evaluated: dict = {}  # (controller, key, alpha, value) -> [J dict per case]: shared by the criteria
            for criterion in o.criteria:
                tuned = {"clipped_optimal_q_scale": o.q_scale}
                for key, (controller, span, _) in TUNED.items():
                    if controller not in options.controllers:
                        continue
                    search = _Search(runner, cases, rigid, stiffness, tuned, evaluated, criterion)
                    if key == "hybrid_gain":
                        value, cost, alpha = min(
                            (*search.best(key, controller, alpha, search_range(o, span)), alpha)
                            for alpha in o.hybrid_alpha
                        )
                        tuned["hybrid_alpha"] = out[("hybrid_alpha", criterion, stiffness)] = alpha
                    else:
                        value, cost = search.best(key, controller, None, search_range(o, span))
                    tuned[key] = out[(key, criterion, stiffness)] = value
                    out[(f"{key}_cost", criterion, stiffness)] = cost
    return _tuned_dataset(out, options, list(inputs))


class _Search:
    """The search of one parameter for one criterion: mean J[criterion] over the tuning cases, runs cached."""

    def __init__(self, runner, cases, rigid, stiffness, tuned, evaluated, criterion):
        self.runner, self.cases, self.rigid, self.stiffness = runner, cases, rigid, stiffness
        self.tuned, self.evaluated, self.criterion = tuned, evaluated, criterion

    def j(self, key, controller, alpha, value) -> list[dict]:
        memo = (controller, key, alpha, float(value))  # a factory reads its own parameters only
        if memo not in self.evaluated:
            trial = {**self.tuned, key: value, **({"hybrid_alpha": alpha} if alpha is not None else {})}
            found = []
            for case, ref in zip(self.cases, self.rigid, strict=True):
                ctx = self.runner.context(case, self.stiffness, trial)
                strategy = strategies.build(controller, ctx)
                response = self.runner.run(ctx, strategy, self.runner.tuning_damper(strategy))
                found.append(scoring.criteria(response, ref, ctx.options.camera, ctx.options.frame_phases)[0])
            self.evaluated[memo] = found
        return self.evaluated[memo]

    def best(self, key, controller, alpha, value_range) -> tuple[float, float]:
        """(best value, its mean J) in value_range."""
        o = self.runner.options.tuning

        def cost(value: float) -> float:
            values = [j[self.criterion] for j in self.j(key, controller, alpha, value)]
            return float(np.mean(values)) if all(math.isfinite(v) for v in values) else math.inf

        lo, hi = value_range
        grid = np.geomspace(lo, hi, o.n_candidates)
        return strategies.best_constant(cost, grid, DamperBounds(lo, hi), maxiter=o.max_refine, min_gain=o.min_gain)


def _tuned_dataset(out: dict, options, names: list[str]) -> xr.Dataset:
    ks, crit = list(options.stiffness), list(options.tuning.criteria)
    data = {}
    for key in sorted({k for k, _, _ in out}):
        long_name = "mean J[tuned_for] on the tuning set" if key.endswith("_cost") else f"tuned {key}"
        values = [[out[(key, c, k)] for k in ks] for c in crit]
        data[key] = (("tuned_for", "stiffness"), values, {"units": _UNITS.get(key, "1"), "long_name": long_name})
    data["clipped_optimal_q_scale"] = (
        ("tuned_for", "stiffness"),
        np.full((len(crit), len(ks)), options.tuning.q_scale),
        {"units": "m", "long_name": "clipped-optimal camera weight scale (fixed)"},
    )
    coords = {
        "stiffness": ("stiffness", ks, {"units": "N m-1", "long_name": "isolator K"}),
        "tuned_for": ("tuned_for", crit, {"units": "1", "long_name": "the criterion the parameters minimise"}),
    }
    return xr.Dataset(data, coords=coords, attrs={"tuning_scenarios": ", ".join(names)})


def merge_tuned(parts: list[xr.Dataset]) -> xr.Dataset:
    """Tuned datasets of single stiffnesses (one tuning job each) as one, over stiffness."""
    merged = xr.concat(parts, dim="stiffness", data_vars="all", join="outer", combine_attrs="override")
    return merged.sortby("stiffness")


def tuned_at(tuned: xr.Dataset, stiffness: float, criterion: str) -> dict:
    """{parameter: value} of the tuned dataset at one stiffness, tuned for `criterion` (costs left out)."""
    at = tuned.sel(stiffness=stiffness, tuned_for=criterion)
    return {k: float(at[k]) for k in tuned.data_vars if not k.endswith("_cost")}
