"""The camera platform as one Exudyn kinematic tree in minimal coordinates (assembly only, no solving).

From the fuselage outwards:

    mount x, y, z       prismatic, massless, prescribed by coordinate constraints (the mount's translation)
    mount rx, ry, rz    revolute about x, then y, then z (intrinsic X-Y-Z angles of the mount's rotation),
                        massless, prescribed: the isolator frame moves and rotates with the mount
    isolator y, z       prismatic, spring K and damper C (the tree's PD control); the base (base_mass) rides on it
    displacement        prismatic z between base and intermediate body, spring only: the structural
                        flexibility (the paper's "spring-mass system")
    yaw                 revolute z, intermediate body (yaw servo); PID on the angle
    pitch               revolute y, pitch body + 0.9 kg camera (pitch servo); PID on the angle

Axes: x forward (camera line of sight), y lateral, z up. Gravity (``platform.gravity_m_s2``, along -z of the
inertial frame) acts on every body; the coordinates are taken about the static equilibrium of the level mount: a
constant joint force on every free joint (`static_forces`) carries the weight there (the isolator's preload or its
spring's static sag, the structural spring's static deflection and the pitch servo's held integral term: linear
springs, so the dynamics about the equilibrium are the same; the sag is reported apart, `uavdamp.platform.stroke`).
What gravity does beyond that stays in the model: the pitch link's pendulum stiffness -m g z_c (compensated in the
servo's design, `design.design_stiffness`) and the weight's turn with the mount's rotation. Variants:
``mount="rigid"`` drops the isolator (the base follows the fuselage), ``body="lumped"`` replaces the platform by
one mass on the isolator (SDOF checks), ``clamped=True`` drops mount and isolator (base fixed: the platform's own
modes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import exudyn as exu
import numpy as np
from exudyn.itemInterface import (
    CoordinateConstraint,
    MarkerNodeCoordinate,
    NodeGenericODE2,
    NodePointGround,
    ObjectKinematicTree,
    SensorKinematicTree,
    SensorNode,
)
from scipy.spatial.transform import Rotation

from uavdamp.contract import MOUNTS, MountMotion
from uavdamp.platform.design import COORDINATES, design_stiffness, mass_matrix, pitch_link
from uavdamp.platform.params import PlatformParams

BODIES = ("full", "lumped")
MOUNT_LINKS = ("mount_x", "mount_y", "mount_z", "mount_rx", "mount_ry", "mount_rz")
MOUNT_JOINTS = (
    exu.JointType.PrismaticX,
    exu.JointType.PrismaticY,
    exu.JointType.PrismaticZ,
    exu.JointType.RevoluteX,
    exu.JointType.RevoluteY,
    exu.JointType.RevoluteZ,
)


def mount_coordinates(mount: MountMotion) -> np.ndarray:
    """The mount links' coordinates (n, 6) of a mount motion: translation x, y, z (m), then the intrinsic X-Y-Z
    angles (rad) of the rotation R = Rx Ry Rz that its rotation vector gives (exact)."""
    angles = Rotation.from_rotvec(np.asarray(mount.rotation, dtype=float).T).as_euler("XYZ")
    return np.column_stack([np.asarray(mount.translation, dtype=float).T, angles])


@dataclass(frozen=True)
class _Link:
    joint: object  # exu.JointType
    mass: float = 0.0
    com: tuple = (0.0, 0.0, 0.0)
    inertia: np.ndarray | None = None


@dataclass
class PlatformModel:
    """An assembled platform: the Exudyn system and what a plant or a linearisation needs of it.

    link_index: tree coordinate index by name (mount_y, mount_z, iso_y, iso_z, displacement, yaw, pitch, as
    present); pvec, dvec: the joint P (N m-1 or N m rad-1) and D terms as built (isolator: default K, no C);
    servo_ki: the servos' I gains per coordinate (0 where none); camera_local: the camera point in the last
    link's frame, m; q0: ODE2 index of the tree's first coordinate; sensors: camera position, coordinates and
    their rates (absent when clamped); constraints: the mount y and z coordinate constraints.
    """

    params: PlatformParams
    mount: str
    body: str
    clamped: bool
    system_container: exu.SystemContainer
    mbs: exu.MainSystem
    tree: int
    node: int
    link_index: dict[str, int]
    n: int
    q0: int
    pvec: np.ndarray
    dvec: np.ndarray
    servo_ki: np.ndarray
    joint_stiffness: np.ndarray
    camera_local: np.ndarray
    static_forces: np.ndarray | None = None
    constraints: list[int] = field(default_factory=list)
    sensors: dict[str, int] = field(default_factory=dict)


def _chain(p: PlatformParams, mount: str, body: str, clamped: bool, lumped_mass: float | None):
    """Links of the kinematic tree from the fuselage out, their indices by name, camera point in the last link."""
    s = p.structure
    links: list[_Link] = []
    idx: dict[str, int] = {}

    def add(name, link):
        idx[name] = len(links)
        links.append(link)

    base_mass = (lumped_mass or s.total_mass) if body == "lumped" else s.base_mass
    no_rotation = np.zeros((3, 3))  # the base's own rotational inertia is left out (its rotation is prescribed)
    if not clamped:
        for name, joint in zip(MOUNT_LINKS, MOUNT_JOINTS, strict=True):
            last = name == MOUNT_LINKS[-1] and mount == "rigid"
            add(name, _Link(joint, base_mass, inertia=no_rotation) if last else _Link(joint))
        if mount == "isolated":
            add("iso_y", _Link(exu.JointType.PrismaticY))
            add("iso_z", _Link(exu.JointType.PrismaticZ, base_mass, inertia=no_rotation))
    if body == "lumped":
        return links, idx, np.zeros(3)
    m_pl, com_pl, inertia_pl = pitch_link(s)
    add("displacement", _Link(exu.JointType.PrismaticZ))
    add("yaw", _Link(exu.JointType.RevoluteZ, s.intermediate_mass, inertia=s.intermediate_yaw_inertia * np.eye(3)))
    add("pitch", _Link(exu.JointType.RevoluteY, m_pl, tuple(com_pl), inertia_pl))
    return links, idx, np.array([s.camera_com_x, 0.0, s.camera_com_z])


def _control_terms(p: PlatformParams, idx: dict, n: int, body: str, clamped: bool):
    """Joint P, D and servo I vectors: structural spring and damping, servo P/D/I, the isolator's default K."""
    pvec, dvec, servo_ki = np.zeros(n), np.zeros(n), np.zeros(n)
    k_joint = design_stiffness(p.structure)
    servo_p = design_stiffness(p.structure, gravity=p.gravity)  # the pitch gain holds the pendulum term too
    if body == "full":
        mdiag = np.diag(mass_matrix(p.structure))
        s = p.structure
        zetas = (s.structural_damping_ratio, s.servo_damping_ratio, s.servo_damping_ratio)
        for name, k, kp, m, zeta in zip(COORDINATES, k_joint, servo_p, mdiag, zetas, strict=True):
            pvec[idx[name]] = kp
            if not clamped:  # clamped: the undamped platform (D and I terms off)
                dvec[idx[name]] = 2 * zeta * math.sqrt(k * m)
                if name != "displacement":
                    servo_ki[idx[name]] = k / s.servo_integral_time
    if "iso_y" in idx:  # until a run sets them: the default K (so that an eigen-analysis sees it), no damping
        pvec[idx["iso_y"]] = pvec[idx["iso_z"]] = p.isolator_stiffness
    return pvec, dvec, servo_ki, servo_p


