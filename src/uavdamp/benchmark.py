"""The controller benchmark: tuned baselines, table lookup, ANFIS, clairvoyant bound, over many scenarios.

    tune(inputs, ...)          the controllers' free parameters on the tuning scenarios only, per stiffness
    run_scenario(input, ...)   every controller on one scenario, per stiffness, ideal and lagged damper: criteria
    gather(runs, split)        stacked over scenarios, with mean and worst over the evaluation set

All runs use the linear plant (`uavdamp.linear_plant.LinearPlant`; the rigid mount too, which near its 6.7 Hz
resonance is 1.2-1.7 % off Exudyn: `uavdamp.plants`). Criteria follow the ASCE/IASC benchmarks: each response
metric divided by the rigid mount's on the same scenario (J = 1: no better than rigid; lower is better):
los_std and los_peak (line of sight, `uavdamp.image_quality`), blur_p95, unsharp_fraction (1 - sharp-frame
fraction, so that lower is better; NaN where the rigid mount has no blurred frame), displacement_std
(sqrt(var y + var z) of the camera) and displacement_peak (largest |camera displacement|). Resource criteria are
kept in their units: energy dissipated (J), damping changes per second (s-1: steps where the applied C changes
by more than 1e-9 relative), peak damper force (N, largest C |v_rel|).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr
from threadpoolctl import threadpool_limits

from uavdamp import image_quality, strategies
from uavdamp.camera import CameraModel
from uavdamp.clairvoyant import OBJECTIVES
from uavdamp.contract import DamperBounds, MountMotion
from uavdamp.platform.linear_plant import LinearPlant
from uavdamp.semi_active import Lagged
from uavdamp.settings import attached, require, setting
from uavdamp.tracking import TrackerOptions

J_CRITERIA = ("los_std", "los_peak", "blur_p95", "unsharp_fraction", "displacement_std", "displacement_peak")
RESOURCES = {
    "energy_dissipated": ("J", "energy dissipated by the damper over the run"),
    "damping_changes_per_s": ("s-1", "changes of the applied damping per second"),
    "peak_damper_force": ("N", "largest damper force C |v_rel| over the run"),
}
DAMPERS = ("ideal", "lagged")
# tuned parameter -> (controller, the TuningOptions field of its search range)
TUNED = {
    "passive_damping": ("passive_tuned", "damping_range"),
    "skyhook_c_max": ("skyhook_on_off", "damping_range"),
    "skyhook_gain": ("skyhook_clipped", "gain_range"),
    "groundhook_gain": ("groundhook", "gain_range"),
    "hybrid_gain": ("hybrid", "gain_range"),
    "clipped_optimal_r_scale": ("clipped_optimal", "r_scale_range"),
}


@dataclass(frozen=True)
class TuningOptions:
    criterion: str = setting()  # the J minimised on average over the tuning scenarios
    n_candidates: int = setting()  # log-spaced values per parameter before the bounded refinement
    max_refine: int = setting()  # refinement evaluations (scipy bounded Brent in log value)
    damping_range: tuple[float, ...] = setting("damping_range_n_s_m", length=2)  # N s m-1: passive C, on-off C_max
    gain_range: tuple[float, ...] = setting("gain_range_n_s_m", length=2)  # N s m-1: skyhook/groundhook/hybrid gain
    hybrid_alpha: tuple[float, ...] = setting()  # 1, alphas tried for the hybrid
    q_scale: float = setting("q_scale_m")  # m, clipped-optimal camera weight scale (fixed: only q/r matters)
    r_scale_range: tuple[float, ...] = setting("r_scale_range_n", length=2)  # N, clipped-optimal force scale

    def validate(self) -> None:
        require(self.criterion in J_CRITERIA, "benchmark.tuning.criterion", f"must be one of {J_CRITERIA}")
        for key in ("damping_range", "gain_range", "r_scale_range"):
            lo, hi = getattr(self, key)
            require(0 < lo < hi, f"benchmark.tuning.{key}", "need 0 < min < max")


@dataclass(frozen=True)
class ClairvoyantOptions:
    n_candidates: int = setting()  # log-spaced C from min_damping to the damper's c_max
    min_damping: float = setting("min_damping_n_s_m")  # N s m-1
    beam_width: int = setting()
    criterion: str = setting()  # uavdamp.clairvoyant.OBJECTIVES

    def validate(self) -> None:
        where = "benchmark.clairvoyant."
        require(self.criterion in OBJECTIVES, where + "criterion", f"must be one of {list(OBJECTIVES)}")
        require(self.n_candidates >= 2, where + "n_candidates", f"must be >= 2, got {self.n_candidates}")
        require(self.beam_width >= 1, where + "beam_width", f"must be >= 1, got {self.beam_width}")
        require(self.min_damping > 0, where + "min_damping_n_s_m", f"must be > 0, got {self.min_damping}")


@dataclass(frozen=True, kw_only=True)
class BenchmarkOptions:
    """The runs' view of the config's ``benchmark`` section, with the study's tracker and the camera attached."""

    controllers: tuple[str, ...] = setting()
    stiffness: tuple[float, ...] = setting("stiffness_n_m")  # N m-1
    damper_lag: float = setting("damper_lag_s")  # s, first-order lag of the lagged damper
    tuning: TuningOptions = setting()
    clairvoyant: ClairvoyantOptions = setting()
    tracking: TrackerOptions | None = attached()
    camera: CameraModel | None = attached()

    def validate(self) -> None:
        require("rigid" in self.controllers, "benchmark.controllers", "must hold rigid (the criteria's reference)")
        require(self.damper_lag > 0, "benchmark.damper_lag_s", "must be > 0")
        for key, values in (("stiffness_n_m", self.stiffness),):
            require(bool(values) and min(values) > 0, f"benchmark.{key}", f"must be > 0, got {list(values)}")


