"""Multibody rotorcraft in Exudyn: 6-DOF fuselage, articulated main rotor, two-blade tail rotor.

Frame: x forward, y left, z up; origin at the fuselage centre of mass. The whole helicopter is
one Exudyn kinematic tree in minimal coordinates:

    links 0-5  PrismaticX, PrismaticY, PrismaticZ, RevoluteX, RevoluteY, RevoluteZ (fuselage on 5)
    link 6     main hub, RevoluteZ, `hub_height` above the fuselage centre of mass
    per blade  flap (RevoluteY at the hinge offset), lag (RevoluteZ), feather (RevoluteX, the blade)
    last link  tail hub, RevoluteY at `position`, carrying the tail blades rigidly

Rotor speeds are prescribed exactly by velocity-level coordinate constraints on the hub
coordinates (relative to the fuselage), not by a penalty servo. Hinge springs and dampers are
the tree's joint PD terms. No gravity, no aerodynamics: the only excitation is a blade mass
imbalance. The fuselage starts with the velocity that makes the total linear momentum zero.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import exudyn as exu
import exudyn.itemInterface as eii
import numpy as np
import xarray as xr
from exudyn.rigidBodyUtilities import RigidBodyInertia, RotationMatrixZ, TreeLink
from scipy.spatial.transform import Rotation

from uavdamp.contract import XYZ
from uavdamp.helicopter.params import Helicopter, SolverOptions, TailRotor
from uavdamp.progress import bar

FUSELAGE_LINK = 5
HUB_LINK = 6
AXES = XYZ  # the fuselage's axes


def solver_settings(options: SolverOptions) -> exu.SimulationSettings:
    """Exudyn settings: no files, sensors kept in memory, dense linear solver (~20 coordinates)."""
    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = int(round(options.duration / options.step))
    ss.timeIntegration.endTime = options.duration
    ss.timeIntegration.verboseMode = 0
    ss.timeIntegration.generalizedAlpha.spectralRadius = options.spectral_radius
    ss.timeIntegration.newton.useModifiedNewton = True
    ss.timeIntegration.newton.relativeTolerance = options.newton_tolerance
    ss.timeIntegration.newton.absoluteTolerance = options.newton_absolute_tolerance
    ss.linearSolver.solverType = exu.LinearSolverType.EXUdense
    ss.solution.sensors.writePeriod = options.output_step
    ss.solution.file.write = False
    ss.show.computationTime = False
    return ss


def _blade_link_inertia(mass: float, length: float, inertia: tuple, scale: float = 1.0) -> RigidBodyInertia:
    """Blade inertia in its link frame (x along the blade from the hinge), kg, kg m^2.

    The paper's blade axes have y along the blade, so its (Ix, Iy, Iz) become (Iy, Ix, Iz) here.
    `scale` multiplies mass and inertia (a uniform change of density).
    """
    ix, iy, iz = inertia
    return RigidBodyInertia(
        mass=scale * mass,
        inertiaTensor=scale * np.diag([iy, ix, iz]),
        com=[length / 2, 0.0, 0.0],
        inertiaTensorAtCOM=True,
    )


def _tail_hub_inertia(tail: TailRotor) -> RigidBodyInertia:
    """Tail hub link: the tail blades rigidly attached, evenly spaced in the x-z plane."""
    ix, iy, iz = tail.blade_inertia
    total = None
    for k in range(tail.n_blades):
        psi = 2 * np.pi * k / tail.n_blades
        c, s = np.cos(psi), np.sin(psi)
        rot_y = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
        at_com = RigidBodyInertia(mass=tail.blade_mass, inertiaTensor=np.diag([iy, ix, iz]))
        blade = at_com.Rotated(rot_y).Translated(rot_y @ [tail.blade_length / 2, 0.0, 0.0])
        total = blade if total is None else total + blade
    return total


def tree_links(heli: Helicopter) -> list[TreeLink]:
    """The kinematic tree's links in order (see the module docstring)."""
    main, tail = heli.main_rotor, heli.tail_rotor
    ix, iy, iz = heli.fuselage.inertia
    ixz = heli.fuselage.inertia_xz
    tensor = np.array([[ix, 0, ixz], [0, iy, 0], [ixz, 0, iz]])
    fuselage = RigidBodyInertia(mass=heli.fuselage.mass, inertiaTensor=tensor, inertiaTensorAtCOM=True)
    none = RigidBodyInertia()
    jt = exu.JointType

    def link(inertia, joint, parent, offset=None, rotation=None, pd=None):
        ht = exu.HT(np.eye(3) if rotation is None else rotation, [0.0, 0.0, 0.0] if offset is None else list(offset))
        return TreeLink(inertia, joint, jointHT=ht, parent=parent, PDcontrol=pd, graphicsDataList=[])

    links = [
        link(none, joint, k - 1)
        for k, joint in enumerate([jt.PrismaticX, jt.PrismaticY, jt.PrismaticZ, jt.RevoluteX, jt.RevoluteY])
    ]
    links.append(link(fuselage, jt.RevoluteZ, 4))
    links.append(link(none, jt.RevoluteZ, FUSELAGE_LINK, offset=[0.0, 0.0, main.hub_height]))
    scales = heli.blade_masses() / main.blade_mass
    for k in range(main.n_blades):
        psi = 2 * np.pi * k / main.n_blades
        hinge = main.hinge_offset * np.array([np.cos(psi), np.sin(psi), 0.0])
        flap = len(links)
        links.append(
            link(
                none,
                jt.RevoluteY,
                HUB_LINK,
                offset=hinge,
                rotation=RotationMatrixZ(psi),
                pd=(main.flap_stiffness, main.flap_damping),
            )
        )
        links.append(link(none, jt.RevoluteZ, flap, pd=(main.lag_stiffness, main.lag_damping)))
        blade = _blade_link_inertia(main.blade_mass, main.blade_length, main.blade_inertia, scales[k])
        links.append(link(blade, jt.RevoluteX, flap + 1, pd=(main.feather_stiffness, main.feather_damping)))
    links.append(link(_tail_hub_inertia(tail), jt.RevoluteY, FUSELAGE_LINK, offset=tail.position))
    return links


