"""One run of the payload comparison (`uavdamp.study.payload`): a payload on a mount, and the camera's metrics.

A run gives the camera's line of sight (roll, pitch, yaw, rad, inertial) and the translation (y, z, m, from its
start) of its optical centre; `run_metrics` turns them into the comparison's numbers. The mounts' bodies
(`BodyMotion`): the rigid mount is the mount motion itself (its rates and accelerations by second-order finite
differences of the samples: nothing better is known of a sampled input); an isolated mount is the six-axis model's
exact solution for a first-order-hold input (`isolated_motion`: the same step map and start as
`uavdamp.platform.six_axis_run.run`, its rates the state's, its accelerations their central differences). The gimbal
(`gimbal_series`) stands on that body at the point `lever` (m, from the mount's reference point) and is run by
`uavdamp.platform.gimbal_sim.simulate_many` (the runs of an input side by side) with one-way coupling (the motors'
reaction torque on the body is left out); an axis it does not stabilise follows the body. The pan-tilt heads
(`head_series`) run on the platform's own plants (`uavdamp.platform.plants`); their roll is the mount's rotation
about x (assumption, first order: the head has no roll joint and the paper's isolator is rigid in rotation). The
gimbal's body and isolators are built here from the section (`gimbal_payload`, `six_axis_isolator`, `yz_isolator`;
`uavdamp.study.payload` re-exports them). An input reaches the runs' grid band-limited (`resampled`).
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import NamedTuple

import numpy as np

from uavdamp.camera.criteria import CRITERIA, los_std, pixel_attrs, window_mask
from uavdamp.camera.image_quality import frame_summary, frames_from_image_path
from uavdamp.camera.optics import CameraModel, image_displacement_px
from uavdamp.contract import MountMotion
from uavdamp.damping.dampers import SpencerMR
from uavdamp.damping.laws import Constant
from uavdamp.platform import six_axis_force, wire_rope
from uavdamp.platform.gimbal import AXES, CHAIN, AxisGains, GimbalParams, camera_inertia
from uavdamp.platform.gimbal_sim import simulate_many
from uavdamp.platform.six_axis import (
    Payload,
    SixAxisIsolator,
    paper_yz,
    square_layout,
    state_space,
    strokes_matrix,
    transform,
)
from uavdamp.platform.statespace import discretise, lift, propagate

SIX_AXIS_MOUNTS = ("six_axis", "wire_rope")  # the gimbal only: the heads' plant has a Y-Z isolator alone
MECHANISM_MASS_KG = 0.3  # kg, the gimbal's brackets and motors (choice: three ~70 g motors and ~90 g of brackets)


# ----------------------------------------------------------------- the gimbal's body and isolators (`section`: a
# `uavdamp.study.payload.PayloadSection`)


def gimbal_params(section) -> GimbalParams:
    """The gimbal of ``payload.gimbal``."""
    return section.gimbal.params()


def gimbal_mass(section) -> float:
    """The gimbal's moving mass, camera included, kg: camera + `MECHANISM_MASS_KG`."""
    return gimbal_params(section).camera_mass + MECHANISM_MASS_KG


def gimbal_height(section) -> float:
    """Height of the gimbal's axes above the elements' plane, m: M h / m_g, so that the plate (in the plane) and
    the gimbal put the payload's centre of mass at h = ``six_axis.com_height_m``."""
    s = section.six_axis
    return (gimbal_mass(section) + s.plate_mass) * s.com_height / gimbal_mass(section)


def gimbal_payload(section) -> Payload:
    """The isolated payload: camera + mechanism + plate, kg; centre of mass (0, 0, h) m; inertia about it, kg m2:
    the camera box and the stabilised axes' brackets (`uavdamp.platform.gimbal`) at the gimbal's axes, the plate
    a thin square of side 2 ``half_spacing_m`` in the elements' plane, each moved to the centre of mass."""
    p, s = gimbal_params(section), section.six_axis
    m_g, side, h = gimbal_mass(section), 2 * s.half_spacing, s.com_height
    gimbal = camera_inertia(p) + sum(np.asarray(p.bracket_inertia[CHAIN.index(a)]) for a in p.axes)
    plate = s.plate_mass * side**2 / 12 * np.array([1.0, 1.0, 2.0])
    shift = (m_g * (gimbal_height(section) - h) ** 2 + s.plate_mass * h**2) * np.array([1.0, 1.0, 0.0])
    return Payload(m_g + s.plate_mass, (0.0, 0.0, h), tuple(map(tuple, np.diag(gimbal + plate + shift))))


