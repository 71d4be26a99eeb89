"""The grid's camera criteria over time windows, and the reference table: the damping that minimises each.

Criteria: the table's `criterion` names a family of `uavdamp.camera.criteria` and tabulates its first member, a
number per run and window (smaller is better), defined there once with its units and long name:
    displacement   displacement_std, m: sqrt(var y + var z) of the camera's displacement (the paper's Eq. 1 up to
                   the square root, which does not move the argmin)
    line_of_sight  los_std, rad: sqrt(var yaw + var pitch)
    blur           blur_p95, in pixels (units "1"): 95th percentile over the window's frames of the smear extent,
                   with the camera section's model (`uavdamp.camera.image_quality`: frames start at the window's start)
Windows are named spans [start, end] s of each run (config `reference_table.windows`): `transient` from rest
(the paper's), `steady` after the isolator's start-up; the samples in a window follow `criteria.window_mask`.

From a response dataset (`response_criteria`, the Exudyn path and the verification) the blur uses the exact
pinhole projection (`uavdamp.camera.optics`); the batched linear grid (`uavdamp.reference_table.sine_batch`) uses its
first-order form.

Grid edges: where the optimum is the C grid's first or last value and that value lies inside the damper's bounds
(`platform.isolator.damping_min_n_s_m`, `damping_max_n_s_m`), the true optimum may lie beyond the grid and the
table's C is only a bound: `optimum_at_grid_edge` flags such cells (1 at the bottom, 2 at the top; 3 where the edge
is the damper's own bound, the best C the damper can give) and `grid_edge_share` counts flags 1 and 2.

Table ties: where several dampings give exactly the same minimum, the smallest damping is taken (numpy's
argmin returns the first index, and the damping axis is increasing). Failed points (NaN) are ignored; a cell
whose points all failed gives NaN.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from uavdamp.camera import criteria as cam
from uavdamp.camera.image_quality import camera_criteria
from uavdamp.camera.optics import CameraOptics


def _table_attrs(family: str) -> dict[str, str]:
    attrs = cam.CRITERIA[cam.primary(family)].attrs
    return {**attrs, "long_name": f"{attrs['long_name']} over the window ({cam.primary(family)})"}


CRITERIA = {family: _table_attrs(family) for family in cam.FAMILIES}  # the table's criteria: families
CRITERION_ATTRS = CRITERIA["displacement"]
WINDOW_ATTRS = {"units": "1", "long_name": "criterion time window (reference_table.windows)"}
EDGE_ATTRS = {
    "units": "1",
    "long_name": "damping_opt on an edge of the C grid (reference_table.damping_n_s_m): 1 bottom, 2 top (a bound "
    "inside the damper's range, not an optimum), 3 the damper's own bound, 0 interior",
    "flag_values": np.arange(4, dtype=np.int8),
    "flag_meanings": "interior at_grid_bottom at_grid_top at_damper_bound",
}
_BY_CRITERION = ("criterion_opt", "criterion_best_constant", "criterion_at_stiffness_opt")  # carry its units


def variable(name: str) -> str:
    """The grid variable of criterion `name` (one variable per criterion: each has its own units)."""
    return f"criterion_{name}"


def check_choice(criterion: str, window: str, windows) -> None:
    """ValueError naming reference_table.criterion or .window if the choice is not a criterion / window."""
    if criterion not in CRITERIA:
        raise ValueError(f"reference_table.criterion: {criterion!r} is not one of {list(CRITERIA)}")
    if window not in windows:
        raise ValueError(f"reference_table.window: {window!r} is not one of reference_table.windows {list(windows)}")


# ------------------------------------------------------------------------------------------ from a response


def _in_window(values: xr.DataArray, window: tuple[float, float]) -> np.ndarray:
    """(rows, samples) of `values` (..., time) within `window` (`criteria.window_mask`); ValueError below 2."""
    keep = cam.window_mask(values.time.values, *window)
    if keep.sum() < 2:
        raise ValueError(f"window {list(window)} s holds fewer than 2 samples")
    return np.atleast_2d(values.transpose(..., "time").values)[:, keep]


def camera_criterion(camera_displacement: xr.DataArray, window: tuple[float, float]) -> float:
    """Displacement criterion (`criteria.displacement_std`), m, of a camera displacement (axis, time) in m over
    `window` = (start, end) s."""
    return cam.displacement_std(_in_window(camera_displacement, window))


def line_of_sight_criterion(response: xr.Dataset, window: tuple[float, float]) -> float:
    """Line-of-sight criterion (`criteria.los_std`), rad, of a response over `window`."""
    yaw, pitch = _in_window(xr.concat([response.camera_yaw, response.camera_pitch], dim="axis"), window)
    return cam.los_std(yaw, pitch)


def blur_criterion(response: xr.Dataset, camera: CameraOptics, window: tuple[float, float]) -> float:
    """Blur criterion (`criteria.blur_p95`), px, exact projection (`image_quality.frame_metrics`) over `window`."""
    args = (response.camera_displacement.values, response.camera_yaw.values, response.camera_pitch.values)
    return camera_criteria(["blur_p95"], response.time.values, *args, camera, *window)["blur_p95"]


def response_criteria(response: xr.Dataset, windows: dict, camera: CameraOptics) -> np.ndarray:
    """Every criterion (CRITERIA order) over every window (`windows` order): (n_criteria, n_windows)."""
    out = np.empty((len(CRITERIA), len(windows)))
    for j, window in enumerate(windows.values()):
        out[0, j] = camera_criterion(response.camera_displacement, window)
        out[1, j] = line_of_sight_criterion(response, window)
        out[2, j] = blur_criterion(response, camera, window)
    return out


# ------------------------------------------------------------------------------------------ the table


def _nanargmin(values: np.ndarray, axis: int) -> tuple[np.ndarray, np.ndarray]:
    """Index and value of the minimum along `axis`, NaN ignored; (-1, NaN) where all are NaN."""
    all_nan = np.all(np.isnan(values), axis=axis)
    filled = np.where(np.isnan(values), np.inf, values)
    index = np.argmin(filled, axis=axis)
    best = np.take_along_axis(filled, np.expand_dims(index, axis), axis).squeeze(axis)
    return np.where(all_nan, -1, index), np.where(all_nan, np.nan, best)


EDGE_FLAGS = {0: "interior", 1: "at_grid_bottom", 2: "at_grid_top", 3: "at_damper_bound"}


def grid_edge(ic: np.ndarray, damping: np.ndarray, damper_bounds: tuple[float, float] | None) -> np.ndarray:
    """`EDGE_FLAGS` of optimum indices `ic` (-1: no optimum) on the increasing C grid `damping` (N s/m), given the
    damper's (min, max) C (N s/m; None: unknown, every grid edge may hide a better C beyond it)."""
    low, high = damper_bounds if damper_bounds is not None else (-np.inf, np.inf)
    last = damping.size - 1
    flags = np.zeros(ic.shape, dtype=np.int8)
    flags[ic == 0] = 3 if damping[0] <= low else 1
    flags[ic == last] = 3 if damping[last] >= high else 2
    return flags


