"""The contract between a plant, a damping law and a metric: the place a new contributor starts.

    scenario (mount motion: translation x, y, z m and rotation about x, y, z rad) --> Plant.run(time, mount,
        stiffness=K, law=law)    |   every update period: Observation --> law --> demand C
                                 |   (the plant clips the demand to the damper bounds: `clip`)
                                 v
                response xarray.Dataset (RESPONSE_VARIABLES) --> metrics --> numbers

Plant: anything with ``mount`` ("isolated" or "rigid") and ``run(time, mount, *, stiffness=None, law=None) ->
xarray.Dataset``: it runs the prescribed mount motion (`MountMotion`, time s from 0) with isolator stiffness K
(N m-1) under a damping law and returns the response dataset below. The isolator frame moves and rotates with
the mount; it is compliant in its y and z (the paper's isolator) and rigid in x and in rotation. The rigid mount
has no isolator: it ignores K and the law, and its damping is NaN. Plants: `uavdamp.platform.ExudynPlant` (Exudyn
time stepping, the reference) and `uavdamp.platform.LinearPlant` (exact for Exudyn's linearisation).

DampingLaw: anything with ``name``, ``update_period`` (s, or None for the platform's configured period),
``reset()`` (called by the plant at the start of every run) and ``__call__(observation) -> float``, the damping
demand in N s m-1. The plant calls it at t = 0, P, 2P, ... (P the update period); the value returned at t_k acts
from t_k on (the state at t_k is still that of the old C). A law may return any finite number: the plant clips it
to [damping_min, damping_max] in one place (`clip`); a non-finite demand is an error. Laws: `uavdamp.damping.laws`.

Metric: a function of a response dataset (and the study's options) registered by name in `uavdamp.study.metrics`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
import xarray as xr

AXES = ("y", "z")  # the isolator's compliant axes (and the camera's translation the criteria score)
STANDARD_GRAVITY = 9.80665  # m s-2, one g (exact by definition)
XYZ = ("x", "y", "z")  # Cartesian axes (x forward, y left, z up): a body's, a sensor's, a frame's
MOUNT_AXES = XYZ  # the mount's translation and rotation axes
MOUNTS = ("isolated", "rigid")
FRAMES = {
    "inertial": "inertial frame: x forward, y left, z up (the fuselage axes at t = 0)",
    "isolator": "isolator frame: moves and rotates with the mount (y, z its compliant axes)",
}

# name: (dims, units, long_name) of every variable a plant's response carries
RESPONSE_VARIABLES = {
    "camera_displacement": (("axis", "time"), "m", "camera displacement from its start, inertial frame"),
    "camera_yaw": (("time",), "rad", "line-of-sight azimuth of the camera's optical axis, inertial frame"),
    "camera_pitch": (("time",), "rad", "line-of-sight elevation (positive down) of the camera's axis, inertial frame"),
    "damping": (("time",), "N s m-1", "isolator damping applied from this time on (NaN: rigid mount)"),
    "mount_displacement": (("mount_axis", "time"), "m", "prescribed translation of the mount, inertial frame"),
    "mount_rotation": (("mount_axis", "time"), "rad", "prescribed rotation vector of the mount, inertial frame"),
    "base_displacement": (("axis", "time"), "m", "platform base displacement from its start, inertial frame"),
    "isolator_stroke": (("axis", "time"), "m", "isolator stroke (base relative to the mount), isolator frame"),
    "isolator_velocity": (("axis", "time"), "m s-1", "isolator stroke rate, isolator frame"),
}


@dataclass(frozen=True)
class MountMotion:
    """A prescribed mount motion on its own time samples: translation (3, n) m and rotation (3, n) rad, inertial
    frame (x forward, y left, z up), the rotation as the rotation vector of R(t) R(0)^T (the helicopter stage's and
    the flight-log reader's `mount_rotation`)."""

    translation: np.ndarray
    rotation: np.ndarray

    @classmethod
    def planar(cls, y, z) -> MountMotion:
        """A translation in y and z only (m): the paper's inputs."""
        y, z = np.asarray(y, dtype=float), np.asarray(z, dtype=float)
        return cls(np.stack([np.zeros_like(y), y, z]), np.zeros((3, y.size)))

    @property
    def y(self) -> np.ndarray:
        return self.translation[1]

    @property
    def z(self) -> np.ndarray:
        return self.translation[2]


def on_grid(time, mount: MountMotion, h: float) -> tuple[np.ndarray, MountMotion]:
    """Validated input resampled (linearly, each component) onto the solver grid 0, h, 2h, ... <= time[-1]."""
    time = np.asarray(time, dtype=float)
    translation = np.asarray(mount.translation, dtype=float)
    rotation = np.asarray(mount.rotation, dtype=float)
    if time.ndim != 1 or time.size < 2 or not np.all(np.diff(time) > 0):
        raise ValueError("time must be 1-D, increasing, with at least 2 samples")
    if abs(time[0]) > 1e-12:
        raise ValueError(f"time must start at 0 s, got {time[0]}")
    for name, values in (("mount translation", translation), ("mount rotation", rotation)):
        if values.shape != (3, time.size):
            raise ValueError(f"{name} must have the shape (3, {time.size}) of (axis, time), got {values.shape}")
        if not np.all(np.isfinite(values)):
            raise ValueError(f"{name} must be finite")
    steps = int(math.floor(time[-1] / h + 1e-9))
    if steps < 1:
        raise ValueError(f"time must reach at least one time_step ({h} s)")
    grid = np.arange(steps + 1) * h
    resample = np.vectorize(lambda row: np.interp(grid, time, row), signature="(n)->(m)")
    return grid, MountMotion(resample(translation), resample(rotation))


def line_of_sight(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(azimuth psi, elevation theta) rad of optical-axis directions `axis` (..., 3) in the inertial frame, the
    camera's convention (`uavdamp.camera.optics`): axis = (cos psi cos theta, sin psi cos theta, -sin theta)."""
    axis = np.asarray(axis, dtype=float)
    return np.arctan2(axis[..., 1], axis[..., 0]), np.arcsin(np.clip(-axis[..., 2], -1.0, 1.0))


class SolverFailed(RuntimeError):
    """A plant did not reach the end of a run (e.g. Newton did not converge)."""


@dataclass(frozen=True)
class Observation:
    """What a damping law sees at an update time t_now (s): all up to and including t_now.

    time (s), mount (n, 6): the prescribed mount coordinates on the solver grid so far (read-only views: x, y, z
    translation m, then the X-Y-Z rotation angles rad of the mount links); base_velocity and mount_velocity
    (m s-1, (y, z)), stroke (m, (y, z)): the isolator's state at t_now in its own frame (base_velocity =
    mount_velocity + stroke rate: the base's absolute velocity to first order in the mount's rotation).
    """

    t_now: float
    time: np.ndarray
    mount: np.ndarray
    base_velocity: np.ndarray
    mount_velocity: np.ndarray
    stroke: np.ndarray

    @property
    def mount_y(self) -> np.ndarray:
        """The mount's y translation so far, m."""
        return self.mount[:, 1]

    @property
    def mount_z(self) -> np.ndarray:
        """The mount's z translation so far, m."""
        return self.mount[:, 2]

    @property
    def stroke_rate(self) -> np.ndarray:
        return self.base_velocity - self.mount_velocity


@runtime_checkable
class DampingLaw(Protocol):
    name: str
    update_period: float | None

    def reset(self) -> None: ...

    def __call__(self, observation: Observation) -> float: ...


@runtime_checkable
class Plant(Protocol):
    mount: str

    def run(self, time, mount: MountMotion, *, stiffness: float | None = None, law=None) -> xr.Dataset: ...


def is_multiple(period: float, step: float) -> bool:
    """True if `period` is a positive whole multiple of `step` (to 1e-9 relative)."""
    n = round(period / step)
    return n >= 1 and abs(n * step - period) <= 1e-9 * max(period, 1.0)


def prepare_run(plant, stiffness: float | None, law) -> tuple[float, object | None, int | None]:
    """(K N m-1, law, solver steps per update) of one run of `plant` (its `params` and `mount`), checked.

    K defaults to the configured one; the rigid mount takes no law (None, None); the isolated mount needs a
    `DampingLaw` (TypeError otherwise: a number is not a law) whose update period (None: the configured one) is a
    whole multiple of the time step. The law is reset for the run.
    """
    p = plant.params
    stiffness = p.isolator_stiffness if stiffness is None else float(stiffness)
    if not (math.isfinite(stiffness) and stiffness > 0):
        raise ValueError(f"stiffness must be > 0, got {stiffness}")
    if plant.mount != "isolated":
        return stiffness, None, None
    if not isinstance(law, DampingLaw):
        raise TypeError(
            f"damping: the isolated mount needs a damping law (uavdamp.contract.DampingLaw, e.g. "
            f"uavdamp.damping.laws.Constant(c)), got {law!r}"
        )
    h = p.time_step
    period = p.update_period if law.update_period is None else float(law.update_period)
    if not is_multiple(period, h):
        raise ValueError(f"update_period ({period} s) must be a positive multiple of time_step ({h} s)")
    law.reset()
    return stiffness, law, int(round(period / h))


@dataclass(frozen=True)
class DamperBounds:
    """Damper bounds, N s m-1: c_min <= C <= c_max."""

    c_min: float
    c_max: float

    def __post_init__(self):
        if not (math.isfinite(self.c_min) and math.isfinite(self.c_max) and 0 <= self.c_min <= self.c_max):
            raise ValueError(f"damper bounds: need 0 <= c_min <= c_max, finite, got {self.c_min}, {self.c_max}")

    @classmethod
    def from_params(cls, params) -> DamperBounds:
        """The bounds of a `PlatformParams` (isolator damping_min, damping_max)."""
        return cls(float(params.damping_min), float(params.damping_max))

    def contains(self, c: float) -> bool:
        return bool(self.c_min <= c <= self.c_max)


class NonFiniteDemand(ValueError):
    """A law returned NaN or inf (its message names the law and the time; the study and benchmark add where)."""


def law_name(law) -> str:
    """A law's name for messages: its ``name`` attribute, else its class name."""
    return str(getattr(law, "name", type(law).__name__))


def clip(demand: float, bounds: DamperBounds, t_now: float, law=None) -> float:
    """The damping a damper gives for a demand, N s m-1: the demand clipped to the bounds (the one place).
    NonFiniteDemand (naming `law` when given) for NaN or inf."""
    c = float(demand)
    if not math.isfinite(c):
        who = f"the law {law_name(law)!r}" if law is not None else "the law"
        raise NonFiniteDemand(f"damping: {who} returned the non-finite value {c} at t = {t_now} s")
    return min(max(c, bounds.c_min), bounds.c_max)


def new_clip_count() -> dict[str, int]:
    """A run's demand counter for `counted_clip`: demands made and demands outside the bounds."""
    return {"updates": 0, "clipped": 0}


def counted_clip(law, observation, bounds: DamperBounds, counts: dict[str, int]) -> float:
    """`law`'s demand for `observation`, clipped (`clip`), counted in `counts` (`new_clip_count`)."""
    raw = float(law(observation))
    c = clip(raw, bounds, observation.t_now, law)
    counts["updates"] += 1
    counts["clipped"] += int(c != raw)
    return c


CLIP_VARIABLES = {
    "demand_updates": ("1", "damping demands the law made in the run"),
    "demands_clipped": ("1", "damping demands outside the damper bounds, clipped to them, in the run"),
}


def response_attrs(plant, stiffness: float) -> dict:
    """The attributes every plant's response carries: which plant, mount and body, K (N m-1; NaN rigid), step (s)."""
    return {
        "title": "Camera platform response to a prescribed fuselage displacement",
        "plant": plant.name,
        "mount": plant.mount,
        "body": plant.body,
        "isolator_stiffness_N_m": stiffness,
        "time_step_s": plant.params.time_step,
    }


def response_dataset(time: np.ndarray, values: dict[str, np.ndarray], attrs: dict, clips=None) -> xr.Dataset:
    """A plant's response dataset from arrays named and shaped as in RESPONSE_VARIABLES (all of them), with the run's
    demand counts (`new_clip_count`; zeros for a run without a law) as the scalars of CLIP_VARIABLES."""
    missing = sorted(set(RESPONSE_VARIABLES) - set(values))
    if missing:
        raise ValueError(f"response: missing variable(s) {missing}")
    data = {
        name: (dims, values[name], {"units": units, "long_name": long_name})
        for name, (dims, units, long_name) in RESPONSE_VARIABLES.items()
    }
    coords = {
        "time": ("time", time, {"units": "s", "long_name": "time"}),
        "axis": ("axis", list(AXES), {"units": "1", "long_name": "direction (y lateral, z up)"}),
        "mount_axis": ("mount_axis", list(MOUNT_AXES), {"units": "1", "long_name": "mount axis (x forward, y, z up)"}),
    }
    clips = clips or new_clip_count()
    keys = {"demand_updates": "updates", "demands_clipped": "clipped"}
    for name, (units, long_name) in CLIP_VARIABLES.items():
        data[name] = ((), int(clips[keys[name]]), {"units": units, "long_name": long_name})
    ds = xr.Dataset(data, coords=coords, attrs={**attrs, **{f"frame_{k}": v for k, v in FRAMES.items()}})
    for name in ("isolator_stroke", "isolator_velocity"):
        ds[name].attrs["frame"] = "isolator"
    for name in ("camera_displacement", "camera_yaw", "camera_pitch", "mount_displacement", "mount_rotation"):
        ds[name].attrs["frame"] = "inertial"
    return ds
