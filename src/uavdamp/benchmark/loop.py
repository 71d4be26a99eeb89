"""The controller benchmark: tuned baselines, table lookup, ANFIS, clairvoyant bound, over many scenarios.

    tune(inputs, ...)          the controllers' free parameters on the tuning scenarios only, per criterion family
                               and stiffness (`uavdamp.benchmark.tuning`)
    run_scenario(input, ...)   every controller on one scenario, per stiffness and damper model: criteria
    gather(runs, split)        stacked over scenarios, with mean and worst over the evaluation set

All runs use the linear plant (`uavdamp.platform.linear_plant.LinearPlant`; the rigid mount too, which near its
6.7 Hz resonance is 1.2-1.7 % off Exudyn: `uavdamp.platform.plants`); a damper with dynamics enters it as a force
(`uavdamp.damping.actuation`, `uavdamp.platform.force_coupling`). Criteria (`uavdamp.benchmark.scoring`): each
response metric over the rigid mount's on the same scenario. A tunable law's J of a criterion family comes from the
run tuned for that family (`tuned_on` says on which criterion); the clairvoyant schedule is a bound only for the
objectives it optimises (displacement_std: the displacement family; los_std: the line of sight), NaN elsewhere. A law
decided every solver step runs only with the dampers of benchmark.per_step_dampers, and on the step-check scenarios it
is rerun at half the step (`step_difference`; the run fails above benchmark.step_check.tolerance, naming the law).
A run is made once per scenario and what it depends on (`runner.run_key`): a tuned law whose parameters coincide for
two families (often: the same candidate or a range's end) is scored for both from one run.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import xarray as xr
from threadpoolctl import threadpool_limits

from uavdamp.benchmark import scoring
from uavdamp.benchmark.runner import Runner, case_of, plant_params, run_key
from uavdamp.benchmark.scoring import J_CRITERIA, RESOURCES
from uavdamp.benchmark.tuning import TUNED_CONTROLLERS, merge_tuned, tune, tuned_at
from uavdamp.camera.criteria import CRITERIA, FAMILIES, PHASED, family_of
from uavdamp.camera.optics import CameraModel
from uavdamp.contract import NonFiniteDemand
from uavdamp.damping import actuation
from uavdamp.damping.clairvoyant import OBJECTIVES
from uavdamp.settings import attached, require, setting
from uavdamp.signals.tracking import TrackerOptions
from uavdamp.study import strategies

__all__ = ["BenchmarkOptions", "gather", "merge_tuned", "plant_params", "run_scenario", "tune", "tuned_at"]
BOUND_OF = {family_of(c): c for c in OBJECTIVES}  # family -> the clairvoyant's objective


@dataclass(frozen=True)
class TuningOptions:
    criteria: tuple[str, ...] = setting()  # the J minimised on average over the tuning set, one per family
    n_candidates: int = setting()  # log-spaced values per parameter before the bounded refinement
    max_refine: int = setting()  # refinement evaluations (scipy bounded Brent in log value)
    min_gain: float = setting()  # 1 (J): refine only where the parabola through the best candidates promises this
    damping_range: tuple[float, ...] = setting("damping_range_n_s_m", length=2)  # N s m-1: passive C, on-off C_max
    gain_range: tuple[float, ...] = setting("gain_range_n_s_m", length=2)  # N s m-1: skyhook/groundhook/hybrid gain
    hybrid_alpha: tuple[float, ...] = setting()  # 1, alphas tried for the hybrid
    q_scale: float = setting("q_scale_m")  # m, clipped-optimal camera weight scale (fixed: only q/r matters)
    r_scale_range: tuple[float, ...] = setting("r_scale_range_n", length=2)  # N, clipped-optimal force scale

    def validate(self) -> None:
        where = "benchmark.tuning.criteria"
        unknown = sorted(set(self.criteria) - set(J_CRITERIA))
        require(bool(self.criteria) and not unknown, where, f"unknown {unknown}: each one of {list(J_CRITERIA)}")
        families = [family_of(c) for c in self.criteria]
        require(len(set(families)) == len(families), where, f"one criterion per family {dict(FAMILIES)}")
        require(self.min_gain >= 0, "benchmark.tuning.min_gain", f"must be >= 0, got {self.min_gain}")
        for key in ("damping_range", "gain_range", "r_scale_range"):
            lo, hi = getattr(self, key)
            require(0 < lo < hi, f"benchmark.tuning.{key}", "need 0 < min < max")


@dataclass(frozen=True)
class ClairvoyantOptions:
    n_candidates: int = setting()  # log-spaced C from min_damping to the damper's c_max
    min_damping: float = setting("min_damping_n_s_m")  # N s m-1
    beam_width: int = setting()
    criterion: str = attached("displacement_std")  # the objective of one run (BOUND_OF: set per family)

    def validate(self) -> None:
        where = "benchmark.clairvoyant."
        require(self.n_candidates >= 2, where + "n_candidates", f"must be >= 2, got {self.n_candidates}")
        require(self.beam_width >= 1, where + "beam_width", f"must be >= 1, got {self.beam_width}")
        require(self.min_damping > 0, where + "min_damping_n_s_m", f"must be > 0, got {self.min_damping}")


@dataclass(frozen=True)
class StepCheck:
    """The per-step laws' convergence in the time step (``benchmark.step_check``)."""

    scenarios: tuple[str, ...] = setting()  # the sample rerun at half the step
    tolerance: float = setting()  # 1, largest |J(h) - J(h/2)| allowed

    def validate(self) -> None:
        require(self.tolerance > 0, "benchmark.step_check.tolerance", f"must be > 0, got {self.tolerance}")


