"""How a law's demand becomes the isolator's force in the benchmark: the damper models, and the step check.

    ideal    the demand, clipped, is the damping C at once (`uavdamp.contract.clip`)
    lagged   a first-order lag of C, time constant benchmark.damper_lag_s (`Lag`), its force an input of the
             linear plant like the MR damper's, for every law
    mr       the Spencer et al. (1997) MR damper (`uavdamp.damping.dampers`) commanded by the voltage whose equivalent
             damping at the reference stroke is the clipped demand (`voltage_for_damping`), its force an input of
             the linear plant (`uavdamp.platform.force_coupling`)

The MR damper is the published one scaled to the platform (`SpencerParams.for_platform`) so that it spans
benchmark.mr.damping_range_n_s_m at the reference stroke (an MR damper cannot reach C = 0: its off-state ratio
c_eq(v_max) / c_eq(0) is at most about 6); `mr_dataset` / `MRSpec.from_dataset` carry it between jobs (building it
costs about 40 loop simulations).

Step check (`step_difference`): a law decided every solver step may depend on the step itself (Karnopp's on-off
skyhook with an ideal damper chatters at the step's rate: camera std 0.87, 0.67, 0.49 mm at 2, 1, 0.5 ms). The
benchmark reruns such a law at half the step on a sample of scenarios and stores the largest change of J;
`check_step` raises naming the law above the configured tolerance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from uavdamp.damping.dampers import REFERENCE_VELOCITY, SpencerMR, SpencerParams, damping_table

DAMPERS = ("ideal", "lagged", "mr")
_SPENCER_UNITS = {
    "c0a": "N s m-1",
    "c0b": "N s m-1 V-1",
    "k0": "N m-1",
    "c1a": "N s m-1",
    "c1b": "N s m-1 V-1",
    "k1": "N m-1",
    "x0": "m",
    "alpha_a": "N m-1",
    "alpha_b": "N m-1 V-1",
    "gamma": "m-2",
    "beta": "m-2",
    "A": "1",
    "n": "1",
    "eta": "s-1",
}


@dataclass(frozen=True)
class MRSpec:
    """The benchmark's MR damper: Spencer parameters and its command table (voltages V, equivalent damping N s m-1
    at the reference stroke), and the damper's internal sub-step (s)."""

    params: SpencerParams
    volts: np.ndarray
    damping: np.ndarray
    max_substep: float

    @classmethod
    def build(cls, c_range, max_substep: float) -> MRSpec:
        """The platform-scaled damper spanning c_range = (c_off, c_on) N s m-1 (slow: see the module docstring)."""
        params = SpencerParams.for_platform(*c_range)
        volts, damping = damping_table(params, REFERENCE_VELOCITY)
        return cls(params, np.asarray(volts), np.asarray(damping), float(max_substep))

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> MRSpec:
        params = SpencerParams(**{k: float(ds[f"spencer_{k}"]) for k in _SPENCER_UNITS})
        return cls(params, ds.voltage.values, ds.equivalent_damping.values, float(ds.attrs["max_substep_s"]))

    def voltage(self, damping: float) -> float:
        """The command voltage for a demand (N s m-1): the table inverted linearly, clamped to its ends."""
        return float(np.interp(damping, self.damping, self.volts))

    def voltages(self, damping) -> np.ndarray:
        """`voltage` of each demand of an array (N s m-1), V."""
        return np.interp(np.asarray(damping, dtype=float), self.damping, self.volts)


def mr_dataset(spec: MRSpec) -> xr.Dataset:
    """The MR damper as a dataset: Spencer parameters (scalars) and the command table over voltage."""
    data = {
        f"spencer_{k}": ((), getattr(spec.params, k), {"units": u, "long_name": f"Spencer model parameter {k}"})
        for k, u in _SPENCER_UNITS.items()
    }
    data["equivalent_damping"] = (
        "voltage",
        spec.damping,
        {"units": "N s m-1", "long_name": "equivalent viscous damping at the reference stroke"},
    )
    coords = {"voltage": ("voltage", spec.volts, {"units": "V", "long_name": "command voltage"})}
    return xr.Dataset(data, coords=coords, attrs={"max_substep_s": spec.max_substep})