def six_axis_isolator(section, c: float, kind: str | None = None) -> SixAxisIsolator:
    """The gimbal's six-axis isolator: `square_layout` of ``payload.six_axis``, every element semi-active with
    damping C (N s m-1) along x, y and z, under the gimbal's gravity (geometric stiffness); elements of `kind`
    (None: ``six_axis.kind``)."""
    s = section.six_axis
    return square_layout(
        gimbal_payload(section),
        s.half_spacing,
        tuple(s.stiffness),
        (c, c, c),
        kind=s.kind if kind is None else kind,
        semi_active=True,
        gravity=gimbal_params(section).gravity,
    )


def yz_isolator(section, mass: float, c: float) -> SixAxisIsolator:
    """The paper's Y-Z isolator (`paper_yz`) under `mass` kg at K = ``yz_stiffness_n_m`` and C (N s m-1)."""
    return paper_yz(mass, section.yz_stiffness, c)


def isolator(section, mount: str, c: float) -> SixAxisIsolator | None:
    """The gimbal's isolator on `mount` ("rigid", "yz", "six_axis", "wire_rope") at C (N s m-1): None for the rigid
    mount; for "wire_rope" the six-axis isolator of wire-rope elements, its small-amplitude limit (the hysteresis
    is ``payload.wire_rope``'s, run by `hysteretic_motions`)."""
    if mount == "rigid":
        return None
    if mount == "yz":
        return yz_isolator(section, gimbal_payload(section).mass, c)
    return six_axis_isolator(section, c, "wire_rope" if mount == "wire_rope" else None)


# ----------------------------------------------------------------------------------------------------- runs


class BodyMotion(NamedTuple):
    """A rigid body's 6-DOF motion at the mount's reference point: coordinates (6, n) m and rad, their rates
    (6, n) m s-1 and rad s-1, accelerations (6, n) m s-2 and rad s-2 (x, y, z, rx, ry, rz, mount axes), and the
    largest |element stroke| along an element axis over the run, m (NaN: no isolator)."""

    coordinates: np.ndarray
    rates: np.ndarray
    accelerations: np.ndarray
    peak_stroke: float


class Series(NamedTuple):
    """What the camera does in one run: line-of-sight roll, pitch (positive down), yaw (rad, inertial) and the
    optical centre's y, z (m, from its start), each (n,); saturated (axes, n) the gimbal's torque-limit flags
    (None for a head); peak_stroke m (NaN: rigid)."""

    roll: np.ndarray
    pitch: np.ndarray
    yaw: np.ndarray
    y: np.ndarray
    z: np.ndarray
    saturated: np.ndarray | None
    peak_stroke: float


def _coordinates(mount: MountMotion) -> np.ndarray:
    """The mount's 6-DOF coordinates (n, 6): translation m, rotation rad."""
    return np.vstack([np.asarray(mount.translation, dtype=float), np.asarray(mount.rotation, dtype=float)]).T


def rigid_motion(time: np.ndarray, mount: MountMotion) -> BodyMotion:
    """The rigid mount: the body is the mount; rates and accelerations by second-order finite differences (the
    rotation vector's rate taken as the angular rate: small rotations)."""
    u = _coordinates(mount).T
    h = float(time[1] - time[0])
    rates = np.gradient(u, h, axis=1, edge_order=2)
    return BodyMotion(u, rates, np.gradient(rates, h, axis=1, edge_order=2), math.nan)


