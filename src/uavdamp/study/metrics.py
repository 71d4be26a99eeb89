"""Metrics by name: functions from one run's response dataset (`uavdamp.contract`) to numbers.

A metric takes the response and the study's options and returns an `xarray.DataArray` with `units` and
`long_name`: a scalar, or over ``axis`` (y, z). The study applies every registered metric to every run and
concatenates them with xarray. Adding a metric is one function with ``@register("name")`` and its tests.

    peak_early         largest |camera displacement| up to early_s (paper: 0.5 s), per axis, m
    std_total          standard deviation of the camera displacement over the run (1/N), per axis, m
    std_settled        the same after settle_s (paper: "both converge after about 1 s"), per axis, m
    energy_dissipated  energy the damper dissipated, sum over axes of the integral of C v_rel^2 dt, J
    peak_stroke        largest |dynamic isolator stroke| over the run, per axis, m (NaN: rigid mount); the
                       study adds the static sag and manoeuvre stroke to it (`uavdamp.platform.stroke`)
    image              line of sight and image blur over the run (`uavdamp.camera.image_quality`; needs options.camera):
                       los_* (rad), blur_* (in pixels: units "1"), sharp_fraction, mtf_nyquist_median, frame_blur
                       (frame, pixels); los_std, los_peak and blur_p95 are the criteria of `uavdamp.camera.criteria`

A metric may also return a Dataset: a group of named values computed together.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import xarray as xr

from uavdamp import registry
from uavdamp.camera import image_quality
from uavdamp.camera.criteria import pixel_attrs

REGISTRY: dict[str, Callable] = {}


def register(name: str):
    """Register a metric function under `name` (decorator)."""
    return registry.add(REGISTRY, "metric", name)


def evaluate(response: xr.Dataset, options) -> xr.Dataset:
    """Every registered metric of one run, as a dataset of scalars and per-axis values."""
    out = xr.Dataset()
    for name, fn in REGISTRY.items():
        value = fn(response, options)
        group = value if isinstance(value, xr.Dataset) else xr.Dataset({name: value})
        for key, var in group.data_vars.items():
            if not {"units", "long_name"} <= set(var.attrs):
                raise ValueError(f"metric {name!r} returned {key!r} without units or long_name")
        out = out.merge(group)
    return out


def _named(value, units: str, long_name: str) -> xr.DataArray:
    value = value if isinstance(value, xr.DataArray) else xr.DataArray(value)
    return value.drop_vars(list(value.coords)).assign_attrs(units=units, long_name=long_name)


@register("peak_early")
def peak_early(response: xr.Dataset, options) -> xr.DataArray:
    early = response.camera_displacement.sel(time=slice(0.0, options.early_s + 1e-9))
    return _named(np.abs(early).max("time"), "m", f"largest |camera displacement| up to {options.early_s} s")


@register("std_total")
def std_total(response: xr.Dataset, options) -> xr.DataArray:
    return _named(
        response.camera_displacement.std("time"), "m", "standard deviation of the camera displacement, whole run"
    )


@register("std_settled")
def std_settled(response: xr.Dataset, options) -> xr.DataArray:
    settled = response.camera_displacement.sel(time=slice(options.settle_s, None))
    return _named(settled.std("time"), "m", f"standard deviation of the camera displacement after {options.settle_s} s")


@register("energy_dissipated")
def energy_dissipated(response: xr.Dataset, options) -> xr.DataArray:
    """sum over axes of sum_n C_n v_n^2 dt (C held over each step: left-point rule); NaN for the rigid mount."""
    time = response.time.values
    v2 = (response.isolator_velocity.values**2).sum(axis=0)
    c = response.damping.values
    energy = float(np.sum(c[:-1] * v2[:-1]) * (time[1] - time[0]))
    return _named(energy, "J", "energy dissipated by the commanded viscous damping over the run, sum C v^2 dt")


@register("peak_stroke")
def peak_stroke(response: xr.Dataset, options) -> xr.DataArray:
    peak = np.abs(response.isolator_stroke).max("time")
    if np.all(np.isnan(response.damping.values)):  # the rigid mount has no isolator
        peak = peak * np.nan
    return _named(peak, "m", "largest |dynamic isolator stroke| over the run")


@register("image")
def image(response: xr.Dataset, options) -> xr.Dataset:
    """What the camera sees over the whole run: line-of-sight statistics and per-frame blur (`image_quality`)."""
    camera = getattr(options, "camera", None)
    if camera is None:
        return xr.Dataset()
    args = (
        response.time.values,
        response.camera_displacement.values,
        response.camera_yaw.values,
        response.camera_pitch.values,
        camera,
    )
    values = image_quality.image_metrics(*args)
    frames = image_quality.frame_metrics(*args)
    out = xr.Dataset(
        {
            name: (
                (),
                value,
                pixel_attrs(long_name) if long_name.endswith("in pixels") else {"units": units, "long_name": long_name},
            )
            for name, (value, units, long_name) in values.items()
        }
    )
    out["frame_blur"] = (
        "frame",
        frames.blur_px,
        pixel_attrs("blur of each frame: extent of the image path of the scene point during the exposure, in pixels"),
    )
    return out.assign_coords(frame=("frame", frames.start_s, {"units": "s", "long_name": "frame start time"}))