@dataclass(frozen=True)
class MROptions:
    """The MR damper (``benchmark.mr``): `uavdamp.damping.actuation.MRSpec`."""

    damping_range: tuple[float, ...] = setting("damping_range_n_s_m", length=2)  # N s m-1, c_eq at 0 V and v_max
    max_substep: float = setting("max_substep_s")  # s, the Spencer model's internal sub-step

    def validate(self) -> None:
        lo, hi = self.damping_range
        require(0 < lo < hi, "benchmark.mr.damping_range_n_s_m", f"need 0 < c_off < c_on, got {[lo, hi]}")
        require(self.max_substep > 0, "benchmark.mr.max_substep_s", "must be > 0")


@dataclass(frozen=True, kw_only=True)
class BenchmarkOptions:
    """The runs' view of the config's ``benchmark`` section, with the study's tracker and the camera attached."""

    controllers: tuple[str, ...] = setting()
    stiffness: tuple[float, ...] = setting("stiffness_n_m")  # N m-1
    dampers: tuple[str, ...] = setting()  # damper models (uavdamp.damping.actuation.DAMPERS)
    per_step_dampers: tuple[str, ...] = setting()  # the dampers a law decided every solver step runs with
    damper_lag: float = setting("damper_lag_s")  # s, first-order lag of the lagged damper
    time_step: float | None = setting("time_step_s", default=None)  # s, the benchmark plant's step; None: platform's
    mr: MROptions = setting()
    frame_phases: int = setting()  # frame-clock starts over one frame period (uavdamp.benchmark.scoring)
    step_check: StepCheck = setting()
    tuning: TuningOptions = setting()
    clairvoyant: ClairvoyantOptions = setting()
    tracking: TrackerOptions | None = attached()
    camera: CameraModel | None = attached()

    def validate(self) -> None:
        w = "benchmark."
        require("rigid" in self.controllers, w + "controllers", "must hold rigid (the criteria's reference)")
        require(self.damper_lag > 0, w + "damper_lag_s", "must be > 0")
        require(
            bool(self.stiffness) and min(self.stiffness) > 0, w + "stiffness_n_m", f"must be > 0, got {self.stiffness}"
        )
        unknown = sorted(set(self.dampers) - set(actuation.DAMPERS))
        require(bool(self.dampers) and not unknown, w + "dampers", f"unknown {unknown} (known: {actuation.DAMPERS})")
        extra = sorted(set(self.per_step_dampers) - set(self.dampers))
        require(bool(self.per_step_dampers) and not extra, w + "per_step_dampers", f"{extra} not in benchmark.dampers")
        require(self.frame_phases >= 1, w + "frame_phases", f"must be >= 1, got {self.frame_phases}")
        step = self.time_step
        require(step is None or 0 < step <= 0.1, w + "time_step_s", f"must be null or in (0, 0.1] s, got {step}")


