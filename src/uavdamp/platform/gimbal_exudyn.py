"""The gimbal as a nested three-body mechanism in Exudyn under the same sampled cascade: the linear run's check.

Model. A base body (`NodeType.RotationRxyz`, 1 kg: its motion is prescribed, its mass changes nothing) carries the
stabilised axes of `GimbalParams` nested as `uavdamp.platform.gimbal.CHAIN`: a yaw frame on the base (revolute
about z), a roll frame on it (revolute about x), the pitch body (pitch cradle + camera) on that (revolute about
y); an axis left out of `axes` has no joint, and the camera then sits on the innermost frame. Every body is an
ObjectRigidBody (RotationRxyz node) at the axes' intersection (the origin), every joint an ObjectJointRevoluteZ
(`CreateRevoluteJoint`) through it. Inertias: each frame's row of `bracket_inertia` (diagonal, about the
intersection); the camera box (`uavdamp.platform.gimbal.camera_inertia`) about its centre at `imbalance_m` on
the innermost body; each bracket a stated mass `BRACKET_MASS` at the intersection (choice: a point the joints hold
still, so it adds no moment and changes nothing in the motion). Per joint an ObjectConnectorTorsionalSpringDamper
(`CreateTorsionalSpringDamper`) about the joint's axis: the friction c on the joint's relative rate, the cable
stiffness k on its relative angle and the motor torque tau (its `torque` parameter, set to -tau: Exudyn's sign,
a positive parameter turns the inner body negatively), action on the inner body, reaction on the outer, as in
`uavdamp.platform.gimbal.axis_model`. Exudyn integrates the full rigid-body equations: products of inertia,
gyroscopic terms and the joints' changing geometry, all of which the linear per-axis model leaves out.

Base motion (choices). The base starts at the neutral pose (`rotation` 0 at the first sample, else ValueError) at
the input's rate; its three Tait-Bryan angles are held at velocity level (CoordinateConstraints) on the rates
that `rate`, the global angular velocity linear between samples, gives: the trapezoidal rule integrates the
attitude from them (`rotation` is not read after the start). The base does not translate: the intersection's
acceleration a (linear between samples) enters exactly as the uniform field -a of the frame translating with that
point, added to gravity (along -z): a LoadMassProportional (-a - g e_z) per unit mass on every gimbal body. Start
as `uavdamp.platform.gimbal_sim`: the camera at rest on the line of sight 0, every frame turning with the base
about the axes outside it and at rest about its own and the inner ones.

Sensors and control, every loop period T, as `uavdamp.platform.gimbal_sim` with sensor_errors=False: the gyro is
the camera body's angular velocity in its own axes (x, y, z: roll, pitch, yaw), the accelerometer the specific
force at the intersection in camera axes, f = R^T (a + g e_z), R the camera's attitude; each of the six channels
passes the IMU's continuous low-pass (`uavdamp.platform.imu.lowpass`) integrated beside Exudyn by its exact map for
an input linear over each solver step (first-order hold on the solver's samples), at rest on the first value.
Tilt roll = atan2(f_y, f_z), pitch = atan2(-f_x, f_z) (`uavdamp.platform.imu.tilt`, f_z the camera's where
`gimbal_sim` reads the base's vertical: equal to second order in the angles), noiseless readings
(`ImuParams.noiseless`, `read_scalar`: no bias, quantisation or clipping), then
`cascade_step` (the compiled loop's arithmetic, written apart), the same start (integral and first torque the
static imbalance torque, estimate 0) and one loop period of delay.

Integration (choices). Exudyn's implicit trapezoidal rule (Newmark beta 1/4, gamma 1/2: no numerical damping)
with velocity-level (index 2) joint constraints at a fixed step that divides the input's, by default the largest
at or below T / 10 (`step`). One solve per loop period, each starting from the last one's state
(`updateInitialValues`) with the accelerations recomputed under the new torque: carried across the torque's jump,
the trapezoidal rule averages the old and new torque over the first step, a lag of half a step (measured: 2 % of
the line of sight at 80 Hz with T / 10, first order in the step); restarted, the gap is second order in the step.
The base's rates and the field are set before each step (pre-step function), the filters advanced after it
(post-step function, which Exudyn also calls at each solve's start: skipped there). Output: the line of sight
about each stabilised axis is that component of the camera's rotation vector (to first order `gimbal_sim`'s
angle).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import exudyn as exu
import numpy as np
import xarray as xr
from exudyn.itemInterface import (
    CoordinateConstraint,
    LoadMassProportional,
    MarkerBodyMass,
    MarkerNodeCoordinate,
    NodePointGround,
)
from exudyn.utilities import RigidBodyInertia

from uavdamp.platform.gimbal import AXES, CHAIN, AxisGains, GimbalParams, camera_inertia, design, imbalance_torque
from uavdamp.platform.gimbal_sim import loop_grid, run_dataset
from uavdamp.platform.imu import lowpass, read_scalar, tilt
from uavdamp.platform.statespace import StateSpace, discretise

BRACKET_MASS = 0.05  # kg, each bracket's, at the axes' intersection (choice; it changes nothing there)
UNIT = {"roll": [1.0, 0.0, 0.0], "pitch": [0.0, 1.0, 0.0], "yaw": [0.0, 0.0, 1.0]}


@dataclass
class ExudynGimbal:
    """An assembled gimbal: the system container (kept alive with the system), the system, the base's node and
    its six rate constraints, the camera's node, each stabilised axis's spring-damper and the field loads."""

    system_container: exu.SystemContainer
    mbs: exu.MainSystem
    base_node: int
    base_constraints: list
    camera_node: int
    joints: dict
    loads: list


def build(p: GimbalParams, base_rate0) -> ExudynGimbal:
    """The base at the neutral pose turning at base_rate0 (3,) rad s-1 (global) and the nested gimbal of the
    module docstring, the camera at rest; not assembled (the run adds its user functions first)."""
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    w0 = np.asarray(base_rate0, dtype=float)
    base = mbs.CreateRigidBody(
        referencePosition=[0.0, 0.0, 0.0],
        initialAngularVelocity=list(w0),
        inertia=RigidBodyInertia(mass=1.0, inertiaTensor=np.eye(3) * 1e-2),
        nodeType=exu.NodeType.RotationRxyz,
        show=False,
    )
    base_node = mbs.GetObject(base)["nodeNumber"]
    ground = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0))
    constraints = [
        mbs.AddObject(
            CoordinateConstraint(
                markerNumbers=[ground, mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=base_node, coordinate=k))],
                offset=float(w0[k - 3]) if k >= 3 else 0.0,
                velocityLevel=True,
            )
        )
        for k in range(6)
    ]
    chain = [a for a in reversed(CHAIN) if a in p.axes]  # outermost first
    outer, joints, loads, rate = base, {}, [], w0.copy()
    for n, axis in enumerate(chain):
        rate[AXES.index(axis)] = 0.0  # at rest about its own axis (and, from the outer frames, those outside)
        row = np.diag(p.bracket_inertia[CHAIN.index(axis)])
        inertia = RigidBodyInertia(mass=BRACKET_MASS, inertiaTensor=row)
        if n == len(chain) - 1:  # the innermost carries the camera
            inertia = inertia + RigidBodyInertia(
                mass=p.camera_mass,
                inertiaTensor=np.diag(camera_inertia(p)),
                com=np.asarray(p.imbalance_m, dtype=float),
                inertiaTensorAtCOM=True,
            )
        body = mbs.CreateRigidBody(
            referencePosition=[0.0, 0.0, 0.0],
            initialAngularVelocity=list(rate),
            inertia=inertia,
            nodeType=exu.NodeType.RotationRxyz,
            show=False,
        )
        ends = {"itemNumbers": [outer, body], "position": [0.0, 0.0, 0.0], "axis": UNIT[axis], "show": False}
        mbs.CreateRevoluteJoint(**ends)
        joints[axis] = mbs.CreateTorsionalSpringDamper(
            **ends, stiffness=p.cable_stiffness, damping=p.friction, unlimitedRotations=False
        )
        loads.append(mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=body)))))
        outer = body
    camera_node = mbs.GetObject(outer)["nodeNumber"]
    return ExudynGimbal(sc, mbs, base_node, constraints, camera_node, joints, loads)


def tait_bryan_rates(rotation: np.ndarray, rate: np.ndarray) -> np.ndarray:
    """Rates (3, n) rad s-1 of the Tait-Bryan XYZ angles (R = R_x R_y R_z, the RotationRxyz node's) of the
    rotation vectors `rotation` (3, n) rad turning at the global angular velocity `rate` (3, n) rad s-1."""
    r = np.asarray(rotation, dtype=float)
    phi = np.sqrt(np.sum(r * r, axis=0))
    small = phi < 1e-4
    safe = np.where(small, 1.0, phi)
    s = np.where(small, 1.0 - phi**2 / 6.0, np.sin(safe) / safe)  # Rodrigues: R = I + s K + c K^2, K = skew(r)
    c = np.where(small, 0.5 - phi**2 / 24.0, (1.0 - np.cos(safe)) / safe**2)
    r02 = s * r[1] + c * r[0] * r[2]
    r12 = -s * r[0] + c * r[1] * r[2]
    r22 = 1.0 + c * (r[2] ** 2 - phi**2)
    a, b = np.arctan2(-r12, r22), np.arcsin(np.clip(r02, -1.0, 1.0))  # R_02 = sin b, R_12 = -sin a cos b
    w = np.asarray(rate, dtype=float)
    sa, ca, cb, tb = np.sin(a), np.cos(a), np.cos(b), np.tan(b)
    return np.stack([w[0] + sa * tb * w[1] - ca * tb * w[2], ca * w[1] + sa * w[2], (-sa * w[1] + ca * w[2]) / cb])


def rotation_vectors(matrices: np.ndarray) -> np.ndarray:
    """Rotation vectors (3, n) rad of rotation matrices (n, 3, 3): the axis of the antisymmetric part times the
    angle atan2(|axial|, (trace - 1) / 2) (accurate at small angles)."""
    m = np.asarray(matrices, dtype=float)
    v = 0.5 * np.stack([m[:, 2, 1] - m[:, 1, 2], m[:, 0, 2] - m[:, 2, 0], m[:, 1, 0] - m[:, 0, 1]])
    sine = np.sqrt(np.sum(v * v, axis=0))
    angle = np.arctan2(sine, 0.5 * (np.trace(m, axis1=1, axis2=2) - 1.0))
    return v * np.where(sine > 0, angle / np.where(sine > 0, sine, 1.0), 1.0)


def _default_step(h: float, period: float) -> float:
    """The largest divisor of the input's step h (s) at or below period / 10."""
    return h / math.ceil(h / (0.1 * period) - 1e-9)


def _fine(x: np.ndarray, sub: int) -> np.ndarray:
    """x (3, n) linear between its samples, at sub points per step."""
    n = x.shape[1]
    t_fine = np.arange((n - 1) * sub + 1) / sub
    return np.stack([np.interp(t_fine, np.arange(n), row) for row in x])


def run(
    p: GimbalParams,
    time,
    rotation,
    rate,
    acceleration,
    *,
    gains: dict[str, AxisGains] | None = None,
    step: float | None = None,
) -> xr.Dataset:
    """Run the Exudyn gimbal of `p` on a base moving with `rotation` (3, n) rad (rotation vector, 0 at the start),
    `rate` (3, n) rad s-1 and `acceleration` (3, n) m s-2 (inertial frame: x forward, y left, z up) on the
    uniform grid `time` (s), as `uavdamp.platform.gimbal_sim.simulate` with sensor_errors=False. gains: default
    `design(p)`; step: Exudyn's fixed step, s (it must divide the grid's; default the module docstring's).
    Returns line_of_sight and motor_torque (axis, time), the layout and units of `simulate`'s."""
    rotation, rate, acceleration = (np.asarray(x, dtype=float) for x in (rotation, rate, acceleration))
    h, m = loop_grid(time, p.period, {"rotation": rotation, "rate": rate, "acceleration": acceleration})
    if np.any(rotation[:, 0] != 0):
        raise ValueError("rotation must be 0 at the first sample (the base starts at the neutral pose)")
    h_e = _default_step(h, p.period) if step is None else float(step)
    sub = round(h / h_e)
    if sub < 1 or abs(sub * h_e - h) > 1e-9 * h:
        raise ValueError(f"step ({h_e} s) must divide the time step ({h} s)")
    gains = design(p) if gains is None else gains
    imu, axes, n = p.imu.noiseless(), p.stabilised, rotation.shape[1]
    per_loop, n_steps = m * sub, (n - 1) * sub
    angle_rates = _fine(tait_bryan_rates(rotation, rate), sub)
    accel = _fine(acceleration, sub)
    field = -accel - np.array([0.0, 0.0, p.gravity])[:, None]  # m s-2: the field on the translating frame
    model = build(p, rate[:, 0])
    mbs = model.mbs

    af, bf, cf = lowpass(imu)
    filt = discretise(StateSpace(af, np.hstack([bf, 0 * bf]), cf, np.zeros((1, 1)), np.zeros((1, 1))), h_e)
    rest = -np.linalg.solve(af, bf)  # filter state at rest per unit input
    hold = {a: -float(imbalance_torque(p, a, acceleration[:, 0] + [0.0, 0.0, p.gravity])) for a in axes}
    s = {"i": 0, "x": None, "u": None, "integral": dict(hold), "estimate": dict.fromkeys(axes, 0.0)}
    s["applied"], s["held"] = dict(hold), dict(hold)
    matrices, held = np.empty((n, 3, 3)), []

    def sense(i: int) -> np.ndarray:
        """The camera's rotation matrix and the six sensor inputs (gyro x, y, z; f x, y, z) at solver step i."""
        r = np.asarray(mbs.GetNodeOutput(model.camera_node, exu.OutputVariableType.RotationMatrix)).reshape(3, 3)
        w = mbs.GetNodeOutput(model.camera_node, exu.OutputVariableType.AngularVelocityLocal)
        return r, np.concatenate([w, -r.T @ field[:, i]])

    def post_step(mbs_, t: float) -> bool:
        """The filters advanced to the step's end i (first-order hold on the solver's samples), recorded; Exudyn
        calls it at each solve's start too (nothing to do there)."""
        i = int(round(t / h_e))
        if i == s["i"]:
            return True
        s["i"] = i
        r, u = sense(i)
        s["x"] = filt.phi @ s["x"] + filt.gamma_u * s["u"] + filt.gamma_v * ((u - s["u"]) / h_e)
        s["u"] = u
        if i % sub == 0:
            matrices[i // sub] = r
        return True

    def pre_step(mbs_, t_end: float) -> bool:
        """The base's rates and the field at the step's end."""
        i = int(round(t_end / h_e))
        for k in range(3):
            mbs_.SetObjectParameter(model.base_constraints[3 + k], "offset", float(angle_rates[k, i]))
        for load in model.loads:  # per unit mass
            mbs_.SetLoadParameter(load, "loadVector", list(field[:, i]))
        return True

    mbs.SetPreStepUserFunction(pre_step)
    mbs.SetPostStepUserFunction(post_step)
    mbs.Assemble()
    pre_step(mbs, 0.0)
    matrices[0], s["u"] = sense(0)
    s["x"] = rest * s["u"]
    ss = exu.SimulationSettings()
    ss.timeIntegration.verboseMode = 0
    ss.timeIntegration.generalizedAlpha.useNewmark = True  # beta 1/4, gamma 1/2: the trapezoidal rule
    ss.timeIntegration.generalizedAlpha.useIndex2Constraints = True
    ss.timeIntegration.newton.relativeTolerance = 1e-10
    ss.solution.file.write = False
    for start in range(0, n_steps, per_loop):  # one solve per loop period: it starts from the new torque
        _control(p, imu, gains, axes, model, s, cf[0] @ s["x"])
        held.append([s["held"][a] for a in axes])
        steps = min(per_loop, n_steps - start)
        ss.timeIntegration.startTime = start * h_e
        ss.timeIntegration.endTime = (start + steps) * h_e
        ss.timeIntegration.numberOfSteps = steps
        mbs.SolveDynamic(ss, updateInitialValues=True)
    if n_steps % per_loop == 0:  # the last sample is a loop sample: its torque is the last demand
        held.append([s["applied"][a] for a in axes])
    torque = np.repeat(np.asarray(held).T, m, axis=1)[:, :n]
    return _dataset(p, np.asarray(time, dtype=float), axes, rotation_vectors(matrices), torque)


def _control(p: GimbalParams, imu, gains: dict, axes, model: ExudynGimbal, s: dict, y: np.ndarray) -> None:
    """One loop sample: each axis's torque of the last demand applied now, the new demand from the readings y
    (gyro x, y, z rad s-1; f x, y, z m s-2) for the next sample (`gimbal_sim`'s order and arithmetic)."""
    f = [read_scalar(y[3 + k], imu.accel_bias[k], imu.accel_step, imu.accel_range) for k in range(3)]
    roll_tilt, pitch_tilt = tilt(np.asarray(f))
    tilts = {"roll": float(roll_tilt), "pitch": float(pitch_tilt), "yaw": 0.0}
    for axis in axes:
        i = AXES.index(axis)
        s["held"][axis] = s["applied"][axis]
        model.mbs.SetObjectParameter(model.joints[axis], "torque", -s["held"][axis])  # Exudyn's sign: -tau
        gyro = read_scalar(y[i], imu.gyro_bias[i], imu.gyro_step, imu.gyro_range)
        s["estimate"][axis], s["integral"][axis], s["applied"][axis], _ = cascade_step(
            gains[axis], s["estimate"][axis], s["integral"][axis], gyro, tilts[axis], p.torque_limit, p.period
        )


def cascade_step(g: AxisGains, estimate: float, integral: float, gyro: float, tilt: float, limit: float, period: float):
    """One loop sample of an axis's cascade from its readings (gyro rad s-1, accelerometer tilt rad), in Python
    floats: the estimate updated, the attitude P and the rate PI, the integral held while the demand saturates;
    returns (estimate rad, integral N m, the demand clipped to +/- limit N m, saturated). Period s. The compiled
    loop of `gimbal_sim` (`uavdamp.platform.gimbal_cascade`) is the same arithmetic, written apart."""
    estimate = g.estimator.update(estimate, gyro, tilt)
    error = -g.ka * estimate - gyro
    candidate = integral + g.ki * period * error
    demand = g.kp * error + candidate
    saturated = abs(demand) > limit
    return estimate, integral if saturated else candidate, min(max(demand, -limit), limit), saturated


def _dataset(p: GimbalParams, time: np.ndarray, axes, rotvec: np.ndarray, torque: np.ndarray) -> xr.Dataset:
    series = {"line_of_sight": rotvec[[AXES.index(a) for a in axes]], "motor_torque": torque}
    return run_dataset(p, time, axes, series, "Gyro-stabilised gimbal on a moving base: Exudyn multibody check")
