"""The paper's ANFIS on the payload: [f_a, f_b, K] -> C learnt from the payload table
(`uavdamp.study.payload_table`), and the law that asks it for C every update period.

The reference (the paper's reference table, built from the payload table in closed form): for each pair of
frequencies (f_a of a line on the mount's DOF a, f_b of one on DOF b: ``payload.anfis.dofs`` and ``freq_hz``) and
each element stiffness K of the payload table, the table's damping that minimises the predicted line of sight of
the two lines at the table's input amplitudes, sqrt(criterion_a(f_a, K, C)^2 + criterion_b(f_b, K, C)^2): the
scheduled law's model (`uavdamp.study.payload_schedule.predicted`: the table interpolated linearly in log
frequency, lines of different frequencies adding in power), among the dampings at which the isolator settles
(``payload.schedule.max_decay_time_s``, as that law). The ANFIS learns it with the ``anfis`` section's options
(structure by cross-validation, epochs, the 80/20 split, baselines: `uavdamp.anfis.training.train` on `reference`'s
table and grid, inputs ``AnfisPayloadSection.inputs``); its regret is the predicted criterion at its C over the best.

The law (``anfis`` beside ``scheduled`` in the payload comparison): at every update of the scheduled law's timing
(``payload.schedule``), the dominant lines of the two DOFs (`payload_schedule.dominant_lines`), the ANFIS's C at
the isolator's z stiffness, clamped to the eligible dampings' range; before both DOFs have a line (or on an input
without one, such as a stated source, which carries no rotation), ``initial_damping_n_s_m``, as the scheduled law
without lines.
Unlike the scheduled law it reads two DOFs' frequencies only, not their amplitudes (the paper's inputs).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import xarray as xr

from uavdamp.platform.six_axis import DOFS
from uavdamp.reference_table.params import Axis
from uavdamp.settings import require, setting
from uavdamp.study.payload_schedule import Table

if TYPE_CHECKING:  # scikit-learn is imported by a fit or a law only, not by the config layer (uavdamp.anfis)
    from uavdamp.anfis.damping import DampingModel
    from uavdamp.anfis.predictor import DampingPredictor


@dataclass(frozen=True)
class AnfisPayloadSection:
    """The payload ANFIS's inputs (``payload.anfis``)."""

    # the mount DOFs whose dominant frequencies the ANFIS reads (choice: the paper's two translations, which every
    # input has; x and pitch leave the stated sources, which carry no rotation, at the initial C:
    # docs/stages/payload.md)
    dofs: tuple[str, ...] = setting(default=("x", "y"))
    freq: Axis = setting("freq_hz", default=Axis(start=2.0, stop=120.0, num=33, spacing="log"))  # Hz, per DOF

    def validate(self, where: str) -> None:
        ok = len(self.dofs) == 2 == len(set(self.dofs)) and set(self.dofs) <= set(DOFS)
        require(ok, f"{where}.dofs", f"must be two distinct mount DOFs of {list(DOFS)}, got {list(self.dofs)}")
        self.freq.validate(f"{where}.freq_hz")

    def check(self, table_freq: np.ndarray, where: str = "payload.anfis") -> None:
        """ConfigError naming ``freq_hz`` when a frequency lies outside the payload table's `table_freq` Hz."""
        f = self.freq.array()
        ok = table_freq[0] * (1 - 1e-9) <= f[0] and f[-1] <= table_freq[-1] * (1 + 1e-9)
        span = f"[{table_freq[0]:g}, {table_freq[-1]:g}] Hz"
        require(ok, f"{where}.freq_hz", f"must lie within payload.table.freq_hz's {span}, got {f[0]:g}-{f[-1]:g} Hz")

    @property
    def inputs(self) -> tuple[str, str, str]:
        """The reference's dimensions: freq_A, freq_B, stiffness."""
        return (f"freq_{self.dofs[0]}", f"freq_{self.dofs[1]}", "stiffness")


def _at(freq: np.ndarray, table: Table, dof: str) -> np.ndarray:
    """(nf, nc) the table's criterion of `dof` at frequencies `freq` Hz, linear in log frequency."""
    rows = table.criterion[DOFS.index(dof)]
    log_f, log_t = np.log(freq), np.log(table.freq)
    return np.column_stack([np.interp(log_f, log_t, rows[:, c]) for c in range(table.damping.size)])


