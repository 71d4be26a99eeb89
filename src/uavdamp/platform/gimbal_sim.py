"""The stabilised gimbal on a moving base in the time domain: continuous axes, sampled IMU, discrete cascade.

Each stabilised axis is the continuous model of `uavdamp.platform.gimbal` (camera, friction, cable, imbalance,
the IMU's filters), exact between samples for base inputs piecewise linear on the input grid and a torque held
over each loop period. The plant is linear, so its state is the sum of the response to the base (and the
sensor noise), computed ahead on the whole grid, and the response to the torque, stepped at the loop rate with
the controller: readings (bias, quantisation, the accelerometer's tilt by atan2), the complementary filter, the
attitude P and the rate PI, the torque limit, one sample of computation delay. Integrator anti-windup (choice):
the PI's integral is held while the demand saturates. Start (choice): the camera at rest on the line of sight 0,
the integral holding the static imbalance torque, the filters at rest on the first input.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import xarray as xr

from uavdamp.platform.gimbal import (
    AXES,
    LATERAL,
    OUTPUTS,
    AxisGains,
    GimbalParams,
    axis_model,
    design,
    imbalance_torque,
)
from uavdamp.platform.gimbal_cascade import cascade
from uavdamp.platform.imu import ImuParams, lowpass, noise_covariance, read, sample_channel
from uavdamp.platform.statespace import Discrete, StateSpace, discretise, lift, propagate


def loop_grid(time: np.ndarray, period: float, series: dict[str, np.ndarray]) -> tuple[float, int]:
    """(step h s, steps per loop period) of a uniform grid; ValueError naming the bad input."""
    t = np.asarray(time, dtype=float)
    if t.ndim != 1 or t.size < 2 or not np.all(np.isfinite(t)):
        raise ValueError(f"time must be a finite 1-D array of >= 2 samples, got shape {t.shape}")
    h = float(t[1] - t[0])
    if not (h > 0 and np.ptp(np.diff(t)) <= 1e-6 * h):
        raise ValueError("time must be strictly increasing and uniform")
    m = round(period / h)
    if m < 1 or abs(m * h - period) > 1e-9 * period:
        raise ValueError(f"the loop period ({period} s) must be a whole multiple of the time step ({h} s)")
    for name, x in series.items():
        if np.shape(x) != (3, t.size) or not np.all(np.isfinite(x)):
            raise ValueError(f"{name} must be a finite (3, {t.size}) array, got shape {np.shape(x)}")
    return h, m


def _exogenous(p: GimbalParams, axis: str, rotation, rate, acceleration) -> np.ndarray:
    """The axis's base inputs (4, n): base angle, base rate, imbalance torque (static gravity part included),
    lateral specific force."""
    i = AXES.index(axis)
    force = acceleration + np.array([0.0, 0.0, p.gravity])[:, None]  # specific force a - g, g along -z
    lateral = acceleration[LATERAL[axis]] if LATERAL[axis] is not None else np.zeros(rate.shape[1])
    return np.stack([rotation[i], rate[i], imbalance_torque(p, axis, force), lateral])


def _base_response(p, imu: ImuParams, axis: str, e: np.ndarray, h: float, rng) -> tuple[np.ndarray, object]:
    """States (n, ns) of the axis driven by the base inputs e (4, n) and the sensors' noise, torque off."""
    model = axis_model(p, axis)
    ns = model.a.shape[0]
    b = model.b[:, 1:]
    plant = StateSpace(model.a, np.hstack([b, np.zeros_like(b)]), model.c, np.zeros((4, 4)), np.zeros((4, 4)))
    step = discretise(plant, h)
    forcing_u, slopes = e[:, :-1].T, np.diff(e, axis=1).T / h
    z0 = np.zeros(ns)
    af, bf, _ = lowpass(imu)
    nf = af.shape[0]
    if axis != "yaw":  # the accelerometer filter at rest on the first lateral reading
        z0[2 + nf :] = -np.linalg.solve(af, bf[:, 0]) * e[3, 0]
    noise = np.zeros((e.shape[1] - 1, ns))
    for start, density in ((2, imu.gyro_noise_density), (2 + nf, imu.accel_noise_density)):
        if density > 0 and start + nf <= ns:
            chol = np.linalg.cholesky(noise_covariance(af, bf, density, h))
            noise[:, start : start + nf] = rng.standard_normal((noise.shape[0], nf)) @ chol.T
    # the noise enters as extra forcing: a third input block with unit gain on the noisy states
    step = Discrete(step.phi, np.hstack([step.gamma_u, np.eye(ns)]), np.hstack([step.gamma_v, np.zeros((ns, ns))]))
    u = np.hstack([forcing_u, noise])
    v = np.hstack([slopes, np.zeros_like(noise)])
    return propagate(step, z0, u, v, lift(step.phi)), model