def _runs(name: str, options: BenchmarkOptions) -> list[tuple[str | None, tuple]]:
    """(tuning criterion or None, the criteria its run scores) of one controller: a tuned law once per tuning
    criterion (its family), the clairvoyant once per family it bounds, any other law once for every criterion."""
    if name not in TUNED_CONTROLLERS and name != "clairvoyant":
        return [(None, J_CRITERIA)]
    out = []
    for criterion in options.tuning.criteria:
        family = family_of(criterion)
        if name != "clairvoyant" or family in BOUND_OF:
            out.append((criterion, FAMILIES[family]))
    return out


def _tuned_on(name: str, options: BenchmarkOptions) -> list[str]:
    """Per J criterion, what its run of `name` was tuned on ("" untuned, "-" not run: NaN)."""
    found = {c: "-" for c in J_CRITERIA}
    for criterion, scored in _runs(name, options):
        label = "" if criterion is None else criterion
        if name == "clairvoyant":
            label = f"bound: {BOUND_OF[family_of(criterion)]}"
        found |= dict.fromkeys(scored, label)
    return [found[c] for c in J_CRITERIA]


def _context(runner, case, stiffness, tuned, criterion, name: str):
    """The strategy context of controller `name`'s run tuned for `criterion` (None: untuned); the clairvoyant's
    objective set by the criterion's family (the one factory that reads it)."""
    first = runner.options.tuning.criteria[0]  # an untuned law sees the first criterion's (it reads none of them)
    ctx = runner.context(case, stiffness, tuned_at(tuned, stiffness, first if criterion is None else criterion))
    if name == "clairvoyant" and criterion is not None and family_of(criterion) in BOUND_OF:
        o = runner.options
        clairvoyant = dataclasses.replace(o.clairvoyant, criterion=BOUND_OF[family_of(criterion)])
        ctx = dataclasses.replace(ctx, options=dataclasses.replace(o, clairvoyant=clairvoyant))
    return ctx


def run_scenario(
    ds: xr.Dataset, tuned: xr.Dataset, params, options: BenchmarkOptions, *, model=None, table=None, mr=None,
    step_check: bool = False,
) -> xr.Dataset:  # fmt: skip
    """Criteria of every controller on one scenario: J (controller, stiffness, criterion, damper), the frame-phase
    spread, resources (controller, stiffness, family, damper) and, with `step_check`, each per-step law's
    `step_difference` (ValueError naming a law above benchmark.step_check.tolerance)."""
    params = plant_params(params, options)
    runner, case = Runner(params, options, model, table, mr), case_of(ds)
    half = Runner(_half_step(params), options, model, table, mr) if step_check else None
    nc, nk, nd = len(options.controllers), len(options.stiffness), len(options.dampers)
    out = {
        "J": np.full((nc, nk, len(J_CRITERIA), nd), math.nan),
        "J_low": np.full((nc, nk, len(PHASED), nd), math.nan),
        "J_high": np.full((nc, nk, len(PHASED), nd), math.nan),
        "step_difference": np.full((nc, nk, nd), math.nan),
        "demand_below_range": np.full((nc, nk, nd), math.nan),
        **{name: np.full((nc, nk, len(FAMILIES), nd), math.nan) for name in RESOURCES},
    }
    scenario = ds.attrs.get("scenario", "?")
    done: dict = {}  # run_key -> ((criteria, share below range, half step's J or None), tuned read): each run once
    with threadpool_limits(1):
        rigid = scoring.response_metrics(runner.rigid.run(*case), options.camera, options.frame_phases)
        for b, stiffness in enumerate(options.stiffness):
            for a, name in enumerate(options.controllers):
                for criterion, scored in _runs(name, options):
                    ctx = _context(runner, case, stiffness, tuned, criterion, name)
                    where = f"benchmark.controllers {name!r}, scenario {scenario}, K = {stiffness:g} N m-1"
                    with _naming(where):
                        strategy = strategies.build(name, ctx)
                    for d, damper in enumerate(options.dampers):
                        if not runner.runs_with(strategy, damper):
                            continue
                        key = run_key(name, damper, ctx, strategy)
                        if key not in done or not ctx.tuned.agrees(done[key][1]):  # run_key's docstring
                            with _naming(f"{where}, damper {damper}"):
                                done[key] = (_outcome(runner, half, ctx, strategy, damper, rigid, name), ctx.tuned.read)
                        result, below, j_half = done[key][0]
                        _store(out, (a, b, d), scored, result)
                        out["demand_below_range"][a, b, d] = np.fmax(out["demand_below_range"][a, b, d], below)
                        if j_half is not None:
                            tolerance = options.step_check.tolerance
                            _check_half_step(out, (a, b, d), criterion, name, damper, stiffness, result[0], j_half,
                                             tolerance)  # fmt: skip
    return _scenario_dataset(ds, out, rigid, options)