def reference(payload_table: xr.Dataset, section: AnfisPayloadSection, max_decay_time: float):
    """(table, grid): ``damping_opt`` and ``criterion_opt`` over `section.inputs`, and the predicted ``criterion``
    (rad) over them and the payload table's damping (NaN where the isolator does not settle within
    max_decay_time s), in the shape `uavdamp.anfis.training.train` reads. ValueError naming payload.anfis.dofs
    when neither DOF reaches the line of sight."""
    a, b = section.dofs
    f, ks, damping = section.freq.array(), payload_table.stiffness.values, payload_table.damping.values
    crit = np.full((f.size, f.size, ks.size, damping.size), math.nan)
    for k, stiffness in enumerate(ks):
        at_k = Table.of(payload_table, float(stiffness), max_decay_time)
        columns = np.flatnonzero(np.isin(damping, at_k.damping))
        ca, cb = _at(f, at_k, a), _at(f, at_k, b)
        crit[:, :, k][..., columns] = np.sqrt(ca[:, None, :] ** 2 + cb[None, :, :] ** 2)
    if not np.nanmax(crit) > 0:
        raise ValueError(f"payload.anfis.dofs: neither {a} nor {b} reaches the gimbal's line of sight in the table")
    names = section.inputs
    coords = {
        names[0]: (names[0], f, {"units": "Hz", "long_name": f"frequency of the mount's {a} line"}),
        names[1]: (names[1], f, {"units": "Hz", "long_name": f"frequency of the mount's {b} line"}),
        "stiffness": ("stiffness", ks, {**payload_table.stiffness.attrs}),
        "damping": ("damping", damping, {**payload_table.damping.attrs}),
    }
    what = f"predicted line of sight of an {a} and a {b} line at the table's amplitudes"
    grid = xr.Dataset({"criterion": ((*names, "damping"), crit, {"units": "rad", "long_name": what})}, coords)
    best = np.nanargmin(crit, axis=-1)
    table = xr.Dataset(
        {
            "damping_opt": (names, damping[best], {"units": "N s m-1", "long_name": f"C of the least {what}"}),
            "criterion_opt": (names, np.nanmin(crit, axis=-1), {"units": "rad", "long_name": f"least {what}"}),
        },
        {k: v for k, v in coords.items() if k != "damping"},
    )
    return table, grid


def edge_shares(table: xr.Dataset, grid: xr.Dataset) -> dict[str, float]:
    """The shares of the reference's cells whose best C is the least or the largest damping eligible at its K
    (the dampings of `grid` with a criterion): there the reference is only a bound, which the ANFIS learns as a
    value."""
    eligible = np.isfinite(grid.criterion.values).any(axis=(0, 1))  # (stiffness, damping)
    c = grid.damping.values
    low = np.array([c[row].min() for row in eligible])
    high = np.array([c[row].max() for row in eligible])
    best = table.damping_opt.transpose(*grid.criterion.dims[:3]).values
    return {
        "share_at_least_eligible_damping": float(np.mean(best == low)),
        "share_at_largest_eligible_damping": float(np.mean(best == high)),
    }


def record_attrs(section: AnfisPayloadSection, table: xr.Dataset, grid: xr.Dataset) -> dict:
    """The training record's attributes beside `uavdamp.anfis.training.train`'s on `reference`'s (table, grid):
    the DOFs and `edge_shares`."""
    return {"dofs": " ".join(section.dofs), **edge_shares(table, grid)}


@dataclass(frozen=True)
class AnfisLaw:
    """The ANFIS as the payload's law: C (N s m-1) from the dominant lines (6, 2) of `payload_schedule`."""

    model: DampingModel | DampingPredictor  # anything with predict([[f_y Hz, f_z Hz, K N/m]]) -> C N s m-1
    dofs: tuple[str, str]
    stiffness: float  # N m-1, the isolator's element z stiffness
    low: float  # N s m-1, the eligible dampings' range
    high: float

    @classmethod
    def of(cls, model: DampingModel | DampingPredictor, dofs, stiffness: float, table: Table) -> AnfisLaw:
        """At element stiffness `stiffness`, clamped to `table`'s (the payload table there) dampings."""
        return cls(model, tuple(dofs), float(stiffness), float(table.damping.min()), float(table.damping.max()))

    def __call__(self, lines: np.ndarray, fallback: float) -> float:
        """The ANFIS's C for both DOFs' line frequencies; `fallback` when either has none."""
        f = [float(lines[DOFS.index(d), 0]) for d in self.dofs]
        if not all(math.isfinite(v) for v in f):
            return float(fallback)
        return float(np.clip(self.model.predict([[*f, self.stiffness]])[0], self.low, self.high))