def initial_fuselage_velocity(heli: Helicopter) -> np.ndarray:
    """Fuselage velocity, m/s, that makes the total linear momentum zero at t = 0.

    An imbalanced main rotor's centre of mass is off the shaft, so the spinning rotor carries
    momentum Omega e_z x sum(m_i r_i); the whole helicopter moves the other way to cancel it.
    The tail rotor's centre of mass lies on its shaft and adds none.
    """
    main = heli.main_rotor
    psi = 2 * np.pi * np.arange(main.n_blades) / main.n_blades
    r_com = main.hinge_offset + main.blade_length / 2
    m = heli.blade_masses()
    first_moment = r_com * np.array([np.sum(m * np.cos(psi)), np.sum(m * np.sin(psi)), 0.0])
    rotor_momentum = main.omega_rad_s * np.cross([0.0, 0.0, 1.0], first_moment)
    return -rotor_momentum / heli.total_mass()


def _initial_state(heli: Helicopter, n: int, fix_fuselage: bool) -> tuple[None, np.ndarray]:
    """(coordinates: None, the tree's default zeros; velocities): rotors at speed, the free fuselage with the
    velocity that cancels the rotor's linear momentum."""
    q_t0 = np.zeros(n)
    if not fix_fuselage:
        q_t0[:3] = initial_fuselage_velocity(heli)
    q_t0[HUB_LINK] = heli.main_rotor.omega_rad_s
    q_t0[-1] = heli.tail_rotor.omega_rad_s
    return None, q_t0


@dataclass
class Model:
    """An assembled Exudyn system and handles to its parts."""

    system_container: exu.SystemContainer
    mbs: exu.MainSystem
    node: int
    sensors: dict[str, int]
    link_masses: dict[int, float]
    constraints: dict[int, int] = field(default_factory=dict)  # tree coordinate -> its CoordinateConstraint