def criteria(response: xr.Dataset, rigid: dict, camera: CameraModel) -> tuple[dict, dict]:
    """({criterion: J}, {resource: value}) of one run; rigid: the rigid mount's `response_metrics`."""
    values = response_metrics(response, camera)
    j = {name: (values[name] / rigid[name] if rigid[name] > 0 else math.nan) for name in J_CRITERIA}
    c = response.damping.values
    if np.all(np.isnan(c)):
        return j, {name: math.nan for name in RESOURCES}
    v = response.isolator_velocity.values
    dt = float(response.time[1] - response.time[0])
    changes = np.abs(np.diff(c[:-1])) > 1e-9 * np.maximum(np.abs(c[:-2]), 1e-12)
    resources = {
        "energy_dissipated": float(np.sum(c[:-1] * (v[:, :-1] ** 2).sum(axis=0)) * dt),
        "damping_changes_per_s": float(changes.sum() / (response.time.values[-1] - response.time.values[0])),
        "peak_damper_force": float(np.max(c * np.linalg.norm(v, axis=0))),
    }
    return j, resources


def response_metrics(response: xr.Dataset, camera: CameraModel) -> dict:
    """The response metrics behind J_CRITERIA (rad, px, 1, m)."""
    t, disp = response.time.values, response.camera_displacement.values
    image = image_quality.image_metrics(t, disp, response.camera_yaw.values, response.camera_pitch.values, camera)
    return {
        "los_std": image["los_std"][0],
        "los_peak": image["los_peak"][0],
        "blur_p95": image["blur_p95"][0],
        "unsharp_fraction": 1.0 - image["sharp_fraction"][0],
        "displacement_std": float(np.sqrt(np.var(disp, axis=1).sum())),
        "displacement_peak": float(np.linalg.norm(disp, axis=0).max()),
    }


class _Runner:
    """The plants of one platform and the contexts of one scenario (time s, y m, z m)."""

    def __init__(self, params, options: BenchmarkOptions, model=None, table=None):
        self.params, self.options, self.model, self.table = params, options, model, table
        self.isolated = LinearPlant.from_params(params)
        self.rigid = LinearPlant.from_params(params, mount="rigid")

    def context(self, case: tuple, stiffness: float, tuned: dict) -> strategies.Context:
        def run(strategy, law=None):
            plant = self.rigid if strategy.mount == "rigid" else self.isolated
            time, mount = case
            return plant.run(time, mount, stiffness=stiffness, law=strategy.law if law is None else law)

        return strategies.Context(
            self.options,
            self.params,
            self.model,
            float(stiffness),
            run,
            tuned=tuned,
            table=self.table,
            case_input=case,
            linear=self.isolated,
        )

    def lagged(self, law):
        inner = self.params.update_period if law.update_period is None else law.update_period
        bounds = DamperBounds.from_params(self.params)
        return Lagged(law, self.options.damper_lag, self.params.time_step, inner, bounds)


def _case(ds: xr.Dataset) -> tuple:
    """(time s, MountMotion) of a scenario's input dataset."""
    return ds.time.values, MountMotion(ds.mount_displacement.values, ds.mount_rotation.values)


