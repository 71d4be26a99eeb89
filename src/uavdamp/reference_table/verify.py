"""The grid checked against the Exudyn plant: its corners and a seeded sample rerun with the other plant.

`verify` reruns `n_points` points (the grid's corners first) with the Exudyn plant where the grid is the linear
plant's (and the reverse), and `check_verification` fails, naming the worst point, criterion and window, above
the relative tolerance of that criterion.
"""

from __future__ import annotations

import json
from functools import partial

import numpy as np
import xarray as xr
from threadpoolctl import threadpool_limits

from uavdamp.camera.criteria import PIXEL_COMMENT
from uavdamp.contract import SolverFailed
from uavdamp.platform import PlatformParams
from uavdamp.reference_table import chunks
from uavdamp.reference_table import criteria as crit
from uavdamp.reference_table.grid import DIMS, POINT_LABEL, GridSpec
from uavdamp.reference_table.params import VerifyOptions
from uavdamp.reference_table.sine_batch import sine_criteria


class VerificationFailed(RuntimeError):
    """The grid's plant and the Exudyn plant disagree beyond the tolerance at some verification point."""


def verification_points(spec: GridSpec, n_points: int, seed: int) -> np.ndarray:
    """Flat indices: the grid's corners (all of them), then seeded random other points up to n_points."""
    ends = [np.unique([0, n - 1]) for n in spec.shape]
    corners = np.ravel_multi_index(tuple(g.ravel() for g in np.meshgrid(*ends, indexing="ij")), spec.shape)
    if n_points < corners.size:
        raise ValueError(
            f"reference_table.verify.n_points: must be >= the grid's {corners.size} corners, got {n_points}"
        )
    others = np.setdiff1d(np.arange(spec.size), corners)
    rng = np.random.default_rng(seed)
    extra = rng.choice(others, size=min(n_points - corners.size, others.size), replace=False)
    return np.concatenate([corners, np.sort(extra)]).astype(int)


def evaluate_points(platform: PlatformParams, spec: GridSpec, indices: np.ndarray, backend: str) -> np.ndarray:
    """Criteria (points, criteria, windows) of single points with one plant (NaN where the Exudyn solver fails)."""
    plant, _ = chunks.plant_for(platform, backend)
    values = np.full((len(indices), *spec.n_values), np.nan)
    with threadpool_limits(limits=1):
        for k, index in enumerate(indices):
            fy, fz, stiffness, damping = spec.point(int(index))
            if backend == "linear":
                one = sine_criteria(
                    plant, stiffness, damping, [fy], [fz], spec.amplitude, spec.duration, spec.windows, spec.camera
                )
                values[k] = [one[name][:, 0, 0] for name in spec.criteria]
                continue
            try:
                values[k] = chunks.evaluate(plant, spec, (fy, fz, stiffness, damping))
            except (SolverFailed, FloatingPointError):
                pass
    return values


def grid_values(spec: GridSpec, full: xr.Dataset) -> np.ndarray:
    """The grid's criteria as (points in flat order, criteria, windows)."""
    return np.stack(
        [full[crit.variable(n)].transpose(*DIMS, "window").values.reshape(spec.size, -1) for n in spec.criteria], axis=1
    )


def verify(
    platform: PlatformParams, spec: GridSpec, full: xr.Dataset, check: VerifyOptions, n_jobs: int = 1
) -> xr.Dataset:
    """Rerun `check.n_points` points with the Exudyn plant (and the linear one where the grid is Exudyn's).

    Returns `verify_point` (verify), `verify_<criterion>_linear` and `_exudyn` (verify, window) per criterion,
    `verify_relative_difference` (verify, criterion, window) and the scalar `verify_max_relative_difference`
    (inf where an Exudyn run failed).
    """
    backend = platform.backend
    points = verification_points(spec, check.n_points, check.seed)
    on_grid = grid_values(spec, full)[points]
    batches = [b for b in np.array_split(points, max(1, min(points.size, 2 * n_jobs))) if b.size]
    other = "exudyn" if backend == "linear" else "linear"
    rerun = np.concatenate(
        chunks.fan_out(partial(evaluate_points, platform, spec, backend=other), batches, n_jobs, False)
    )
    linear, exudyn = (on_grid, rerun) if backend == "linear" else (rerun, on_grid)
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = np.abs(linear - exudyn) / np.abs(exudyn)
    relative = np.where(np.isfinite(relative), relative, np.inf)
    data = {
        "verify_point": ("verify", points, {"units": "1", "long_name": POINT_LABEL}),
        "verify_relative_difference": (
            ("verify", "criterion", "window"),
            relative,
            {"units": "1", "long_name": "|linear - Exudyn| / Exudyn"},
        ),
        "verify_max_relative_difference": (
            (),
            float(relative.max()),
            {"units": "1", "long_name": "largest relative criterion difference, linear vs Exudyn plant"},
        ),
    }
    for j, name in enumerate(spec.criteria):
        for plant, values in (("linear", linear), ("exudyn", exudyn)):
            data[f"verify_{name}_{plant}"] = (
                ("verify", "window"),
                values[:, j],
                {**crit.CRITERIA[name], "long_name": f"{name} criterion, {plant} plant{_in_pixels(name)}"},
            )
    coords = {
        "criterion": (
            "criterion",
            np.array(spec.criteria, dtype=object),
            {"units": "1", "long_name": "camera criterion"},
        ),
        **spec.window_coords(),
    }
    tolerance = json.dumps(check.tolerance, sort_keys=True)
    return xr.Dataset(data, coords=coords, attrs={"verify_seed": check.seed, "verify_tolerance": tolerance})


def _in_pixels(name: str) -> str:
    """ ", in pixels" for a criterion measured in pixels (`uavdamp.camera.criteria.pixel_attrs`), else ""."""
    return ", in pixels" if crit.CRITERIA[name].get("comment") == PIXEL_COMMENT else ""


def check_verification(spec: GridSpec, checked: xr.Dataset, tolerance: float | dict) -> None:
    """Raise VerificationFailed naming the worst point, criterion and window if a relative difference exceeds
    its criterion's `tolerance` (a number: every criterion's)."""
    relative = checked.verify_relative_difference.transpose("verify", "criterion", "window").values
    limit = np.array([tolerance[n] if isinstance(tolerance, dict) else tolerance for n in spec.criteria])
    p, j, w = np.unravel_index(int(np.argmax(relative / limit[:, None])), relative.shape)
    if relative[p, j, w] > limit[j]:
        index = int(checked.verify_point.values[p])
        fy, fz, k, c = spec.point(index)
        name, window = spec.criteria[j], list(spec.windows)[w]
        units = crit.CRITERIA[name]["units"]
        linear, exudyn = (checked[f"verify_{name}_{plant}"].values[p, w] for plant in ("linear", "exudyn"))
        raise VerificationFailed(
            f"linear and Exudyn plants differ by {relative[p, j, w]:.3%} (tolerance {limit[j]:.3%}) in the {name} "
            f"criterion, window {window}, at point {index} (f_y {fy:g} Hz, f_z {fz:g} Hz, K {k:g} N/m, C {c:g} "
            f"N s/m): linear {linear:.6g} {units}, Exudyn {exudyn:.6g} {units}"
        )