def optimum(
    values: xr.DataArray, flat_tolerance: float = 0.05, damper_bounds: tuple[float, float] | None = None
) -> xr.Dataset:
    """The reference table of one criterion `values` (freq_y, freq_z, stiffness, damping), with its units.

    - damping_opt, criterion_opt (freq_y, freq_z, stiffness): the best constant C per K;
    - stiffness_opt, damping_at_stiffness_opt, criterion_at_stiffness_opt (freq_y, freq_z);
    - damping_flat_min/max (freq_y, freq_z, stiffness): the damping range whose criterion stays
      within (1 + flat_tolerance) of the optimum, how flat the criterion is around it;
    - optimum_at_grid_edge (freq_y, freq_z, stiffness): `grid_edge` flags of damping_opt (`damper_bounds`: the
      damper's (min, max) C, N s/m), grid_edge_share: the share of cells flagged 1 or 2 (a bound, not an optimum);
    - damping_opt_spread (stiffness): max / min of damping_opt over the frequencies, and
      scheduling_gain (stiffness): the mean over frequencies of criterion(best single C for this K)
      / criterion_opt; 1 means frequency scheduling of C buys nothing at this K.
    """
    crit = values.transpose("freq_y", "freq_z", "stiffness", "damping")
    units = crit.attrs.get("units", CRITERION_ATTRS["units"])
    values, damping, stiffness = crit.values, crit.damping.values, crit.stiffness.values
    ic, c_best = _nanargmin(values, axis=3)
    c_opt = np.where(ic >= 0, damping[np.maximum(ic, 0)], np.nan)

    ik, k_best = _nanargmin(c_best, axis=2)
    k_opt = np.where(ik >= 0, stiffness[np.maximum(ik, 0)], np.nan)
    c_at_k = np.take_along_axis(c_opt, np.maximum(ik, 0)[..., None], axis=2).squeeze(2)
    c_at_k = np.where(ik >= 0, c_at_k, np.nan)

    within = values <= (1 + flat_tolerance) * c_best[..., None]
    flat_min = np.where(within.any(axis=3), np.min(np.where(within, damping, np.inf), axis=3), np.nan)
    flat_max = np.where(within.any(axis=3), np.max(np.where(within, damping, -np.inf), axis=3), np.nan)

    with np.errstate(invalid="ignore", divide="ignore"):
        spread = np.nanmax(c_opt, axis=(0, 1)) / np.nanmin(c_opt, axis=(0, 1))
        mean_over_freq = np.nanmean(values, axis=(0, 1))  # (stiffness, damping)
        ic_const, _ = _nanargmin(mean_over_freq, axis=1)
        const = np.take_along_axis(values, np.maximum(ic_const, 0)[None, None, :, None], axis=3).squeeze(3)
        gain = np.nanmean(const / c_best, axis=(0, 1))
    c_const = np.where(ic_const >= 0, damping[np.maximum(ic_const, 0)], np.nan)

    edge = grid_edge(ic, damping, damper_bounds)
    d3, d2, k, ns = ("freq_y", "freq_z", "stiffness"), ("freq_y", "freq_z"), ("stiffness",), "N s m-1"
    tol = f"{flat_tolerance:.0%}"
    rows = [
        ("damping_opt", d3, c_opt, ns, "damping minimising the criterion at each stiffness"),
        ("criterion_opt", d3, c_best, units, "criterion at damping_opt"),
        ("damping_flat_min", d3, flat_min, ns, f"smallest damping within {tol} of criterion_opt"),
        ("damping_flat_max", d3, flat_max, ns, f"largest damping within {tol} of criterion_opt"),
        ("stiffness_opt", d2, k_opt, "N m-1", "stiffness of the overall best (K, C)"),
        ("damping_at_stiffness_opt", d2, c_at_k, ns, "damping of the overall best (K, C)"),
        ("criterion_at_stiffness_opt", d2, k_best, units, "criterion of the overall best (K, C)"),
        ("damping_opt_spread", k, spread, "1", "max / min of damping_opt over the input frequencies"),
        ("damping_best_constant", k, c_const, ns, "single damping minimising the mean criterion over all frequencies"),
        ("criterion_best_constant", d3, const, units, "criterion with damping_best_constant"),
        ("scheduling_gain", k, gain, "1", "mean of criterion_best_constant / criterion_opt over the frequencies"),
    ]
    out = xr.Dataset(
        {name: (dims, value, {"units": u, "long_name": text}) for name, dims, value, u, text in rows},
        coords={name: crit[name] for name in ("freq_y", "freq_z", "stiffness")},
    )
    out["optimum_at_grid_edge"] = (d3, edge, EDGE_ATTRS)
    share = float(np.isin(edge, (1, 2)).mean())
    out["grid_edge_share"] = (
        (),
        share,
        {"units": "1", "long_name": "share of cells whose damping_opt is a grid bound"},
    )
    return out