def build(heli: Helicopter, *, fix_fuselage: bool = False, momentum_sensors: bool = False, initial=None) -> Model:
    """Assemble the rotorcraft (no solve).

    fix_fuselage: hold the six fuselage coordinates at zero (hinged-blade eigen-analysis, the trim).
    momentum_sensors: add a velocity sensor at every massive link's centre of mass.
    initial: (coordinates, velocities) of the tree to start from instead of the spinning rotor at rest.
    """
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    links = tree_links(heli)
    q_0, q_t0 = _initial_state(heli, len(links), fix_fuselage) if initial is None else initial
    tree = mbs.CreateKinematicTree(listOfTreeLinks=links, initialCoordinates=q_0, initialCoordinates_t=q_t0, show=False)
    node = mbs.GetObject(tree)["nodeNumber"]

    ground = mbs.AddMarker(eii.MarkerNodeCoordinate(nodeNumber=mbs.AddNode(eii.NodePointGround()), coordinate=0))

    constraints = {}

    def hold(coordinate: int, speed: float | None) -> None:
        """Coordinate held at zero (speed None) or turning at `speed` rad/s exactly."""
        marker = mbs.AddMarker(eii.MarkerNodeCoordinate(nodeNumber=node, coordinate=coordinate))
        constraints[coordinate] = mbs.AddObject(
            eii.CoordinateConstraint(
                markerNumbers=[ground, marker], offset=speed or 0.0, velocityLevel=speed is not None
            )
        )

    hold(HUB_LINK, heli.main_rotor.omega_rad_s)
    hold(len(links) - 1, heli.tail_rotor.omega_rad_s)
    if fix_fuselage:
        for coordinate in range(6):
            hold(coordinate, None)

    def tree_sensor(link_number, position, output):
        return mbs.AddSensor(
            eii.SensorKinematicTree(
                objectNumber=tree,
                linkNumber=link_number,
                localPosition=list(position),
                outputVariableType=output,
                storeInternal=True,
                writeToFile=False,
            )
        )

    sensors = {
        **{
            f"mount:{name}": tree_sensor(FUSELAGE_LINK, point, exu.OutputVariableType.Position)
            for name, point in heli.mount_points.items()
        },
        "rotation": tree_sensor(FUSELAGE_LINK, (0.0, 0.0, 0.0), exu.OutputVariableType.RotationMatrix),
        "coordinates": mbs.AddSensor(
            eii.SensorNode(
                nodeNumber=node,
                outputVariableType=exu.OutputVariableType.Coordinates,
                storeInternal=True,
                writeToFile=False,
            )
        ),
    }
    masses = {k: lk.linkInertia.Mass() for k, lk in enumerate(links) if lk.linkInertia.Mass() > 0}
    if momentum_sensors:
        for k in masses:
            sensors[f"velocity_{k}"] = tree_sensor(k, links[k].linkInertia.COM(), exu.OutputVariableType.Velocity)
    mbs.Assemble()
    return Model(sc, mbs, node, sensors, masses, constraints)


class SolverFailure(RuntimeError):
    """The helicopter's time integration did not converge (its message names the keys that set it)."""


SOLVER_KEYS = (
    "helicopter.solver.step_s",
    "helicopter.solver.newton_absolute_tolerance_n",
    "helicopter.main_rotor.omega_rad_s",
    "helicopter.fuselage.mass_kg",
)


def solver_failure(model: Model, options: SolverOptions, reason: str) -> str:
    """The text of a failed integration: the time it stopped, Exudyn's reason, the keys that set the step."""
    t = float(model.mbs.systemData.GetTime())
    return (
        f"helicopter time integration did not converge at t = {t:.4g} s of {options.duration:g} s "
        f"(step {options.step:g} s) [{reason.strip().splitlines()[0] if reason.strip() else 'no reason given'}]: "
        f"the keys that set the step and the loads it resolves: {', '.join(SOLVER_KEYS)}"
    )


def solve(model: Model, options: SolverOptions, progress: str | None = None) -> dict:
    """Integrate in time; return solver statistics. Raises SolverFailure (a RuntimeError naming the config keys
    that set the step, `solver_failure`) if the solver fails.

    progress: a label for a console bar in simulated seconds (`uavdamp.progress`; shown only on a terminal).
    """
    shown = bar(options.duration, progress, "s") if progress else None
    if shown is not None and not shown.disable:  # a per-step call only when the bar is on screen

        def advance(mbs, t):
            if t - shown.n >= 0.1:
                shown.update(t - shown.n)
            return True

        model.mbs.SetPreStepUserFunction(advance)
    try:
        ok = model.mbs.SolveDynamic(solver_settings(options), solverType=exu.DynamicSolverType.GeneralizedAlpha)
    except Exception as error:  # Exudyn's SolverError (Newton failure, singular matrix) or a user function's
        if isinstance(error, SolverFailure):
            raise
        raise SolverFailure(solver_failure(model, options, f"{type(error).__name__}: {error}")) from error
    finally:
        if shown is not None:
            shown.close()
    if not ok:
        raise SolverFailure(solver_failure(model, options, "SolveDynamic returned False"))
    it = model.mbs.sys["dynamicSolver"].it
    return {"newton_iterations": int(it.newtonStepsCount), "jacobian_updates": int(it.newtonJacobiCount)}