def isolated_motion(isolator: SixAxisIsolator, time: np.ndarray, mount: MountMotion) -> BodyMotion:
    """The payload of `isolator` (its elements' own damping) under the mount motion: coordinates and rates exact
    for a first-order-hold input (the exact step map from q = u, q' = the first slope, as `six_axis_run.run`);
    accelerations the central differences of those rates (second order: the equations of motion's value at a
    sample would carry the input's slope jump there, an artefact of the sampled input that a stiff element turns
    into a spike)."""
    u = _coordinates(mount)
    h = float(time[1] - time[0])
    slopes = np.diff(u, axis=0) / h
    step = discretise(state_space(isolator), h)
    z = propagate(step, np.concatenate([u[0], slopes[0]]), u[:-1], slopes, lift(step.phi))
    return _state_motion(isolator, z, u, h)


def _state_motion(isolator: SixAxisIsolator, states: np.ndarray, u: np.ndarray, h: float) -> BodyMotion:
    """The `BodyMotion` of the payload's states (n, 12) (q, q') under the mount coordinates u (n, 6) on a grid of
    step h s: the accelerations the rates' central differences, the peak |element stroke| along an element axis."""
    strokes = (states[:, :6] - u) @ strokes_matrix(isolator).T
    rates = states[:, 6:].T
    accelerations = np.gradient(rates, h, axis=1, edge_order=2)
    return BodyMotion(states[:, :6].T, rates, accelerations, float(np.abs(strokes).max()))


def hysteretic_motions(section, dampings, time: np.ndarray, mount: MountMotion) -> list[BodyMotion]:
    """The payload on the wire-rope isolator (``payload.wire_rope``) at each of `dampings` (N s m-1, every element),
    integrated side by side (`uavdamp.platform.wire_rope.integrate`); rates the states', accelerations their
    central differences (as `isolated_motion`)."""
    found = isolator(section, "wire_rope", float(dampings[0]))
    n_semi = len(found.semi_active)
    u = _coordinates(mount)
    h = float(time[1] - time[0])
    states, _, _ = wire_rope.integrate(
        found, section.wire_rope.params(), time, u[:, :3].T, u[:, 3:].T, [[float(c)] * n_semi for c in dampings]
    )
    return [_state_motion(found, w, u, h) for w in states]


def hysteretic_law_motions(section, c: float, schedules: list, time: np.ndarray, mount: MountMotion):
    """(the payload on the wire-rope isolator (its elements' own damping C, N s m-1) under each of `schedules` (the
    semi-active elements' damping: arrays or callables, `uavdamp.platform.wire_rope.integrate_scheduled`),
    integrated side by side, as `BodyMotion`s; the applied C (B, n, n_semi) N s m-1)."""
    found = isolator(section, "wire_rope", c)
    u = _coordinates(mount)
    states, _, _, applied = wire_rope.integrate_scheduled(
        found, section.wire_rope.params(), time, u[:, :3].T, u[:, 3:].T, schedules
    )
    return [_state_motion(found, w, u, float(time[1] - time[0])) for w in states], applied


def mr_law_motions(section, params, max_substep: float, schedules: list, time: np.ndarray, mount: MountMotion):
    """(the payload on the six-axis isolator with a Spencer MR damper (`params`, a `SpencerParams`; its sub-step
    max_substep s) along each element's x, y, z under each of `schedules` of command voltages (arrays or callables,
    V: `uavdamp.platform.six_axis_force.integrate`), side by side, as `BodyMotion`s; the applied voltages
    (B, n, n_semi))."""
    found = six_axis_isolator(section, 0.0)
    u = _coordinates(mount)

    def dampers(n: int) -> SpencerMR:  # one damper per damper axis of every run, advanced together
        return SpencerMR(params, n_axes=n, max_substep=max_substep)

    states, _, applied, _ = six_axis_force.integrate(found, dampers, time, u[:, :3].T, u[:, 3:].T, schedules)
    return [_state_motion(found, w, u, float(time[1] - time[0])) for w in states], applied