def _torque_steps(model, h: float, period: float) -> tuple[Discrete, Discrete]:
    """Torque (held) step maps over one grid step h and one loop period."""
    b = model.b[:, :1]
    plant = StateSpace(model.a, np.hstack([b, np.zeros_like(b)]), model.c, np.zeros((4, 1)), np.zeros((4, 1)))
    return discretise(plant, h), discretise(plant, period)


def simulate(
    p: GimbalParams,
    time,
    rotation,
    rate,
    acceleration,
    *,
    gains: dict[str, AxisGains] | None = None,
    sensor_errors: bool = True,
    rng: np.random.Generator | None = None,
) -> xr.Dataset:
    """Run the stabilised axes of `p` on a base moving with `rotation` (3, n) rad (rotation vector), `rate` (3, n)
    rad s-1 and linear `acceleration` (3, n) m s-2, inertial frame (x forward, y left, z up), on the uniform grid
    `time` (s; the loop period a whole multiple of its step). gains: default `design(p)`; sensor_errors False:
    the IMU without noise, bias and quantisation; rng: the noise's generator (default seed 0)."""
    rng = np.random.default_rng(0) if rng is None else rng
    (ds,) = simulate_many(p, time, [(rotation, rate, acceleration)], gains=gains, sensor_errors=sensor_errors,
                          rngs=[rng])  # fmt: skip
    return ds


def simulate_many(
    p: GimbalParams,
    time,
    bases,
    *,
    gains: dict[str, AxisGains] | None = None,
    sensor_errors: bool = True,
    rngs,
) -> list[xr.Dataset]:
    """`simulate` on each base motion of `bases` ((rotation, rate, acceleration) each (3, n), as `simulate`'s), one
    generator of `rngs` each, the discrete cascades of all the runs stepped side by side (the same arithmetic per
    run; what a stage pays per loop sample in Python is paid once for them all)."""
    bases, rngs = list(bases), list(rngs)
    if len(bases) != len(rngs) or not bases:
        raise ValueError(f"need one generator per base motion and at least one, got {len(bases)} and {len(rngs)}")
    gains = design(p) if gains is None else gains
    imu = p.imu if sensor_errors else p.imu.noiseless()
    n, axes = np.size(time), p.stabilised
    runs = [_exogenous_run(p, imu, time, base, rng) for base, rng in zip(bases, rngs, strict=True)]
    h, m = runs[0].h, runs[0].per_loop
    loops = np.arange(0, n, m)
    out = {k: np.zeros((len(bases), len(axes), n)) for k in ("line_of_sight", "motor_torque", "attitude_estimate")}
    out["saturated"] = np.zeros((len(bases), len(axes), n), dtype=bool)
    f_z = np.stack([r.f_z for r in runs])
    for j, axis in enumerate(axes):
        model = axis_model(p, axis)
        fine, coarse = _torque_steps(model, h, p.period)
        base = np.stack([r.states[axis] for r in runs])  # (runs, n, states)
        hold = -np.array([r.static_torque[axis] for r in runs])
        held, flags, estimate = _control(p, imu, gains[axis], model, coarse, base[:, loops], f_z, hold)
        torque, lifted = np.repeat(held, m, axis=1)[:, :n], lift(fine.phi)
        for b in range(len(bases)):
            z = propagate(fine, np.zeros(model.a.shape[0]), torque[b, :-1, None], np.zeros((n - 1, 1)), lifted)
            out["line_of_sight"][b, j] = (base[b] + z) @ model.c[OUTPUTS.index("angle")]
        out["motor_torque"][:, j] = torque
        out["saturated"][:, j] = np.repeat(flags, m, axis=1)[:, :n]
        out["attitude_estimate"][:, j] = np.repeat(estimate, m, axis=1)[:, :n]
    t = np.asarray(time, dtype=float)
    return [_dataset(p, t, axes, {k: v[b] for k, v in out.items()}, m) for b in range(len(bases))]


class _Exogenous(NamedTuple):
    """One run's parts that need no controller."""

    h: float  # s, the grid's step
    per_loop: int  # grid steps per loop period
    f_z: np.ndarray  # m s-2, the vertical accelerometer's reading at each loop sample
    states: dict  # {axis: states (n, ns) driven by the base and the noise}
    static_torque: dict  # {axis: the imbalance torque at the start, N m}