def _outcome(runner, half, ctx, strategy, damper: str, rigid: dict, name: str) -> tuple:
    """One run's criteria (`scoring.criteria`), its share of demands below the damper's range, and, for a per-step
    law with the step check on (`half`: the runner at half the step), the half step's J (else None)."""
    options = runner.options
    response = runner.run(ctx, strategy, damper)
    result = scoring.criteria(response, rigid, options.camera, options.frame_phases)
    j_half = None
    if half is not None and actuation.is_per_step(strategy.law, runner.params.time_step):
        half_ctx = dataclasses.replace(
            half.context(ctx.case_input, ctx.stiffness, ctx.tuned.unread()), options=ctx.options
        )
        half_run = half.run(half_ctx, strategies.build(name, half_ctx), damper)
        j_half = scoring.criteria(half_run, rigid, options.camera, 1)[0]
    return result, below_range(response, damper, options), j_half


@contextlib.contextmanager
def _naming(where: str):
    """A law's non-finite demand inside re-raised naming the controller, scenario, K (and damper): `where`."""
    try:
        yield
    except NonFiniteDemand as error:
        raise NonFiniteDemand(f"{where}: {error}") from None


def below_range(response: xr.Dataset, damper: str, options: BenchmarkOptions) -> float:
    """Share (1) of the run's time steps whose damping demand lies below the damper's range: the MR damper's
    off-state c_off (benchmark.mr.damping_range_n_s_m); the ideal and lagged dampers take every demand (0). NaN
    without a damper (the rigid mount)."""
    demand = response["damping"].values if "damping" in response else np.array([math.nan])
    if not np.isfinite(demand).any():
        return math.nan
    c_off = options.mr.damping_range[0] if damper == "mr" else -math.inf
    return float(np.mean(demand[np.isfinite(demand)] < c_off * (1 - 1e-9)))


def _store(out: dict, at: tuple, scored, result) -> None:
    a, b, d = at
    j, spread, resources = result
    for c in scored:
        out["J"][a, b, J_CRITERIA.index(c), d] = j[c]
        if c in PHASED:
            out["J_low"][a, b, PHASED.index(c), d], out["J_high"][a, b, PHASED.index(c), d] = spread[c]
    for family in {family_of(c) for c in scored}:
        f = list(FAMILIES).index(family)
        for key, value in resources.items():
            out[key][a, b, f, d] = value


def _half_step(params):
    solver = dataclasses.replace(params.solver, time_step=params.time_step / 2)
    return dataclasses.replace(params, solver=solver)


def _check_half_step(out, at, criterion, name, damper, stiffness, j_step, j_half, tolerance: float) -> None:
    """|J(h) - J(h/2)| over the criteria the run scores (its family's, or all untuned), stored and checked against
    benchmark.step_check.tolerance."""
    scored = [c for c in (J_CRITERIA if criterion is None else FAMILIES[family_of(criterion)]) if c not in PHASED]
    difference = actuation.step_difference(j_step, j_half, scored)
    a, b, d = at
    out["step_difference"][a, b, d] = np.fmax(out["step_difference"][a, b, d], difference)
    where = f"{damper} damper, K = {stiffness:g} N/m" + (f", tuned on {criterion}" if criterion else "")
    actuation.check_step(difference, tolerance, name, where)


