"""The benchmark's criteria of one run: J per criterion (ASCE form), their families, resources, the frame-phase spread.

Each response metric is divided by the rigid mount's on the same scenario (J = 1: no better than rigid; lower is
better): los_std and los_peak (line of sight, `uavdamp.camera.image_quality`), blur_p95, unsharp_fraction (1 -
sharp-frame fraction, NaN where the rigid mount has no blurred frame), displacement_std (sqrt(var y + var z) of the
camera) and displacement_peak (largest |camera displacement|). Families (`FAMILIES`): a tunable law is tuned, and the
clairvoyant schedule optimised, per family (`uavdamp.benchmark.tuning`); a J of a family comes from the run tuned for
it.

Frame phase: the image metrics depend on where the frame clock starts (a 4 ms exposure every 33 ms samples the
motion at one phase). They are computed for `phases` frame-clock starts spread evenly over one frame period
(0, T/n, ..., (n - 1) T/n, T = 1 / frame rate); the metric is their mean, and its spread (lowest, highest) is kept
beside it: J_low and J_high are the lowest and highest phase's metric over the rigid mount's phase mean. A ranking
on a frame metric is claimed only where the intervals do not overlap (`uavdamp.benchmark.loop.gather`).

Resources are kept in their units: damper work (J, the damper force F on the stroke rate v: F v, which for a lagged or
MR damper differs from the study's C v^2 `energy_dissipated`), damping changes
per second (s-1: steps where the applied C changes by more than 1e-9 relative), peak damper force (N).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from uavdamp.camera import image_quality
from uavdamp.camera.optics import CameraModel

FAMILIES = {
    "displacement": ("displacement_std", "displacement_peak"),
    "line_of_sight": ("los_std", "los_peak"),
    "blur": ("blur_p95", "unsharp_fraction"),
}
J_CRITERIA = tuple(c for members in FAMILIES.values() for c in members)
FAMILY_OF = {c: family for family, members in FAMILIES.items() for c in members}
PHASED = ("blur_p95", "unsharp_fraction")  # the criteria that depend on the frame clock's phase
UNITS = {
    "los_std": "rad",
    "los_peak": "rad",
    "blur_p95": "px",
    "unsharp_fraction": "1",
    "displacement_std": "m",
    "displacement_peak": "m",
}
RESOURCES = {
    "damper_work": ("J", "work of the damper force on the isolator stroke over the run, sum F v dt"),
    "damping_changes_per_s": ("s-1", "changes of the applied damping per second"),
    "peak_damper_force": ("N", "largest damper force over the run"),
    "demand_updates": ("1", "damping demands the law made in the run"),
    "demands_clipped": ("1", "damping demands outside the damper bounds, clipped to them, in the run"),
}


def family_of(criterion: str) -> str:
    """The family of a J criterion (ValueError names an unknown one)."""
    if criterion not in FAMILY_OF:
        raise ValueError(f"criterion: unknown {criterion!r} (known: {list(J_CRITERIA)})")
    return FAMILY_OF[criterion]


def response_metrics(response: xr.Dataset, camera: CameraModel, phases: int = 1) -> dict:
    """The response metrics behind J_CRITERIA (rad, px, 1, m) and, for the PHASED ones, "<name>_low" and
    "<name>_high": the lowest and highest over `phases` frame-clock starts (module docstring; the value is the mean)."""
    t, disp = response.time.values, response.camera_displacement.values
    yaw, pitch = response.camera_yaw.values, response.camera_pitch.values
    los = image_quality.line_of_sight_stats(t, yaw, pitch)
    period = 1.0 / camera.frame_rate_hz
    per_phase = {"blur_p95": [], "unsharp_fraction": []}
    for k in range(phases):
        start = float(t[0]) + period * k / phases
        frames = image_quality.frame_metrics(t, disp, yaw, pitch, camera, start_s=start)
        summary = image_quality.frame_summary(frames, camera.sharp_threshold_px)
        per_phase["blur_p95"].append(summary["blur_p95"][0])
        per_phase["unsharp_fraction"].append(1.0 - summary["sharp_fraction"][0])
    out = {
        "los_std": los["los_std"][0],
        "los_peak": los["los_peak"][0],
        "displacement_std": float(np.sqrt(np.var(disp, axis=1).sum())),
        "displacement_peak": float(np.linalg.norm(disp, axis=0).max()),
    }
    for name, values in per_phase.items():
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
