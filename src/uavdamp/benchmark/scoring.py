"""The benchmark's criteria of one run: J per criterion (ASCE form), their families, resources, the frame-phase spread.

Each criterion of `uavdamp.camera.criteria` (defined there once, with its units and family) over the whole run is
divided by the rigid mount's on the same scenario (J = 1: no better than rigid; lower is better): displacement_std,
displacement_peak, los_std, los_peak, blur_p95 and unsharp_fraction (NaN where the rigid mount has no blurred
frame). Families (`FAMILIES`): a tunable law is tuned, and the clairvoyant schedule optimised, per family
(`uavdamp.benchmark.tuning`); a J of a family comes from the run tuned for it.

Frame phase: the frame criteria (`PHASED`) depend on where the frame clock starts (a 4 ms exposure every 33 ms
samples the motion at one phase). They are computed for `phases` frame-clock starts spread evenly over one frame
period (0, T/n, ..., (n - 1) T/n, T = 1 / frame rate); the metric is their mean, and its spread (lowest, highest) is
kept beside it: J_low and J_high are the lowest and highest phase's metric over the rigid mount's phase mean. A
ranking on a frame metric is claimed only where the intervals do not overlap (`uavdamp.benchmark.loop.gather`).

Resources are kept in their units: damper work (J, the damper force F on the stroke rate v: F v, which for a lagged or
MR damper differs from the study's C v^2 `energy_dissipated`), damping changes
per second (s-1: steps where the applied C changes by more than 1e-9 relative), peak damper force (N).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from uavdamp.camera.criteria import CRITERIA, PHASED
from uavdamp.camera.image_quality import camera_criteria
from uavdamp.camera.optics import CameraModel, image_displacement_px

J_CRITERIA = tuple(CRITERIA)
RESOURCES = {
    "damper_work": ("J", "work of the damper force on the isolator stroke over the run, sum F v dt"),
    "damping_changes_per_s": ("s-1", "changes of the applied damping per second"),
    "peak_damper_force": ("N", "largest damper force over the run"),
    "demand_updates": ("1", "damping demands the law made in the run"),
    "demands_clipped": ("1", "damping demands outside the damper bounds, clipped to them, in the run"),
}


def response_metrics(response: xr.Dataset, camera: CameraModel, phases: int = 1) -> dict:
    """The criteria J_CRITERIA of one run (their units) and, for the PHASED ones, "<name>_low" and "<name>_high":
    the lowest and highest over `phases` frame-clock starts (module docstring; the value is the mean)."""
    t, disp = response.time.values, response.camera_displacement.values
    yaw, pitch = response.camera_yaw.values, response.camera_pitch.values
    whole = [name for name in J_CRITERIA if name not in PHASED]
    out = camera_criteria(whole, t, disp, yaw, pitch)
    period, image_px = 1.0 / camera.frame_rate_hz, image_displacement_px(camera, yaw, pitch, disp[0], disp[1])
    per_phase = [
        camera_criteria(PHASED, t, disp, yaw, pitch, camera, float(t[0]) + period * k / phases, image_px=image_px)
        for k in range(phases)
    ]  # one image path, each phase its own frame clock on it
    for name in PHASED:
        values = [phase[name] for phase in per_phase]
        out |= {name: float(np.mean(values)), f"{name}_low": min(values), f"{name}_high": max(values)}
    return out


def damper_force(response: xr.Dataset) -> np.ndarray:
    """The damper force on the stroke (axis, time), N: the response's `damper_force` where the plant gives it (a
    damper with its own dynamics), else C v_rel of the applied damping."""
    if "damper_force" in response:
        return response.damper_force.values
    return response.damping.values * response.isolator_velocity.values


def criteria(response: xr.Dataset, rigid: dict, camera: CameraModel, phases: int = 1) -> tuple[dict, dict, dict]:
    """({criterion: J}, {criterion: (J_low, J_high)} of the PHASED ones, {resource: value}) of one run; rigid: the
    rigid mount's `response_metrics` (its phase means divide the spread too)."""
    values = response_metrics(response, camera, phases)

    def ratio(value, name):
        return value / rigid[name] if rigid[name] > 0 else math.nan

    j = {name: ratio(values[name], name) for name in J_CRITERIA}
    spread = {name: (ratio(values[f"{name}_low"], name), ratio(values[f"{name}_high"], name)) for name in PHASED}
    c = response.damping.values
    if np.all(np.isnan(c)):
        return j, spread, {name: math.nan for name in RESOURCES}
    v, force = response.isolator_velocity.values, damper_force(response)
    t = response.time.values
    dt = float(t[1] - t[0])
    power = (force * v).sum(axis=0)
    changes = np.abs(np.diff(c[:-1])) > 1e-9 * np.maximum(np.abs(c[:-2]), 1e-12)
    resources = {
        "damper_work": float(np.sum(power[:-1]) * dt),
        "damping_changes_per_s": float(changes.sum() / (t[-1] - t[0])),
        "peak_damper_force": float(np.max(np.linalg.norm(force, axis=0))),
        **{k: float(response[k]) if k in response else 0.0 for k in ("demand_updates", "demands_clipped")},
    }
    return j, spread, resources