def reference_table(
    grid: xr.Dataset, flat_tolerance: float = 0.05, damper_bounds: tuple[float, float] | None = None
) -> xr.Dataset:
    """The table (`optimum`, with the damper's (min, max) C `damper_bounds`, N s/m) of every criterion variable of
    the grid and every window, in one dataset.

    Variables in N s m-1, N m-1 or 1 are stacked over (criterion, window, ...); those in the criterion's
    own units (criterion_opt, criterion_best_constant, criterion_at_stiffness_opt) are one variable per
    criterion, `<name>_<criterion>` over (window, ...), since a NetCDF variable has one unit.
    """
    names = [name for name in CRITERIA if variable(name) in grid]
    if not names:
        raise ValueError(f"the grid holds no criterion variable ({[variable(n) for n in CRITERIA]})")
    windows = {name: grid[name] for name in ("window", "window_start", "window_end") if name in grid.coords}

    def stacked(parts: list[xr.Dataset], dim: str) -> xr.Dataset:
        return xr.concat(parts, dim=dim, coords="minimal", compat="override", join="exact")

    tables = {}
    for name in names:
        values = grid[variable(name)].reset_coords(drop=True)
        tables[name] = stacked(
            [optimum(values.isel(window=j), flat_tolerance, damper_bounds) for j in range(values.sizes["window"])],
            "window",
        ).assign_coords(windows)
    shared = [v for v in tables[names[0]].data_vars if v not in _BY_CRITERION]
    out = stacked([tables[n][shared] for n in names], "criterion")
    out = out.assign_coords(
        criterion=(
            "criterion",
            np.array(names, dtype=object),
            {"units": "1", "long_name": "camera criterion minimised"},
        )
    )
    for name in names:
        for var in _BY_CRITERION:
            da = tables[name][var]
            out[f"{var}_{name}"] = da.assign_attrs(long_name=f"{da.attrs['long_name']} ({name})")
    out.attrs = {
        "flat_tolerance": flat_tolerance,
        "tie_rule": "smallest damping among equal minima",
        "n_failed_points": int(grid.failed.sum()) if "failed" in grid else 0,
        **({"damper_bounds_n_s_m": list(damper_bounds)} if damper_bounds is not None else {}),
    }
    return out


