"""The six-axis isolator as an Exudyn model: one rigid body on N spring-dampers (assembly, modes and a run).

The payload is an ObjectRigidBody whose node (Tait-Bryan angles, `NodeType.RotationRxyz`: no constraint
equation) sits at the payload's reference point, with the centre of mass and inertia of `Payload`; each element
is an ObjectConnectorCartesianSpringDamper (stiffness and damping along the global axes, the mount axes at rest)
between a ground point and the body point at its position; an element's own rotational stiffness, if any, is an
ObjectConnectorRigidBodySpringDamper (rotational block only) at the same point. For the modes the mount is held
still (ground); for a run (`run`) it is a body whose coordinates follow the input. This model is the independent
check of `uavdamp.platform.six_axis`'s matrices and modes and of `uavdamp.platform.six_axis_run`'s runs.
"""

from __future__ import annotations

from dataclasses import dataclass

import exudyn as exu
import numpy as np
from exudyn.itemInterface import CoordinateConstraint, MarkerNodeCoordinate, NodePointGround, ObjectGround, SensorNode
from exudyn.utilities import RigidBodyInertia
from scipy.spatial.transform import Rotation

from uavdamp.platform.six_axis import SixAxisIsolator


@dataclass
class ExudynIsolator:
    """An assembled model: the system container (kept alive with the system), the system and the body."""

    system_container: exu.SystemContainer
    mbs: exu.MainSystem
    body: int
    node: int


def build(isolator: SixAxisIsolator) -> ExudynIsolator:
    """Assemble the payload on its elements (the mount held still), at rest at the reference configuration; the
    weightless isolator only (gravity 0: this check is of the elastic stiffness and the mass matrix)."""
    if isolator.gravity != 0:
        raise ValueError("platform.six_axis.gravity_m_s2: the Exudyn check builds the weightless isolator (0)")
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    p = isolator.payload
    inertia = RigidBodyInertia(
        mass=p.mass, inertiaTensor=np.asarray(p.inertia, dtype=float), com=np.asarray(p.com), inertiaTensorAtCOM=True
    )
    body = mbs.CreateRigidBody(
        referencePosition=[0.0, 0.0, 0.0], inertia=inertia, nodeType=exu.NodeType.RotationRxyz, show=False
    )
    _add_elements(mbs, isolator, mbs.AddObject(ObjectGround()), body)
    mbs.Assemble()
    node = mbs.GetObject(body)["nodeNumber"]
    return ExudynIsolator(sc, mbs, body, node)


def _add_elements(mbs, isolator: SixAxisIsolator, base: int, body: int) -> None:
    """Each element between `base` and `body` (object numbers) at its position: a CartesianSpringDamper for its
    translational stiffness and damping, and a RigidBodySpringDamper for its rotational ones where it has any."""
    for e in isolator.elements:
        ends = {"itemNumbers": [base, body], "localPosition0": list(e.position), "localPosition1": list(e.position)}
        mbs.CreateCartesianSpringDamper(**ends, stiffness=list(e.stiffness), damping=list(e.damping), show=False)
        if max(e.rotational_stiffness) > 0 or max(e.rotational_damping) > 0:
            k, c = np.zeros((6, 6)), np.zeros((6, 6))
            k[3:, 3:], c[3:, 3:] = np.diag(e.rotational_stiffness), np.diag(e.rotational_damping)
            mbs.CreateRigidBodySpringDamper(**ends, stiffness=k, damping=c, show=False)


def modes(isolator: SixAxisIsolator) -> tuple[np.ndarray, np.ndarray]:
    """Undamped natural frequencies (6,) Hz ascending and mode shapes (6, 6) (columns over the node's x, y, z
    m and Tait-Bryan angles rad, Exudyn's normalisation) by Exudyn's eigen-analysis at the rest configuration."""
    model = build(isolator)
    values, vectors = model.mbs.ComputeODE2Eigenvalues()
    values = np.asarray(values, dtype=float)
    order = np.argsort(values)
    return np.sqrt(np.abs(values[order])) / (2 * np.pi), np.asarray(vectors)[:, order]


