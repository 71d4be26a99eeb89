"""The camera criterion and the reference table: the damping that minimises it.

criterion = sqrt(sigma_y^2 + sigma_z^2), sigma the standard deviation (1/N normalisation, the
paper's Eq. 1 up to the square root, which does not move the argmin) of the camera's y and z
displacement over a time window.

Ties: where several dampings give exactly the same minimum, the smallest damping is taken
(numpy's argmin returns the first index, and the damping axis is increasing). Failed points
(NaN) are ignored; a cell whose points all failed gives NaN.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

CRITERION_ATTRS = {"units": "m", "long_name": "camera criterion sqrt(sigma_y^2 + sigma_z^2) over the window"}


def camera_criterion(camera_displacement: xr.DataArray, window: tuple[float, float]) -> float:
    """Criterion, m, of a camera displacement (axis, time) in m over `window` = (start, end) s."""
    start, end = window
    part = camera_displacement.sel(time=slice(start - 1e-12, end + 1e-12))
    if part.sizes["time"] < 2:
        raise ValueError(f"window {list(window)} s holds fewer than 2 samples")
    sigma = part.std(dim="time", ddof=0)
    return float(np.sqrt((sigma**2).sum(dim="axis")))


def _nanargmin(values: np.ndarray, axis: int) -> tuple[np.ndarray, np.ndarray]:
    """Index and value of the minimum along `axis`, NaN ignored; (-1, NaN) where all are NaN."""
    all_nan = np.all(np.isnan(values), axis=axis)
    filled = np.where(np.isnan(values), np.inf, values)
    index = np.argmin(filled, axis=axis)
    best = np.take_along_axis(filled, np.expand_dims(index, axis), axis).squeeze(axis)
    return np.where(all_nan, -1, index), np.where(all_nan, np.nan, best)


def reference_table(grid: xr.Dataset, flat_tolerance: float = 0.05) -> xr.Dataset:
    """The reference table from the grid's `criterion` (freq_y, freq_z, stiffness, damping).

    - damping_opt, criterion_opt (freq_y, freq_z, stiffness): the best constant C per K;
    - stiffness_opt, damping_at_stiffness_opt, criterion_at_stiffness_opt (freq_y, freq_z);
    - damping_flat_min/max (freq_y, freq_z, stiffness): the damping range whose criterion stays
      within (1 + flat_tolerance) of the optimum, how flat the criterion is around it;
    - damping_opt_spread (stiffness): max / min of damping_opt over the frequencies, and
      scheduling_gain (stiffness): the mean over frequencies of criterion(best single C for this K)
      / criterion_opt; 1 means frequency scheduling of C buys nothing at this K.
    """
    crit = grid.criterion.transpose("freq_y", "freq_z", "stiffness", "damping")
    values = crit.values
    damping = grid.damping.values
    stiffness = grid.stiffness.values
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

    d3, d2 = ("freq_y", "freq_z", "stiffness"), ("freq_y", "freq_z")
    per_k = {"units": "N s m-1"}
    return xr.Dataset(
        {
            "damping_opt": (d3, c_opt, {**per_k, "long_name": "damping minimising the criterion at each stiffness"}),
            "criterion_opt": (d3, c_best, {"units": "m", "long_name": "criterion at damping_opt"}),
            "damping_flat_min": (d3, flat_min, {**per_k, "long_name": f"smallest damping within {flat_tolerance:.0%} of criterion_opt"}),
            "damping_flat_max": (d3, flat_max, {**per_k, "long_name": f"largest damping within {flat_tolerance:.0%} of criterion_opt"}),
            "stiffness_opt": (d2, k_opt, {"units": "N m-1", "long_name": "stiffness of the overall best (K, C)"}),
            "damping_at_stiffness_opt": (d2, c_at_k, {**per_k, "long_name": "damping of the overall best (K, C)"}),
            "criterion_at_stiffness_opt": (d2, k_best, {"units": "m", "long_name": "criterion of the overall best (K, C)"}),
            "damping_opt_spread": ("stiffness", spread, {"units": "1", "long_name": "max / min of damping_opt over the input frequencies"}),
            "damping_best_constant": ("stiffness", c_const, {**per_k, "long_name": "single damping minimising the mean criterion over all frequencies"}),
            "criterion_best_constant": (d3, const, {"units": "m", "long_name": "criterion with damping_best_constant"}),
            "scheduling_gain": ("stiffness", gain, {"units": "1", "long_name": "mean of criterion_best_constant / criterion_opt over the frequencies"}),
        },
        coords={name: grid[name] for name in ("freq_y", "freq_z", "stiffness")},
        attrs={"flat_tolerance": flat_tolerance, "tie_rule": "smallest damping among equal minima",
               "n_failed_points": int(grid.failed.sum()) if "failed" in grid else 0},
    )