def build(
    p: PlatformParams,
    *,
    mount: str = "isolated",
    body: str = "full",
    lumped_mass: float | None = None,
    clamped: bool = False,
) -> PlatformModel:
    """Assemble the platform `p` (see the module docstring)."""
    if mount not in MOUNTS:
        raise ValueError(f"mount must be one of {MOUNTS}, got {mount!r}")
    if body not in BODIES:
        raise ValueError(f"body must be one of {BODIES}, got {body!r}")
    if lumped_mass is not None and not lumped_mass > 0:
        raise ValueError(f"lumped_mass must be > 0, got {lumped_mass}")
    if clamped and body != "full":
        raise ValueError("clamped=True needs body='full'")
    links, idx, camera_local = _chain(p, mount, body, clamped, lumped_mass)
    n = len(links)
    pvec, dvec, servo_ki, k_joint = _control_terms(p, idx, n, body, clamped)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    zeros = [0.0] * n
    node = mbs.AddNode(
        NodeGenericODE2(
            referenceCoordinates=zeros, initialCoordinates=zeros, initialCoordinates_t=zeros, numberOfODE2Coordinates=n
        )
    )
    tree = mbs.AddObject(
        ObjectKinematicTree(
            nodeNumber=node,
            jointTypes=[link.joint for link in links],
            linkParents=list(range(-1, n - 1)),
            jointTransformations=exu.Matrix3DList([np.eye(3)] * n),
            jointOffsets=exu.Vector3DList([[0.0, 0.0, 0.0]] * n),
            linkInertiasCOM=exu.Matrix3DList(
                [lk.inertia if lk.inertia is not None else np.zeros((3, 3)) for lk in links]
            ),
            linkCOMs=exu.Vector3DList([list(lk.com) for lk in links]),
            linkMasses=[lk.mass for lk in links],
            gravity=[0.0, 0.0, -p.gravity],
            jointForceVector=zeros,
            jointPositionOffsetVector=zeros,
            jointVelocityOffsetVector=zeros,
            jointPControlVector=pvec.tolist(),
            jointDControlVector=dvec.tolist(),
        )
    )
    model = PlatformModel(
        p, mount, body, clamped, sc, mbs, tree, node, idx, n, 0, pvec, dvec, servo_ki, k_joint, camera_local
    )
    if not clamped:
        _add_mount_and_sensors(model)
    mbs.Assemble()
    model.q0 = mbs.GetNodeODE2Index(node)
    model.static_forces = static_forces(model)
    return model


