"""The isolator's stroke budget: what gravity and manoeuvres take of the stroke before the vibration does.

The plants run about the static equilibrium (`uavdamp.platform.model`), so their `isolator_stroke` is the dynamic
stroke alone. On top of it, each way from the unloaded length (``platform.stroke``):

    static sag        m g / K along z when the spring carries the weight (weight_support: spring); 0 when a
                      preload (an air spring, a constant-force spring) carries it (weight_support: preloaded)
    manoeuvre stroke  m n g / K on y and on z: a quasi-static load factor n (manoeuvre_g) in any direction

with m the mass the isolator carries (`supported_mass`). A run is feasible when, on both axes, static sag +
manoeuvre stroke + its peak dynamic stroke <= max_stroke_m. At the paper's K = 10 N/m the 1.6 kg platform would
sag 1.57 m: the reason the sag is reported (and a run with it flagged), not silently carried by a preload.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from uavdamp.platform.linear_plant import OUTPUTS
from uavdamp.platform.params import PlatformParams, StrokeBudget


def supported_mass(params: PlatformParams) -> float:
    """Mass the isolator carries, kg: the whole platform (base, intermediate and pitch bodies, camera)."""
    return params.structure.total_mass


def static_sag(budget: StrokeBudget, params: PlatformParams, stiffness) -> np.ndarray:
    """Static deflection of the isolator under the platform's weight, m (0 when preloaded), per stiffness N m-1."""
    k = np.asarray(stiffness, dtype=float)
    if budget.weight_support == "preloaded":
        return np.zeros_like(k)
    return supported_mass(params) * params.gravity / k


def manoeuvre_stroke(budget: StrokeBudget, params: PlatformParams, stiffness) -> np.ndarray:
    """Quasi-static deflection under the manoeuvre load factor n, m n g / K (m), per stiffness N m-1."""
    k = np.asarray(stiffness, dtype=float)
    return supported_mass(params) * budget.manoeuvre_g * params.gravity / k


def stroke_budget(
    budget: StrokeBudget, params: PlatformParams, stiffness: xr.DataArray, peak_stroke: xr.DataArray
) -> xr.Dataset:
    """`static_sag`, `manoeuvre_stroke` (per stiffness), `stroke_needed` (peak_stroke's dims, m) and
    `stroke_feasible` (1 where every axis fits in max_stroke_m, 0 where not, NaN without an isolator).

    `peak_stroke` is the largest |dynamic stroke| of each run over ``axis`` (y, z), NaN for the rigid mount."""
    sag = xr.DataArray(static_sag(budget, params, stiffness.values), coords={"stiffness": stiffness})
    manoeuvre = xr.DataArray(manoeuvre_stroke(budget, params, stiffness.values), coords={"stiffness": stiffness})
    sag_on_axis = sag * xr.DataArray([0.0, 1.0], coords={"axis": ["y", "z"]})  # the weight acts along z
    needed = (sag_on_axis + manoeuvre + peak_stroke).transpose(*peak_stroke.dims)
    fits = (needed <= budget.max_stroke).all("axis").astype(float)
    feasible = fits.where(peak_stroke.notnull().all("axis"))
    limit = f"max_stroke_m = {budget.max_stroke} m"
    return xr.Dataset(
        {
            "static_sag": sag.assign_attrs(
                units="m", long_name=f"static sag of the isolator ({budget.weight_support})"
            ),
            "manoeuvre_stroke": manoeuvre.assign_attrs(
                units="m", long_name=f"stroke under a {budget.manoeuvre_g} g quasi-static manoeuvre"
            ),
            "stroke_needed": needed.assign_attrs(units="m", long_name="static sag + manoeuvre + peak dynamic stroke"),
            "stroke_feasible": feasible.assign_attrs(units="1", long_name=f"1: the stroke fits in {limit}"),
        }
    )


def steady_stroke(plant, stiffness: float, damping: float, freq_y_hz: float, freq_z_hz: float, amplitude: float):
    """Steady-state stroke amplitude bound (y, z), m, of the linear plant (`LinearPlant`) at (K, C) under the
    table's inputs y = A sin(2 pi f_y t), z = A sin(2 pi f_z t): on each stroke axis the sum of the amplitudes the
    two inputs drive (|H(j w)| A from the frequency response, exact for the linear plant; transients not counted)."""

    ss = plant.model.state_space(stiffness, damping)
    rows = [OUTPUTS.index("stroke_y"), OUTPUTS.index("stroke_z")]
    m = ss.du.shape[1]
    amplitudes = np.zeros(2)
    for column, freq in ((1, freq_y_hz), (2, freq_z_hz)):  # mount inputs: x, y, z translation, then rotations
        w = 2 * np.pi * freq
        drive = ss.b[:, column] + 1j * w * ss.b[:, m + column]
        state = np.linalg.solve(1j * w * np.eye(ss.n_states) - ss.a, drive)
        out = ss.c[rows] @ state + ss.du[rows, column] + 1j * w * ss.dv[rows, column]
        amplitudes += np.abs(out) * amplitude
    return amplitudes


def table_stroke_budget(budget: StrokeBudget, plant, table: xr.Dataset, amplitude: float) -> xr.Dataset:
    """The stroke budget of the reference table's optimum: `stroke_needed` (freq_y, freq_z, stiffness, axis) at
    `damping_opt` with the steady-state stroke (`steady_stroke`) and `stroke_feasible` (freq_y, freq_z, stiffness);
    `table` is one criterion and window of the table (`criteria.select_table`)."""
    opt = table.damping_opt.transpose("freq_y", "freq_z", "stiffness")
    peak = np.zeros((*opt.shape, 2))
    for i, fy in enumerate(opt.freq_y.values):
        for j, fz in enumerate(opt.freq_z.values):
            for k, stiffness in enumerate(opt.stiffness.values):
                c = float(opt.values[i, j, k])
                if np.isfinite(c):
                    peak[i, j, k] = steady_stroke(plant, float(stiffness), c, float(fy), float(fz), amplitude)
                else:
                    peak[i, j, k] = np.nan
    axis = xr.DataArray(["y", "z"], dims="axis", attrs={"units": "1", "long_name": "isolator axis (y lateral, z up)"})
    peak = xr.DataArray(peak, coords={**{d: opt[d] for d in opt.dims}, "axis": axis}, dims=(*opt.dims, "axis"))
    out = stroke_budget(budget, plant.params, opt.stiffness, peak)
    out["peak_stroke"] = peak.assign_attrs(units="m", long_name="steady-state stroke amplitude bound at damping_opt")
    return out
