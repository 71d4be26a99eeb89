"""The benchmark's runner: the plants of one platform and how a law runs on them under a damper model.

    case_of(ds)                    (time s, MountMotion) of a scenario's input dataset
    Runner(params, options, ...)   the isolated and rigid linear plants: `context` for a scenario and K, `run` of a
                                   strategy under a damper (ideal, lagged, MR: `uavdamp.damping.actuation`)
    run_key(name, damper, ctx, s)  what a run depends on in one scenario, so that a repeated run is run once
    plant_params(params, options)  the platform parameters at the benchmark's solver step

Used by the per-criterion tuning (`uavdamp.benchmark.tuning`) and the loop over scenarios (`uavdamp.benchmark.loop`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import xarray as xr

from uavdamp.contract import MountMotion
from uavdamp.damping import actuation
from uavdamp.platform import force_coupling
from uavdamp.platform.linear_plant import LinearPlant
from uavdamp.study import strategies


def case_of(ds: xr.Dataset) -> tuple:
    """(time s, MountMotion) of a scenario's input dataset."""
    return ds.time.values, MountMotion(ds.mount_displacement.values, ds.mount_rotation.values)


class ReadTuned(Mapping):
    """Tuned parameters {name: value} that record which of them a strategy factory reads (looked up, tested with
    `in`, or all of them where it iterates): with the controller, damper and K, what its run depends on."""

    def __init__(self, values: dict):
        self._values, self.read = dict(values), {}

    def __getitem__(self, key):
        value = self._values[key]
        self.read[key] = value
        return value

    def get(self, key, default=None):
        self.read[key] = self._values.get(key, _ABSENT)
        return self._values.get(key, default)

    def __contains__(self, key) -> bool:
        self.read[key] = self._values.get(key, _ABSENT)
        return key in self._values

    def __iter__(self):
        self.read.update(self._values)
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def unread(self) -> dict:
        """The parameters as a plain dict (taking it records nothing)."""
        return dict(self._values)

    def agrees(self, read: dict) -> bool:
        """True if every parameter of `read` (another run's `read`) has the same value here (or is absent in both)."""
        return all(self._values.get(k, _ABSENT) == v for k, v in read.items())


_ABSENT = "(absent)"  # what `ReadTuned.read` holds for a parameter asked for and not found


def run_key(name: str, damper: str, ctx: strategies.Context, strategy: strategies.Strategy) -> tuple:
    """What a run of controller `name` (`strategy`, built on `ctx`, a `Runner.context`) depends on in one scenario:
    the damper, K, the tuned parameters its factory read and the clairvoyant's objective; on the rigid mount, nothing
    (no damper, no K). A tuned law often gets the same parameters for two criterion families (a range's end, or the
    same candidate): the two are one run. A law that reads `Context.tuned` while it runs (after the key was made)
    is caught by `ReadTuned.agrees` on the run's full record (`uavdamp.benchmark.loop.run_scenario`)."""
    if strategy.mount == "rigid":
        return (name, "rigid mount")
    read = tuple(sorted(ctx.tuned.read.items()))
    return name, damper, ctx.stiffness, read, ctx.options.clairvoyant.criterion


class Runner:
    """The plants of one platform (isolated and rigid linear plants) and the damper models of the benchmark."""

    def __init__(self, params, options, model=None, table=None, mr=None):
        self.params, self.options, self.model, self.table, self.mr = params, options, model, table, mr
        self.isolated = LinearPlant.from_params(params)
        self.rigid = LinearPlant.from_params(params, mount="rigid")

    def context(self, case: tuple, stiffness: float, tuned: dict) -> strategies.Context:
        """The strategy context for a scenario `case` and K, its tuned parameters a `ReadTuned` (`run_key`)."""

        def run(strategy, law=None):  # a trial run (searches): the ideal damper
            plant = self.rigid if strategy.mount == "rigid" else self.isolated
            return plant.run(*case, stiffness=stiffness, law=strategy.law if law is None else law)

        return strategies.Context(
            self.options,
            self.params,
            self.model,
            float(stiffness),
            run,
            tuned=ReadTuned(tuned),
            table=self.table,
            case_input=case,
            linear=self.isolated,
        )

    def runs_with(self, strategy, damper: str) -> bool:
        """False where the benchmark does not run this law with this damper: a per-step law outside
        benchmark.per_step_dampers (its J is NaN there)."""
        if strategy.law is None or not actuation.is_per_step(strategy.law, self.params.time_step):
            return True
        return damper in self.options.per_step_dampers

    def tuning_damper(self, strategy) -> str:
        """The damper a law is tuned with (module docstring)."""
        per_step = strategy.law is not None and actuation.is_per_step(strategy.law, self.params.time_step)
        return self.options.per_step_dampers[0] if per_step else "ideal"

    def run(self, ctx: strategies.Context, strategy, damper: str) -> xr.Dataset:
        """One run of `strategy` in the context's scenario and K with the named damper (`uavdamp.damping.actuation`)."""
        if strategy.mount == "rigid":
            return self.rigid.run(*ctx.case_input, stiffness=ctx.stiffness)
        law, per_step = strategy.law, actuation.is_per_step(strategy.law, self.params.time_step)
        if damper == "ideal" and not per_step:
            return self.isolated.run(*ctx.case_input, stiffness=ctx.stiffness, law=law)
        return force_coupling.run(
            self.isolated, *ctx.case_input, stiffness=ctx.stiffness, law=law, damper=self.force_damper(damper)
        )

    def force_damper(self, damper: str):
        if damper == "ideal":
            return force_coupling.Viscous()
        if damper == "lagged":
            return actuation.Lag(self.options.damper_lag)
        if damper == "mr":
            if self.mr is None:
                raise ValueError("the mr damper needs its MRSpec (benchmark/mr_damper.nc)")
            return actuation.MRDamper(self.mr)
        raise ValueError(f"benchmark.dampers: unknown {damper!r} (known: {list(actuation.DAMPERS)})")


def plant_params(params, options):
    """The platform parameters the benchmark's plants step with: the solver step benchmark.time_step_s where set
    (a law decided every step is decided at this rate), else the platform's."""
    if options.time_step is None:
        return params
    return dataclasses.replace(params, solver=dataclasses.replace(params.solver, time_step=options.time_step))