def static_forces(model: PlatformModel) -> np.ndarray:
    """Joint forces (N or N m per tree coordinate) that hold every free joint at rest at q = 0 against gravity:
    minus the generalized gravity forces there (Exudyn's ODE2 right-hand side at rest with no joint force), zero on
    the prescribed mount coordinates (their constraints carry them)."""
    mbs, n = model.mbs, model.n
    zeros = np.zeros(mbs.systemData.ODE2Size())
    for config in (exu.ConfigurationType.Initial, exu.ConfigurationType.Current):
        mbs.systemData.SetODE2Coordinates(zeros, configuration=config)
        mbs.systemData.SetODE2Coordinates_t(zeros, configuration=config)
    settings = exu.SimulationSettings()
    settings.staticSolver.verboseMode = 0
    settings.solution.file.write = False  # no solution/ folder in the working directory
    solver = exu.MainSolverStatic()
    solver.InitializeSolver(mbs, settings)
    solver.ComputeODE2RHS(mbs)
    rhs = np.array(solver.GetSystemResidual(), dtype=float)[model.q0 : model.q0 + n]
    out = -rhs
    out[[model.link_index[k] for k in MOUNT_LINKS if k in model.link_index]] = 0.0
    return out


def _add_mount_and_sensors(model: PlatformModel) -> None:
    """Coordinate constraints on the mount coordinates; in-memory sensors of the camera point and the state."""
    mbs, idx = model.mbs, model.link_index
    ground = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0))
    for name in MOUNT_LINKS:
        marker = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=model.node, coordinate=idx[name]))
        model.constraints.append(mbs.AddObject(CoordinateConstraint(markerNumbers=[ground, marker])))
    stored = {"storeInternal": True, "writeToFile": False}  # in memory, no files
    base = idx["iso_z"] if "iso_z" in idx else idx[MOUNT_LINKS[-1]]
    for name, link, local, kind in (
        ("camera", model.n - 1, model.camera_local, exu.OutputVariableType.Position),
        ("camera_rotation", model.n - 1, np.zeros(3), exu.OutputVariableType.RotationMatrix),
        ("base", base, np.zeros(3), exu.OutputVariableType.Position),
    ):
        model.sensors[name] = mbs.AddSensor(
            SensorKinematicTree(
                objectNumber=model.tree,
                linkNumber=link,
                localPosition=np.asarray(local, dtype=float).tolist(),
                outputVariableType=kind,
                **stored,
            )
        )
    for name, kind in (
        ("coordinates", exu.OutputVariableType.Coordinates),
        ("rates", exu.OutputVariableType.Coordinates_t),
    ):
        model.sensors[name] = mbs.AddSensor(SensorNode(nodeNumber=model.node, outputVariableType=kind, **stored))