def _scenario_dataset(ds, out: dict, rigid: dict, options: BenchmarkOptions) -> xr.Dataset:
    dims, rdims = ("controller", "stiffness", "criterion", "damper"), ("controller", "stiffness", "family", "damper")
    pdims = ("controller", "stiffness", "phased", "damper")
    result = xr.Dataset(
        {
            "J": (
                dims,
                out["J"],
                {"units": "1", "long_name": "criterion relative to the rigid mount (lower is better)"},
            ),
            "J_low": (pdims, out["J_low"], {"units": "1", "long_name": "J at the frame-clock phase giving the lowest"}),
            "J_high": (
                pdims,
                out["J_high"],
                {"units": "1", "long_name": "J at the frame-clock phase giving the highest"},
            ),
            "step_difference": (
                ("controller", "stiffness", "damper"),
                out["step_difference"],
                {"units": "1", "long_name": "largest |J(step) - J(half step)| of a per-step law (NaN: not checked)"},
            ),
            "demand_below_range": (
                ("controller", "stiffness", "damper"),
                out["demand_below_range"],
                {
                    "units": "1",
                    "long_name": "share of the time steps whose demand lies below the damper's range (MR: c_off; "
                    "largest over the controller's runs; NaN: no damper)",
                },
            ),
            **{k: (rdims, out[k], {"units": RESOURCES[k][0], "long_name": RESOURCES[k][1]}) for k in RESOURCES},
            "rigid_value": (
                "criterion",
                [rigid[c] for c in J_CRITERIA],
                {"units": "1", "long_name": "the rigid mount's metric (in criterion_units)"},
            ),
        },
        coords=_coords(options),
    )
    result = result.expand_dims(scenario=[ds.attrs.get("scenario", "scenario")])
    return result.assign_coords(scenario=result.scenario.assign_attrs(units="1", long_name="scenario"))


def _coords(options: BenchmarkOptions) -> dict:
    def names(dim, values, long_name):
        return (dim, list(values), {"units": "1", "long_name": long_name})

    return {
        "controller": names("controller", options.controllers, "controller"),
        "stiffness": ("stiffness", list(options.stiffness), {"units": "N m-1", "long_name": "isolator K"}),
        "criterion": names("criterion", J_CRITERIA, "criterion"),
        "criterion_units": names(
            "criterion", [CRITERIA[c].units for c in J_CRITERIA], "units of the rigid mount's metric"
        ),
        "family": names("family", FAMILIES, "criterion family (a tuned law's runs: one per family)"),
        "phased": names("phased", PHASED, "criteria that depend on the frame clock's phase"),
        "damper": names("damper", options.dampers, "damper model (uavdamp.damping.actuation)"),
        "tuned_on": (
            ("controller", "criterion"),
            [_tuned_on(c, options) for c in options.controllers],
            {"units": "1", "long_name": "what the run behind J was tuned on ('' untuned, '-' not run)"},
        ),
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
    evaluation = ds.where(ds.set == "evaluation", drop=True)
    for name, over in (
        ("J", "J"),
        ("J_low", "J at its lowest frame phase"),
        ("J_high", "J at its highest frame phase"),
    ):
        ds[f"{name}_mean"] = (
            evaluation[name].mean("scenario").assign_attrs(units="1", long_name=f"mean {over} over the evaluation set")
        )
    ds["J_worst"] = evaluation.J.max("scenario").assign_attrs(units="1", long_name="worst J over the evaluation set")
    if "demand_below_range" in ds:
        ds["demand_below_range_mean"] = evaluation.demand_below_range.mean("scenario").assign_attrs(
            units="1", long_name="mean share of demands below the damper's range over the evaluation set"
        )
    ds["step_difference_max"] = ds.step_difference.max("scenario").assign_attrs(
        units="1", long_name="largest |J(step) - J(half step)| over the step-check scenarios (NaN: not checked)"
    )
    tuned = tuned.rename({k: f"tuned_{k}" for k in tuned.data_vars})
    return ds.merge(tuned, combine_attrs="override")