def gimbal_series(
    p: GimbalParams,
    gains: dict[str, AxisGains],
    time: np.ndarray,
    bodies: list[BodyMotion],
    lever,
    *,
    sensor_errors: bool,
    seed: int,
) -> list[Series]:
    """The gimbal at `lever` (m, from the body's reference point) on each of `bodies`: its base rotation, rate and
    the point's acceleration (linear kinematics, T(lever) q'') into `simulate_many` (the runs side by side), a fresh
    Generator of `seed` per run (common random numbers). The optical centre at the gimbal's axes: translation
    T(lever) q from its start."""
    t_point = transform(lever)
    bases = [(body.coordinates[3:], body.rates[3:], t_point @ body.accelerations) for body in bodies]
    rngs = [np.random.default_rng(seed) for _ in bodies]
    runs = simulate_many(p, time, bases, gains=gains, sensor_errors=sensor_errors, rngs=rngs)
    out = []
    for body, ds in zip(bodies, runs, strict=True):
        angles = body.coordinates[3:].copy()
        for axis in ds.axis.values:
            angles[AXES.index(str(axis))] = ds.line_of_sight.sel(axis=axis).values
        translation = t_point @ body.coordinates
        translation = translation - translation[:, :1]
        saturated = ds.torque_saturated.values.astype(float)
        out.append(Series(angles[0], angles[1], angles[2], translation[1], translation[2], saturated, body.peak_stroke))
    return out


def head_series(plants, mount_kind: str, time: np.ndarray, mount: MountMotion, stiffness: float, damping: float):
    """A pan-tilt head on its plant: `mount_kind` "rigid" or "yz" (the isolated mount at K `stiffness` N m-1 and a
    constant C `damping` N s m-1)."""
    law = None if mount_kind == "rigid" else Constant(damping)
    plant = plants.for_run("rigid" if law is None else "isolated", law)
    r = plant.run(time, mount, stiffness=stiffness, law=law)
    stroke = math.nan if law is None else float(np.abs(r.isolator_stroke.values).max())
    y, z = r.camera_displacement.values
    roll = np.asarray(mount.rotation[0], dtype=float)
    return Series(roll, r.camera_pitch.values, r.camera_yaw.values, y, z, None, stroke)


# name: (units, long_name, in pixels) of the metrics of one run; None: a criterion of `uavdamp.camera.criteria`
METRICS = {
    "los_std": None,
    "los_detrended_std": (
        "rad",
        "line of sight (yaw, pitch) rms about its least-squares quadratic over the settled window: the vibration "
        "without a slow drift (a gyro bias's)",
        False,
    ),
    "los_roll_rms": ("rad", "line-of-sight roll rms (std) over the settled window", False),
    "los_peak_to_peak": ("rad", "largest frame-to-frame image offset, as an angle (arctan of px / focal px)", False),
    "jitter_within_exposure": ("1", "rms over frames of the jitter about the exposure's linear smear, in pixels", True),
    "drift_frame_to_frame": ("1", "rms distance between consecutive frame centroids, in pixels", True),
    "mtf_nyquist": ("1", "mean over frames of the motion and jitter MTF at the sensor Nyquist frequency", False),
    "skew_px": ("1", "95th percentile of the rolling-shutter shift first row to last row, in pixels", True),
    "blur_p95": None,
    "torque_saturated": ("1", "share of gimbal samples (axes x time, settled window) at the torque limit", False),
    "peak_stroke": ("m", "largest isolator element stroke along an element axis over the run", False),
}


def metric_attrs(name: str) -> dict[str, str]:
    """CF attributes of metric `name` (a criterion's from `uavdamp.camera.criteria`, over the settled window)."""
    if METRICS[name] is None:
        attrs = CRITERIA[name].attrs
        return {**attrs, "long_name": f"{attrs['long_name']} over the settled window"}
    units, long_name, pixels = METRICS[name]
    return pixel_attrs(long_name) if pixels else {"units": units, "long_name": long_name}