def _exogenous_run(p: GimbalParams, imu: ImuParams, time, base, rng) -> _Exogenous:
    """`_Exogenous` of one run on `base` ((rotation, rate, acceleration), as `simulate`'s), noise from `rng`."""
    rotation, rate, acceleration = (np.asarray(x, dtype=float) for x in base)
    h, m = loop_grid(time, p.period, {"rotation": rotation, "rate": rate, "acceleration": acceleration})
    loops = np.arange(0, np.size(time), m)
    f_z = sample_channel(time, p.gravity + acceleration[2], imu, imu.accel_noise_density, rng)[loops]
    f_z = read(f_z, imu.accel_bias[2], imu.accel_step, imu.accel_range)
    states, e0 = {}, {}
    for axis in p.stabilised:
        e = _exogenous(p, axis, rotation, rate, acceleration)
        states[axis], _ = _base_response(p, imu, axis, e, h, rng)
        e0[axis] = e[2, 0]
    return _Exogenous(h, m, f_z, states, e0)


def _control(p, imu, g: AxisGains, model, coarse: Discrete, base_loop: np.ndarray, f_z: np.ndarray, hold):
    """The discrete cascade on one axis of each run, the runs side by side (`gimbal_cascade.cascade`, compiled):
    base_loop (runs, K, states) at the loop samples, f_z (runs, K), hold (runs,) N m. Returns (torque applied over
    each loop period, its saturation flag, the estimate), each (runs, K)."""
    i, lateral = AXES.index(g.axis), LATERAL[g.axis]
    c_gyro, c_force = model.c[OUTPUTS.index("gyro")], model.c[OUTPUTS.index("specific_force")]
    accel = (0.0, 0.0, 0.0) if lateral is None else (imu.accel_bias[lateral], imu.accel_step, imu.accel_range)
    sensors = np.array([imu.gyro_bias[i], imu.gyro_step, imu.gyro_range, *accel], dtype=float)
    gains = np.array([g.kp, g.ki, g.ka, g.estimator.alpha], dtype=float)
    held, flags, estimates = cascade(
        np.ascontiguousarray(np.swapaxes(base_loop, 0, 1), dtype=float),  # (K, runs, states)
        np.ascontiguousarray(np.asarray(f_z, dtype=float).T),
        np.asarray(hold, dtype=float),
        np.ascontiguousarray(c_gyro, dtype=float),
        np.ascontiguousarray(c_force, dtype=float),
        np.ascontiguousarray(coarse.phi.T),
        np.ascontiguousarray(coarse.gamma_u[:, 0]),
        sensors,
        {"roll": 1.0, "pitch": -1.0, "yaw": 0.0}[g.axis],
        gains,
        float(p.torque_limit),
        float(p.period),
    )
    # the flag belongs to the period its torque acts in: the demand computed at k acts over period k + 1
    flags = np.concatenate([np.zeros((1, flags.shape[1]), bool), flags[:-1]])
    return held.T, flags.T, estimates.T


VARIABLES = {  # name: (units, long_name) of a run's outputs (the Exudyn check's too)
    "line_of_sight": ("rad", "camera's inertial attitude about the axis (line of sight)"),
    "motor_torque": ("N m", "motor torque applied (zero-order hold over the loop period)"),
    "attitude_estimate": ("rad", "complementary filter's attitude estimate (held over the loop period)"),
    "torque_saturated": ("1", "1 where the applied torque is the clipped demand (the torque limit acts)"),
}


def run_dataset(p: GimbalParams, time: np.ndarray, axes, series: dict, title: str, **attrs) -> xr.Dataset:
    """A run's dataset: each series (axis, time) with its `VARIABLES` units and long name, the axis and time
    coordinates, the title, the loop's rate and torque limit and `attrs`."""
    data = {
        k: (("axis", "time"), v, dict(zip(("units", "long_name"), VARIABLES[k], strict=True)))
        for k, v in series.items()
    }
    coords = {
        "time": ("time", time, {"units": "s", "long_name": "time"}),
        "axis": ("axis", list(axes), {"units": "1", "long_name": "stabilised axis (roll x, pitch y, yaw z)"}),
    }
    attrs = {"title": title, "loop_rate_hz": p.loop_rate_hz, "torque_limit_N_m": p.torque_limit, **attrs}
    return xr.Dataset(data, coords=coords, attrs={**attrs, "frame": "inertial: x forward, y left, z up"})


def _dataset(p: GimbalParams, time: np.ndarray, axes, out: dict, m: int) -> xr.Dataset:
    flags = out.pop("saturated").astype(bool)
    series = {**out, "torque_saturated": flags.astype(np.int8)}
    ds = run_dataset(p, time, axes, series, "Gyro-stabilised gimbal on a moving base", saturated=int(flags.any()))
    ds["saturation_count"] = (
        ("axis",),
        flags[:, ::m].sum(axis=1),
        {"units": "1", "long_name": "loop samples whose torque was clipped to the limit"},
    )
    return ds