def run(isolator: SixAxisIsolator, time, translation, rotation) -> np.ndarray:
    """The payload's coordinates (6, n) at the samples of `time` (s, uniform, from 0): translation m and Tait-Bryan
    angles rad of its node, under the mount motion translation (3, n) m and rotation vectors (3, n) rad, by Exudyn's
    implicit integrator (trapezoidal: spectral radius 1) at the samples' step. The mount is a rigid body whose six
    coordinates are held by coordinate constraints on the input, linear between samples (each step's end value
    set before the step); the elements join it to the payload as in `build`, their axes the global ones (to first
    order in the rotation, the mount's). The payload starts at rest relative to the mount (its velocity the
    mount's first slope): `uavdamp.platform.six_axis_run.run`'s start, for the independent check of that run."""
    t = np.asarray(time, dtype=float)
    h = float(t[1] - t[0])
    angles = Rotation.from_rotvec(np.asarray(rotation, dtype=float).T).as_euler("XYZ")  # the node's Rxyz angles
    u = np.column_stack([np.asarray(translation, dtype=float).T, angles])  # (n, 6)
    slope0 = (u[1] - u[0]) / h
    model = _two_bodies(isolator, u[0], slope0)
    mbs = model.mbs
    ground = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0))
    held = [
        mbs.AddObject(
            CoordinateConstraint(
                markerNumbers=[ground, mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=model.mount, coordinate=k))],
                offset=float(u[0, k]),
            )
        )
        for k in range(6)
    ]
    sensor = mbs.AddSensor(
        SensorNode(nodeNumber=model.node, storeInternal=True, outputVariableType=exu.OutputVariableType.Coordinates)
    )

    def pre_step(mbs_, t_end: float) -> bool:
        row = u[min(int(round(t_end / h)), len(u) - 1)]
        for k, constraint in enumerate(held):
            mbs_.SetObjectParameter(constraint, "offset", float(row[k]))
        return True

    mbs.SetPreStepUserFunction(pre_step)
    mbs.Assemble()
    ss = exu.SimulationSettings()
    ss.timeIntegration.endTime = h * (t.size - 1)
    ss.timeIntegration.numberOfSteps = t.size - 1
    ss.timeIntegration.verboseMode = 0
    ss.timeIntegration.generalizedAlpha.spectralRadius = 1.0
    ss.timeIntegration.newton.relativeTolerance = 1e-10
    ss.solution.file.write = False
    ss.solution.sensors.writePeriod = h
    mbs.SolveDynamic(ss)
    data = np.asarray(mbs.GetSensorStoredData(sensor))
    return data[: t.size, 1:7].T


@dataclass
class _Pair:
    mbs: exu.MainSystem
    system_container: exu.SystemContainer
    node: int  # the payload's node
    mount: int  # the mount's node


def _two_bodies(isolator: SixAxisIsolator, u0: np.ndarray, v0: np.ndarray) -> _Pair:
    """The payload and a 1 kg mount body (its motion is prescribed, its mass changes nothing) joined by the
    elements, both at u0 (m, rad) moving at v0 (m s-1, rad s-1)."""
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    p = isolator.payload
    bodies = []
    for inertia in (
        RigidBodyInertia(
            mass=p.mass, inertiaTensor=np.asarray(p.inertia), com=np.asarray(p.com), inertiaTensorAtCOM=True
        ),
        RigidBodyInertia(mass=1.0, inertiaTensor=np.eye(3) * 1e-2),
    ):
        bodies.append(
            mbs.CreateRigidBody(
                referencePosition=[0.0, 0.0, 0.0],
                initialDisplacement=list(u0[:3]),
                initialRotationMatrix=Rotation.from_euler("XYZ", u0[3:]).as_matrix().tolist(),
                initialVelocity=list(v0[:3]),
                initialAngularVelocity=list(_angular_velocity(u0[3:], v0[3:])),
                inertia=inertia,
                nodeType=exu.NodeType.RotationRxyz,
                show=False,
            )
        )
    payload, mount = bodies
    _add_elements(mbs, isolator, mount, payload)
    node = mbs.GetObject(payload)["nodeNumber"]
    return _Pair(mbs, sc, node, mbs.GetObject(mount)["nodeNumber"])


def _angular_velocity(angles: np.ndarray, rates: np.ndarray) -> np.ndarray:
    """Angular velocity (global) of Tait-Bryan XYZ angles and their rates: the columns R_x e_y and R_x R_y e_z."""
    rx = Rotation.from_euler("X", angles[0]).as_matrix()
    rxy = rx @ Rotation.from_euler("Y", angles[1]).as_matrix()
    return np.array([1.0, 0.0, 0.0]) * rates[0] + rx[:, 1] * rates[1] + rxy[:, 2] * rates[2]