class MRDamper:
    """`uavdamp.platform.force_coupling.ForceDamper` of an `MRSpec`: one Spencer damper per axis, one voltage."""

    name = "mr"

    def __init__(self, spec: MRSpec):
        self.spec = spec
        self.damper = SpencerMR(spec.params, n_axes=2, max_substep=spec.max_substep)
        self.volts = 0.0

    def reset(self, stroke) -> None:
        self.damper.reset(np.asarray(stroke, float))
        self.volts = 0.0

    def command(self, damping: float) -> None:
        self.volts = self.spec.voltage(damping)

    def force(self, x, xd) -> np.ndarray:
        return self.damper.force(np.asarray(x, float), np.asarray(xd, float))

    def step(self, h, x0, xd0, x1, xd1) -> np.ndarray:
        self.damper.step(h, self.volts, x0, xd0, x1, xd1)
        return self.damper.force_mean.copy()

    def couple(self, h, x0, xd0, free_end, g_rows) -> np.ndarray:
        """`ForceDamper.couple`: the predictor-corrector step compiled (`SpencerMR.coupled_step`); the step's mean."""
        self.damper.coupled_step(h, self.volts, (x0, xd0), free_end, g_rows)
        return self.damper.force_mean.copy()

    def save(self):
        d = self.damper
        return d.y.copy(), d.z.copy(), d.u.copy()

    def restore(self, state) -> None:
        self.damper.y, self.damper.z, self.damper.u = (s.copy() for s in state)


def is_per_step(law, time_step: float) -> bool:
    """True for a law decided every solver step (its update period is the step)."""
    period = getattr(law, "update_period", None)
    return period is not None and math.isclose(float(period), time_step, rel_tol=1e-9)


def step_difference(j_step: dict, j_half: dict, criteria) -> float:
    """The largest |J(step) - J(half step)| over `criteria` (J is relative to the rigid mount: 0.01 is 1 % of
    its motion); NaN criteria are skipped."""
    diffs = [abs(j_step[c] - j_half[c]) for c in criteria if math.isfinite(j_step[c]) and math.isfinite(j_half[c])]
    return max(diffs) if diffs else math.nan


def check_step(difference: float, tolerance: float, law: str, where: str) -> None:
    """ValueError naming the law unless its J moved by at most `tolerance` at half the time step."""
    if math.isfinite(difference) and difference > tolerance:
        raise ValueError(
            f"benchmark.step_check: {law!r} ({where}) is not converged in the time step: J changes by "
            f"{difference:.3g} at half the step (tolerance benchmark.step_check.tolerance = {tolerance:g}); "
            "run it with a damper that has dynamics (benchmark.per_step_dampers) or a smaller step"
        )


class Lag:
    """`ForceDamper` of the lagged damper: C' = (C_cmd - C) / tau, F_d = C x'; starts settled at the first command.

    Over a step C follows the held command exactly, C_1 = C_cmd + (C_0 - C_cmd) exp(-h / tau); the step's mean force
    is the mean of C over the step times the stroke's mean rate (x_1 - x_0) / h."""

    name = "lagged"

    def __init__(self, tau: float):
        if not (math.isfinite(tau) and tau > 0):
            raise ValueError(f"damper_lag_s: must be > 0, got {tau}")
        self.tau = float(tau)
        self._h = None  # the step length the decay and mean weight below were computed for (`rate_gain`)

    def reset(self, stroke) -> None:
        self.c, self.cmd = math.nan, math.nan

    def command(self, damping: float) -> None:
        self.cmd = float(damping)
        if math.isnan(self.c):
            self.c = self.cmd

    def force(self, x, xd) -> np.ndarray:
        return self.c * np.asarray(xd, float)

    def step(self, h, x0, xd0, x1, xd1) -> np.ndarray:
        return self.rate_gain(h) * (np.asarray(x1, float) - np.asarray(x0, float))

    def rate_gain(self, h: float) -> float:
        """k = mean C / h, N m-1 (the step's mean force is k (x_1 - x_0)); C advanced over the step."""
        if h != self._h:  # the step's decay and mean weight, once per step length
            self._h, decay = h, math.exp(-h / self.tau)
            self._decay, self._mean = decay, self.tau / h * (1.0 - decay)
        gap = self.c - self.cmd
        mean_c = self.cmd + gap * self._mean
        self.c = self.cmd + gap * self._decay
        return mean_c / h

    def save(self):
        return self.c

    def restore(self, state) -> None:
        self.c = state