def tune(inputs: dict[str, xr.Dataset], params, options: BenchmarkOptions) -> xr.Dataset:
    """Tuned parameters per stiffness from the tuning scenarios `inputs` ({name: input dataset}) only.

    Each parameter of a controller in options.controllers minimises the mean over `inputs` of J[criterion]
    (options.tuning.criterion) by `strategies.best_constant` in its range; the hybrid's gain for each alpha.
    """
    o, runner = options.tuning, _Runner(params, options)
    cases = [_case(ds) for ds in inputs.values()]
    out = {}
    with threadpool_limits(1):
        for stiffness in options.stiffness:
            rigid = [
                response_metrics(
                    runner.context(c, stiffness, {}).run(strategies.Strategy("r", "rigid", None)), options.camera
                )
                for c in cases
            ]
            tuned = {"clipped_optimal_q_scale": o.q_scale}
            for key, (controller, field) in TUNED.items():
                if controller not in options.controllers:
                    continue
                search = getattr(o, field)
                if key == "hybrid_gain":
                    value, cost, alpha = min(
                        (*_tune_one(runner, cases, rigid, stiffness, tuned, key, controller, alpha, search), alpha)
                        for alpha in o.hybrid_alpha
                    )
                    tuned["hybrid_alpha"] = out[("hybrid_alpha", stiffness)] = alpha
                else:
                    value, cost = _tune_one(runner, cases, rigid, stiffness, tuned, key, controller, None, search)
                tuned[key] = out[(key, stiffness)] = value
                out[(f"{key}_cost", stiffness)] = cost
    return _tuned_dataset(out, options, list(inputs))


def _tune_one(runner, cases, rigid, stiffness, tuned, key, controller, alpha, value_range):
    """(best value, its mean J) of one parameter on the tuning cases."""
    criterion = runner.options.tuning.criterion

    def cost(value: float) -> float:
        trial = {**tuned, key: value, **({"hybrid_alpha": alpha} if alpha is not None else {})}
        total = 0.0
        for case, ref in zip(cases, rigid, strict=True):
            ctx = runner.context(case, stiffness, trial)
            response = ctx.run(strategies.build(controller, ctx))
            total += criteria(response, ref, runner.options.camera)[0][criterion]
        return total / len(cases)

    lo, hi = value_range
    grid = np.geomspace(lo, hi, runner.options.tuning.n_candidates)
    return strategies.best_constant(cost, grid, DamperBounds(lo, hi), maxiter=runner.options.tuning.max_refine)


_TUNED_UNITS = {
    "passive_damping": "N s m-1",
    "skyhook_c_max": "N s m-1",
    "skyhook_gain": "N s m-1",
    "groundhook_gain": "N s m-1",
    "hybrid_gain": "N s m-1",
    "hybrid_alpha": "1",
    "clipped_optimal_r_scale": "N",
    "clipped_optimal_q_scale": "m",
}


def _tuned_dataset(out: dict, options: BenchmarkOptions, names: list[str]) -> xr.Dataset:
    ks = list(options.stiffness)
    data = {}
    for key in sorted({k for k, _ in out}):
        units = _TUNED_UNITS.get(key, "1")
        long_name = f"mean J[{options.tuning.criterion}] on the tuning set" if key.endswith("_cost") else f"tuned {key}"
        data[key] = ("stiffness", [out[(key, k)] for k in ks], {"units": units, "long_name": long_name})
    data["clipped_optimal_q_scale"] = (
        "stiffness",
        [options.tuning.q_scale] * len(ks),
        {"units": "m", "long_name": "clipped-optimal camera weight scale (fixed)"},
    )
    return xr.Dataset(
        data,
        coords={"stiffness": ("stiffness", ks, {"units": "N m-1", "long_name": "isolator K"})},
        attrs={"tuning_scenarios": ", ".join(names), "tuning_criterion": options.tuning.criterion},
    )


def merge_tuned(parts: list[xr.Dataset]) -> xr.Dataset:
    """Tuned datasets of single stiffnesses (one tuning job each) as one, over stiffness."""
    merged = xr.concat(parts, dim="stiffness", data_vars="all", join="outer", combine_attrs="override")
    return merged.sortby("stiffness")


def tuned_at(tuned: xr.Dataset, stiffness: float) -> dict:
    """{parameter: value} of the tuned dataset at one stiffness (costs left out)."""
    at = tuned.sel(stiffness=stiffness)
    return {k: float(at[k]) for k in tuned.data_vars if not k.endswith("_cost")}