def detrended_std(time: np.ndarray, *angles: np.ndarray) -> float:
    """sqrt of the summed mean squares (rad) of each angle (rad) about its least-squares quadratic in time (s): the
    rms a drift slower than the window (a ramp, a settling over a long time constant) leaves out."""
    t = np.asarray(time, dtype=float) - float(np.mean(time))
    basis = np.column_stack([np.ones_like(t), t, t * t])
    total = 0.0
    for angle in angles:
        a = np.asarray(angle, dtype=float)
        residual = a - basis @ np.linalg.lstsq(basis, a, rcond=None)[0]
        total += float(np.mean(residual**2))
    return math.sqrt(total)


def run_metrics(time: np.ndarray, s: Series, camera: CameraModel, start: float, end: float) -> dict[str, float]:
    """The metrics of `METRICS` of one run over the window [start, end] s (peak_stroke over the whole run)."""
    keep = window_mask(time, start, end)
    u, v = image_displacement_px(camera, s.yaw, s.pitch, s.y, s.z)
    frames = frames_from_image_path(time, u, v, camera, start, end)
    summary = frame_summary(frames, camera.sharp_threshold_px)
    steps = np.linalg.norm(np.diff(frames.centroid_px, axis=0), axis=-1)
    return {
        "los_std": los_std(s.yaw[keep], s.pitch[keep]),
        "los_detrended_std": detrended_std(time[keep], s.yaw[keep], s.pitch[keep]),
        "los_roll_rms": float(np.std(s.roll[keep])),
        "los_peak_to_peak": float(np.arctan(steps.max() / camera.focal_px)) if steps.size else math.nan,
        "jitter_within_exposure": float(np.sqrt(np.mean(frames.sigma_px**2))),
        "drift_frame_to_frame": summary["frame_jitter_rms"][0],
        "mtf_nyquist": float(np.mean(frames.mtf_nyquist)),
        "skew_px": summary["rolling_shutter_skew_p95"][0],
        "blur_p95": summary["blur_p95"][0],
        "torque_saturated": math.nan if s.saturated is None else float(np.mean(s.saturated[:, keep])),
        "peak_stroke": s.peak_stroke,
    }


def resample_ratio(dt: float, h: float) -> Fraction | None:
    """up / down with `resampled`'s polyphase filter taking a step of dt s to one of h s: dt / h as a ratio of
    integers up to 1000 (within 1e-9), None where there is none (the config checks refuse such an input first)."""
    ratio = Fraction(dt / h).limit_denominator(1000)
    return ratio if math.isclose(float(ratio), dt / h, rel_tol=1e-9) else None


def resampled(time: np.ndarray, mount: MountMotion, h: float) -> tuple[np.ndarray, MountMotion]:
    """The motion (uniform `time` from 0, s) on the grid 0, h, 2h, ... by polyphase band-limited resampling
    (`scipy.signal.resample_poly`, the input's step over h a ratio of integers up to 1000; ValueError otherwise)
    through a Kaiser (beta 12, about 120 dB) low-pass at 0.9 of the input's Nyquist frequency, 40 input samples
    either side: the acceleration of a line below 0.2 of the Nyquist frequency within 0.1 %, at 0.2 within 1 %
    (tests/test_payload.py); scipy's default filter (beta 5) left images whose second derivative was 86 % of a
    7 Hz line's sampled at 200 Hz."""
    from scipy import signal

    ratio = resample_ratio(float(time[1] - time[0]), h)
    if ratio is None:
        raise ValueError(
            f"payload.time_step_s: {h} s is not a rational fraction of the input's step {time[1] - time[0]} s"
        )
    up, down = ratio.numerator, ratio.denominator
    taps = signal.firwin(2 * 40 * max(up, down) + 1, 0.9 / max(up, down), window=("kaiser", 12.0))
    series = np.vstack([mount.translation, mount.rotation])
    out = signal.resample_poly(series, up, down, axis=1, window=taps, padtype="line")
    n = min(out.shape[1], int(math.floor(time[-1] / h + 1e-9)) + 1)
    return np.arange(n) * h, MountMotion(out[:3, :n], out[3:, :n])