def select_table(table: xr.Dataset, criterion: str, window: str) -> xr.Dataset:
    """The chosen criterion and window's table: the `optimum` variables over (freq_y, freq_z, stiffness).

    ValueError naming reference_table.criterion or .window if the table does not hold them."""
    check_choice(criterion, window, [str(w) for w in table.window.values])
    if criterion not in table.criterion.values:
        raise ValueError(
            f"reference_table.criterion: {criterion!r} is not in the table ({[str(c) for c in table.criterion.values]})"
        )
    keep = [v for v in table.data_vars if "criterion" in table[v].dims]
    chosen = table[keep].sel(criterion=criterion, window=window, drop=True)
    for var in _BY_CRITERION:
        chosen[var] = table[f"{var}_{criterion}"].sel(window=window, drop=True)
    chosen.attrs = {**table.attrs, "criterion": criterion, "window": window}
    return chosen


def select_grid(grid: xr.Dataset, criterion: str, window: str) -> xr.DataArray:
    """The chosen criterion over (freq_y, freq_z, stiffness, damping) in the chosen window."""
    check_choice(criterion, window, [str(w) for w in grid.window.values])
    if variable(criterion) not in grid:
        raise ValueError(f"reference_table.criterion: the grid holds no {variable(criterion)!r}")
    return grid[variable(criterion)].sel(window=window, drop=True)