def run_scenario(
    ds: xr.Dataset, tuned: xr.Dataset, params, options: BenchmarkOptions, *, model=None, table=None
) -> xr.Dataset:
    """Criteria of every controller on one scenario: J (controller, stiffness, criterion, damper) and resources."""
    runner, case = _Runner(params, options, model, table), _case(ds)
    shape = (len(options.controllers), len(options.stiffness), len(DAMPERS))
    j = np.full((*shape[:2], len(J_CRITERIA), shape[2]), math.nan)
    res = {name: np.full(shape, math.nan) for name in RESOURCES}
    with threadpool_limits(1):
        rigid = response_metrics(
            runner.context(case, options.stiffness[0], {}).run(strategies.Strategy("rigid", "rigid", None)),
            options.camera,
        )
        for b, stiffness in enumerate(options.stiffness):
            ctx = runner.context(case, stiffness, tuned_at(tuned, stiffness))
            for a, name in enumerate(options.controllers):
                strategy = strategies.build(name, ctx)
                for d, damper in enumerate(DAMPERS):
                    law = strategy.law if (damper == "ideal" or strategy.law is None) else runner.lagged(strategy.law)
                    values, resources = criteria(ctx.run(strategy, law), rigid, options.camera)
                    j[a, b, :, d] = [values[c] for c in J_CRITERIA]
                    for key, value in resources.items():
                        res[key][a, b, d] = value
    dims = ("controller", "stiffness", "damper")
    out = xr.Dataset(
        {
            "J": (
                ("controller", "stiffness", "criterion", "damper"),
                j,
                {"units": "1", "long_name": "criterion relative to the rigid mount (lower is better)"},
            ),
            **{k: (dims, v, {"units": RESOURCES[k][0], "long_name": RESOURCES[k][1]}) for k, v in res.items()},
            "rigid_value": (
                "criterion",
                [rigid[c] for c in J_CRITERIA],
                {"units": "1", "long_name": "the rigid mount's metric (in criterion_units)"},
            ),
        },
        coords=_coords(options),
    )
    out = out.expand_dims(scenario=[ds.attrs.get("scenario", "scenario")])
    return out.assign_coords(scenario=out.scenario.assign_attrs(units="1", long_name="scenario"))


def _coords(options: BenchmarkOptions) -> dict:
    units = {
        "los_std": "rad",
        "los_peak": "rad",
        "blur_p95": "px",
        "unsharp_fraction": "1",
        "displacement_std": "m",
        "displacement_peak": "m",
    }
    return {
        "controller": ("controller", list(options.controllers), {"units": "1", "long_name": "controller"}),
        "stiffness": ("stiffness", list(options.stiffness), {"units": "N m-1", "long_name": "isolator K"}),
        "criterion": ("criterion", list(J_CRITERIA), {"units": "1", "long_name": "criterion"}),
        "criterion_units": (
            "criterion",
            [units[c] for c in J_CRITERIA],
            {"units": "1", "long_name": "units of the rigid mount's metric"},
        ),
        "damper": ("damper", list(DAMPERS), {"units": "1", "long_name": "damper: ideal or first-order lag"}),
    }


def gather(runs: list[xr.Dataset], split: dict[str, str], tuned: xr.Dataset) -> xr.Dataset:
    """All scenarios' criteria, the split, mean and worst J over the evaluation set, and the tuned parameters."""
    ds = xr.concat(
        runs,
        dim="scenario",
        data_vars="all",
        coords="minimal",
        compat="override",
        join="exact",
        combine_attrs="override",
    )
    names = [str(s) for s in ds.scenario.values]
    missing = sorted(set(names) - set(split))
    if missing:
        raise ValueError(f"benchmark: scenarios {missing} are in no set of the split")
    ds = ds.assign_coords(
        scenario=("scenario", names, {"units": "1", "long_name": "scenario"}),
        set=(
            "scenario",
            [split[n] for n in names],
            {"units": "1", "long_name": "set of the scenario: tuning or evaluation"},
        ),
    )
    evaluation = ds.J.where(ds.set == "evaluation", drop=True)
    ds["J_mean"] = evaluation.mean("scenario").assign_attrs(units="1", long_name="mean J over the evaluation set")
    ds["J_worst"] = evaluation.max("scenario").assign_attrs(units="1", long_name="worst J over the evaluation set")
    tuned = tuned.rename({k: f"tuned_{k}" for k in tuned.data_vars})
    return ds.merge(tuned, combine_attrs="override")