def linear_momentum(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """Total linear momentum over time, kg m/s (needs `momentum_sensors`): (time s, momentum (n, 3))."""
    data = {k: model.mbs.GetSensorStoredData(model.sensors[f"velocity_{k}"]) for k in model.link_masses}
    first = next(iter(data.values()))
    return first[:, 0], sum(model.link_masses[k] * d[:, 1:4] for k, d in data.items())


MOTION_ATTRS = {
    "frame": "inertial, the fuselage axes at t = 0: x forward, y left, z up; origin at the fuselage centre of mass",
    "rotation": "rotation vector of R(t) R(0)^T (right hand, about the inertial axes; small angles: roll about x, "
    "pitch about y, yaw about z); the same at every point of the rigid fuselage",
}


def mount_motion(
    model: Model, heli: Helicopter, start: float = 0.0, from_start: bool = True
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(time s, displacement (mount, 3, n) m from the start, rotation (3, n) rad) of a solved model (MOTION_ATTRS).

    start: s, the samples before it are dropped and the record starts there (time from 0). from_start False: the
    rotation is R(t)'s own (relative to the model's axes, for flight runs the trim attitude), not R(t) R(0)^T."""
    names = list(heli.mount_points)
    data = [np.asarray(model.mbs.GetSensorStoredData(model.sensors[f"mount:{n}"])) for n in names]
    first = int(np.searchsorted(data[0][:, 0], start - 1e-9)) if start else 0
    data = [d[first:] for d in data]
    time = np.round(data[0][:, 0] - start, 9) if start else data[0][:, 0]  # ns: the record's clock from 0
    displacement = np.stack([(d[:, 1:4] - d[0, 1:4]).T for d in data])
    matrices = np.asarray(model.mbs.GetSensorStoredData(model.sensors["rotation"]))[first:, 1:].reshape(-1, 3, 3)
    relative = matrices @ matrices[0].T if from_start else matrices
    rotation = Rotation.from_matrix(relative).as_rotvec().T
    return time, displacement, rotation


def motion_dataset(heli: Helicopter, time: np.ndarray, displacement: np.ndarray, rotation: np.ndarray, attrs=None):
    """The mount-motion dataset: `mount_displacement` (mount, axis, time), m, and `mount_rotation` (axis, time), rad,
    with the mount points' positions (m, fuselage frame) as coordinates."""
    names = list(heli.mount_points)
    return xr.Dataset(
        {
            "mount_displacement": (
                ("mount", "axis", "time"),
                displacement,
                {"units": "m", "long_name": "displacement of the platform mount point from its start", **MOTION_ATTRS},
            ),
            "mount_rotation": (
                ("axis", "time"),
                rotation,
                {
                    "units": "rad",
                    "long_name": "rotation of the fuselage (and every mount) from its start",
                    **MOTION_ATTRS,
                },
            ),
        },
        coords={
            "mount": ("mount", names, {"units": "1", "long_name": "platform mount point"}),
            "mount_position": (
                ("mount", "axis"),
                np.array([heli.mount_points[n] for n in names], dtype=float),
                {"units": "m", "long_name": "mount point in the fuselage frame (x forward, y left, z up)"},
            ),
            "axis": ("axis", list(AXES), {"units": "1", "long_name": "axis (x forward, y left, z up)"}),
            "time": ("time", time, {"units": "s", "long_name": "simulation time"}),
        },
        attrs=attrs or {},
    )


def run(heli: Helicopter, options: SolverOptions, progress: str | None = None) -> xr.Dataset:
    """Simulate and return the motion of every mount point (`motion_dataset`), from the start.

    Attributes record the main rotor angle error after the run (rad) and solver statistics; `progress` as `solve`.
    """
    model = build(heli)
    stats = solve(model, options, progress)
    time, displacement, rotation = mount_motion(model, heli)
    q = model.mbs.GetSensorStoredData(model.sensors["coordinates"])
    angle_error = float(q[-1, 1 + HUB_LINK] - heli.main_rotor.omega_rad_s * time[-1])
    return motion_dataset(heli, time, displacement, rotation, {"rotor_angle_error_rad": angle_error, **stats})


def blade_frequencies(heli: Helicopter) -> np.ndarray:
    """Undamped natural frequencies, rad/s, of the rotor with the fuselage held, ascending.

    Exudyn's eigen-analysis linearises at the spinning state, so centrifugal stiffening is
    included; the hub coordinates are removed by their constraints.
    """
    model = build(heli, fix_fuselage=True)
    eig, _ = model.mbs.ComputeODE2Eigenvalues(
        exu.SimulationSettings(), useSparseSolver=False, ignoreAlgebraicEquations=False
    )
    return np.sort(np.sqrt(np.abs(np.asarray(eig))))
