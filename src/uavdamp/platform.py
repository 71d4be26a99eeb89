"""Camera platform (SPT 200-like pan-tilt head) on a semi-active Y-Z isolator, in Exudyn.

Axes: x forward (camera line of sight), y lateral (the paper's "perpendicular axis"),
z up (the paper's "gravity axis"). Coordinates and displacements are about the static
equilibrium: gravity is left out (with the paper's K = 10 N/m a 1.6 kg platform would sag
1.6 m; the isolator is taken as preloaded) and the servos hold their set-point 0 rad.

The model is one Exudyn kinematic tree in minimal coordinates, from the fuselage outwards:

    mount y, mount z    prismatic, massless, prescribed by coordinate constraints
                        (offsets set once per step from the fuselage time series)
    isolator y, z       prismatic, spring K and damper C (the tree's PD control);
                        the base (base_mass) rides on it
    displacement        prismatic z between base and intermediate body, spring only:
                        the structural flexibility (the paper's "spring-mass system")
    yaw                 revolute z, intermediate body (yaw servo); PID on the angle
    pitch               revolute y, pitch body + 0.9 kg camera (pitch servo); PID on the angle

Stiffnesses are not inputs: the displacement spring and the servos' proportional gains are
designed in closed form (`design_stiffness`) so that the undamped, base-clamped platform has
the configured natural frequencies (paper Table 1: 6.7, 5.7, 4.5 Hz). The yaw mode is
uncoupled (it takes the middle frequency); displacement and pitch are coupled through the
camera's forward offset and take the outer two. `natural_frequencies` checks the design by
Exudyn's eigen-analysis.

Variants: ``mount="rigid"`` drops the isolator (the base follows the fuselage) and
``body="lumped"`` replaces the platform by one mass on the isolator (SDOF checks).
"""

from __future__ import annotations

import math
import time as _time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields

import exudyn as exu
import numpy as np
import xarray as xr
from exudyn.itemInterface import (
    CoordinateConstraint,
    MarkerNodeCoordinate,
    NodeGenericODE2,
    NodePointGround,
    ObjectKinematicTree,
    SensorKinematicTree,
    SensorNode,
)

AXES = ("y", "z")
MODE_COORDINATES = ("displacement", "yaw", "pitch")


# config section layout: {section: {config key: PlatformParams field}}
_LAYOUT = {
    "structure": {
        name: name
        for name in (
            "base_mass",
            "intermediate_mass",
            "intermediate_yaw_inertia",
            "pitch_body_mass",
            "pitch_body_inertia",
            "camera_mass",
            "camera_size",
            "camera_com_x",
            "camera_com_z",
            "natural_frequencies_hz",
            "structural_damping_ratio",
            "servo_damping_ratio",
            "servo_integral_time",
        )
    },
    "isolator": {
        "stiffness": "isolator_stiffness",
        "damping_min": "damping_min",
        "damping_max": "damping_max",
        "update_period": "update_period",
    },
    "solver": {"time_step": "time_step"},
}
_KEY_OF = {field: f"platform.{section}.{key}" for section, keys in _LAYOUT.items() for key, field in keys.items()}
_VECTORS = ("camera_size", "natural_frequencies_hz")


@dataclass(frozen=True)
class ResponseSettings:
    """The stage's response figure (config ``platform.response``): mono-frequency input per axis."""

    freq_y_hz: float  # Hz, y input frequency
    freq_z_hz: float  # Hz, z input frequency
    amplitude: float  # m, input amplitude (paper: 1.3 mm)
    duration: float  # s, run length
    damping: float  # N s m-1, isolator damping of the isolated run


@dataclass(frozen=True)
class PlatformParams:
    """Platform, isolator and solver parameters (config section ``platform``), SI units.

    The config section nests them: ``structure`` (bodies, targets, damping ratios), ``isolator``
    (stiffness, damper bounds, update period), ``solver`` (time step) and, optionally, ``response``
    (the stage's figure only; leave it out of what the grid and study rules receive, so that a figure
    edit does not rerun them).
    """

    base_mass: float  # kg, base riding on the isolator
    intermediate_mass: float  # kg, yaw body (pan bracket + yaw servo)
    intermediate_yaw_inertia: float  # kg m2, about the yaw axis through its COM
    pitch_body_mass: float  # kg, tilt bracket + pitch servo, COM on the pitch axis
    pitch_body_inertia: float  # kg m2, about its COM, same about the pitch and yaw axes
    camera_mass: float  # kg (paper: 0.9 kg)
    camera_size: tuple[float, float, float]  # m, (x, y, z) edges of the camera as a uniform box
    camera_com_x: float  # m, camera COM forward of the pitch axis
    camera_com_z: float  # m, camera COM above the pitch axis
    natural_frequencies_hz: tuple[float, float, float]  # Hz, undamped clamped-base targets
    structural_damping_ratio: float  # 1, of the displacement spring
    servo_damping_ratio: float  # 1, servo D term
    servo_integral_time: float  # s, servo I term: Ki = Kp / servo_integral_time
    isolator_stiffness: float  # N m-1, default K (paper: 10 N/m)
    damping_min: float  # N s m-1, damper lower bound
    damping_max: float  # N s m-1, damper upper bound
    update_period: float  # s, damping update period (paper: 0.5 s)
    time_step: float  # s, solver step
    response: ResponseSettings | None = None

    @classmethod
    def from_config(cls, config: dict) -> PlatformParams:
        """Validated parameters from the config section; ValueError names the offending key."""
        _check_keys(config, [*_LAYOUT, "response"], "platform", optional=("response",))
        values = {}
        for section, keys in _LAYOUT.items():
            _check_keys(config[section], list(keys), f"platform.{section}")
            for key, field in keys.items():
                value = config[section][key]
                if field in _VECTORS:
                    if len(value) != 3:
                        raise ValueError(f"{_KEY_OF[field]}: needs 3 values, got {value!r}")
                    values[field] = tuple(float(v) for v in value)
                else:
                    values[field] = float(value)
        if "response" in config:
            names = [f.name for f in fields(ResponseSettings)]
            _check_keys(config["response"], names, "platform.response")
            values["response"] = ResponseSettings(**{n: float(config["response"][n]) for n in names})
        params = cls(**values)
        params.validate()
        return params

    def validate(self) -> None:
        """Raise ValueError naming the first parameter out of its valid range."""
        positive = [
            "base_mass",
            "intermediate_mass",
            "intermediate_yaw_inertia",
            "pitch_body_mass",
            "pitch_body_inertia",
            "camera_mass",
            "servo_integral_time",
            "isolator_stiffness",
            "update_period",
            "time_step",
        ]
        for name in positive:
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{_KEY_OF[name]} must be > 0, got {value}")
        for name in _VECTORS:
            if not all(math.isfinite(v) and v > 0 for v in getattr(self, name)):
                raise ValueError(f"{_KEY_OF[name]} must be > 0, got {getattr(self, name)}")
        if len(set(self.natural_frequencies_hz)) != 3:
            raise ValueError(f"{_KEY_OF['natural_frequencies_hz']} must be distinct, got {self.natural_frequencies_hz}")
        for name in ("structural_damping_ratio", "servo_damping_ratio", "damping_min"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"{_KEY_OF[name]} must be >= 0, got {value}")
        for name in ("camera_com_x", "camera_com_z"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{_KEY_OF[name]} must be finite")
        if not (math.isfinite(self.damping_max) and self.damping_max >= self.damping_min):
            raise ValueError(
                f"{_KEY_OF['damping_max']} ({self.damping_max}) must be >= {_KEY_OF['damping_min']} ({self.damping_min})"
            )
        if self.update_period < self.time_step:
            raise ValueError(
                f"{_KEY_OF['update_period']} ({self.update_period}) must be >= {_KEY_OF['time_step']} ({self.time_step})"
            )
        if self.response is not None:
            r = self.response
            for name in ("freq_y_hz", "freq_z_hz", "amplitude", "duration"):
                value = getattr(r, name)
                if not (math.isfinite(value) and value > 0):
                    raise ValueError(f"platform.response.{name} must be > 0, got {value}")
            if not self.damping_min <= r.damping <= self.damping_max:
                raise ValueError("platform.response.damping must lie within [damping_min, damping_max]")
        design_stiffness(self)  # raises ValueError if the targets cannot be met with these inertias

    @property
    def total_mass(self) -> float:
        """Mass of base, intermediate body, pitch body and camera, kg."""
        return self.base_mass + self.intermediate_mass + self.pitch_body_mass + self.camera_mass


def _check_keys(config, names: list[str], where: str, optional: tuple[str, ...] = ()) -> None:
    """ValueError naming unknown or missing keys of a config mapping."""
    if not isinstance(config, dict):
        raise ValueError(f"{where}: expected a mapping, got {type(config).__name__}")
    unknown = sorted(set(config) - set(names))
    missing = [n for n in names if n not in config and n not in optional]
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {unknown}")
    if missing:
        raise ValueError(f"{where}: missing key(s) {missing}")


# ---------------------------------------------------------------------------- design


def _pitch_link(p: PlatformParams) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass (kg), COM (m, pitch-axis frame) and inertia about that COM (kg m2) of pitch body + camera."""
    a, b, c = p.camera_size
    cam_inertia = p.camera_mass / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    cam_com = np.array([p.camera_com_x, 0.0, p.camera_com_z])
    mass = p.pitch_body_mass + p.camera_mass
    com = p.camera_mass * cam_com / mass  # the pitch body's COM is on the pitch axis (origin)

    def shifted(m, inertia, r):  # parallel-axis theorem, from the body's COM to `com`
        d = r - com
        return inertia + m * (d @ d * np.eye(3) - np.outer(d, d))

    inertia = shifted(p.camera_mass, cam_inertia, cam_com) + shifted(
        p.pitch_body_mass, p.pitch_body_inertia * np.eye(3), np.zeros(3)
    )
    return mass, com, inertia


def mass_matrix(p: PlatformParams) -> np.ndarray:
    """Closed-form mass matrix of the clamped platform in (displacement, yaw, pitch) at rest.

    Units: kg, kg m, kg m2 (coordinates in m, rad, rad).
    """
    m_pl, com, inertia = _pitch_link(p)
    x, _, z = com
    m = np.zeros((3, 3))
    m[0, 0] = p.intermediate_mass + m_pl
    m[1, 1] = p.intermediate_yaw_inertia + inertia[2, 2] + m_pl * x * x
    m[2, 2] = inertia[1, 1] + m_pl * (x * x + z * z)
    m[0, 2] = m[2, 0] = -m_pl * x  # pitching by theta moves a point at x down by x * theta
    return m


def design_stiffness(p: PlatformParams) -> np.ndarray:
    """Displacement spring (N m-1) and yaw, pitch servo P gains (N m rad-1) meeting the targets.

    Closed form: yaw is uncoupled, k_yaw = omega_mid^2 J_yaw. For the coupled (displacement,
    pitch) pair with mass matrix [[m11, m12], [m12, m22]] and diagonal stiffness (k1, k2),
    det(K - lambda M) = 0 has the roots lambda_a, lambda_b (outer targets squared, rad2 s-2) iff
    k1 k2 = det(M) lambda_a lambda_b and k1 m22 + k2 m11 = det(M) (lambda_a + lambda_b).
    Of the two solutions, the one with the displacement mode the higher one is taken.
    """
    lam = np.sort((2 * np.pi * np.asarray(p.natural_frequencies_hz)) ** 2)
    m = mass_matrix(p)
    lam_low, lam_mid, lam_high = lam
    m11, m22, m12 = m[0, 0], m[2, 2], m[0, 2]
    det = m11 * m22 - m12 * m12
    prod = det * lam_low * lam_high
    total = det * (lam_low + lam_high)
    # k1 m22 + (prod / k1) m11 = total  ->  m22 k1^2 - total k1 + prod m11 = 0
    disc = total * total - 4 * m22 * m11 * prod
    if disc < 0:
        coupling = abs(m12) / math.sqrt(m11 * m22)
        raise ValueError(
            f"{_KEY_OF['camera_com_x']}: the displacement-pitch coupling "
            f"{coupling:.3f} is too strong to place the modes at {p.natural_frequencies_hz} Hz"
        )
    k1 = (total + math.sqrt(disc)) / (2 * m22)
    k2 = prod / k1
    return np.array([k1, lam_mid * m[1, 1], k2])


# ---------------------------------------------------------------------------- model


@dataclass(frozen=True)
class _Link:
    joint: object  # exu.JointType
    mass: float = 0.0
    com: tuple = (0.0, 0.0, 0.0)
    inertia: np.ndarray | None = None


@dataclass
class Seen:
    """What a damping decision function sees at an update time (all up to and including t_now).

    time (s), mount_y and mount_z (m): the fuselage input on the solver grid so far;
    base_velocity and mount_velocity (m s-1, (y, z), inertial): the state at t_now.
    """

    time: np.ndarray
    mount_y: np.ndarray
    mount_z: np.ndarray
    base_velocity: np.ndarray
    mount_velocity: np.ndarray


Decide = Callable[[float, Seen], float]


class SolverFailed(RuntimeError):
    """The Exudyn solver did not reach the end of a run (e.g. Newton did not converge)."""


def _chain(
    p: PlatformParams, mount: str, body: str, clamped: bool, lumped_mass: float | None
) -> tuple[list[_Link], dict[str, int], np.ndarray]:
    """Links of the kinematic tree from the fuselage out, their indices by name, camera point in the last link."""
    links: list[_Link] = []
    idx: dict[str, int] = {}

    def add(name, link):
        idx[name] = len(links)
        links.append(link)

    base_mass = (lumped_mass or p.total_mass) if body == "lumped" else p.base_mass
    no_rotation = np.zeros((3, 3))  # the base only translates
    if not clamped:
        add("mount_y", _Link(exu.JointType.PrismaticY))
        if mount == "rigid":
            add("mount_z", _Link(exu.JointType.PrismaticZ, base_mass, inertia=no_rotation))
        else:
            add("mount_z", _Link(exu.JointType.PrismaticZ))
            add("iso_y", _Link(exu.JointType.PrismaticY))
            add("iso_z", _Link(exu.JointType.PrismaticZ, base_mass, inertia=no_rotation))
    if body == "lumped":
        return links, idx, np.zeros(3)
    m_pl, com_pl, inertia_pl = _pitch_link(p)
    add("displacement", _Link(exu.JointType.PrismaticZ))
    add("yaw", _Link(exu.JointType.RevoluteZ, p.intermediate_mass, inertia=p.intermediate_yaw_inertia * np.eye(3)))
    add("pitch", _Link(exu.JointType.RevoluteY, m_pl, tuple(com_pl), inertia_pl))
    return links, idx, np.array([p.camera_com_x, 0.0, p.camera_com_z])


class PlatformSimulator:
    """A platform model built once and solved many times with different K, C and inputs.

    mount: "isolated" (spring K and damper C in y and z) or "rigid" (the base follows the mount).
    body: "full" (base, intermediate body, pitch body + camera) or "lumped" (one mass, default the
    platform's total mass, on the isolator; the "camera" is that mass).
    clamped=True drops the mount and isolator (base fixed to ground): used for eigen-analysis.
    """

    def __init__(
        self,
        params: PlatformParams | dict,
        *,
        mount: str = "isolated",
        body: str = "full",
        lumped_mass: float | None = None,
        clamped: bool = False,
    ):
        t0 = _time.perf_counter()
        self.params = params if isinstance(params, PlatformParams) else PlatformParams.from_config(params)
        if mount not in ("isolated", "rigid"):
            raise ValueError(f"mount must be 'isolated' or 'rigid', got {mount!r}")
        if body not in ("full", "lumped"):
            raise ValueError(f"body must be 'full' or 'lumped', got {body!r}")
        if lumped_mass is not None and not lumped_mass > 0:
            raise ValueError(f"lumped_mass must be > 0, got {lumped_mass}")
        if clamped and body != "full":
            raise ValueError("clamped=True needs body='full'")
        self.mount, self.body, self.clamped = mount, body, clamped
        p = self.params
        self.joint_stiffness = design_stiffness(p)  # displacement, yaw, pitch
        links, self.link_index, self._camera_local = _chain(p, mount, body, clamped, lumped_mass)
        idx = self.link_index
        n = self._n = len(links)

        # the tree's PD control: isolator K and C, structural spring and damping, servo P and D terms;
        # clamped: the undamped platform (D and I terms off)
        self._pvec = np.zeros(n)
        self._dvec = np.zeros(n)
        self._servo_ki = np.zeros(n)
        if body == "full":
            mdiag = np.diag(mass_matrix(p))
            zetas = (p.structural_damping_ratio, p.servo_damping_ratio, p.servo_damping_ratio)
            for name, k, m, zeta in zip(MODE_COORDINATES, self.joint_stiffness, mdiag, zetas):
                self._pvec[idx[name]] = k
                if not clamped:
                    self._dvec[idx[name]] = 2 * zeta * math.sqrt(k * m)
                    if name != "displacement":
                        self._servo_ki[idx[name]] = k / p.servo_integral_time
        if "iso_y" in idx:  # until a run sets them: the default K (so that eigen() sees it), no damping
            self._pvec[idx["iso_y"]] = self._pvec[idx["iso_z"]] = p.isolator_stiffness

        self.sc = exu.SystemContainer()
        mbs = self.sc.AddSystem()
        self.mbs = mbs
        zeros = [0.0] * n
        self._node = mbs.AddNode(
            NodeGenericODE2(
                referenceCoordinates=zeros,
                initialCoordinates=zeros,
                initialCoordinates_t=zeros,
                numberOfODE2Coordinates=n,
            )
        )
        self._tree = mbs.AddObject(
            ObjectKinematicTree(
                nodeNumber=self._node,
                jointTypes=[link.joint for link in links],
                linkParents=list(range(-1, n - 1)),
                jointTransformations=exu.Matrix3DList([np.eye(3)] * n),
                jointOffsets=exu.Vector3DList([[0.0, 0.0, 0.0]] * n),
                linkInertiasCOM=exu.Matrix3DList(
                    [link.inertia if link.inertia is not None else np.zeros((3, 3)) for link in links]
                ),
                linkCOMs=exu.Vector3DList([list(link.com) for link in links]),
                linkMasses=[link.mass for link in links],
                jointForceVector=zeros,
                jointPositionOffsetVector=zeros,
                jointVelocityOffsetVector=zeros,
                jointPControlVector=self._pvec.tolist(),
                jointDControlVector=self._dvec.tolist(),
            )
        )
        self._constraints = []
        if not clamped:
            ground = mbs.AddNode(NodePointGround())
            m_ground = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
            for name in ("mount_y", "mount_z"):
                m_link = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=self._node, coordinate=idx[name]))
                self._constraints.append(mbs.AddObject(CoordinateConstraint(markerNumbers=[m_ground, m_link])))
            stored = {"storeInternal": True, "writeToFile": False}  # in memory, no files
            self._s_camera = mbs.AddSensor(
                SensorKinematicTree(
                    objectNumber=self._tree,
                    linkNumber=n - 1,
                    localPosition=self._camera_local.tolist(),
                    outputVariableType=exu.OutputVariableType.Position,
                    **stored,
                )
            )
            self._s_coords = mbs.AddSensor(
                SensorNode(nodeNumber=self._node, outputVariableType=exu.OutputVariableType.Coordinates, **stored)
            )
            self._s_rates = mbs.AddSensor(
                SensorNode(nodeNumber=self._node, outputVariableType=exu.OutputVariableType.Coordinates_t, **stored)
            )
            mbs.SetPreStepUserFunction(self._pre_step)
        mbs.Assemble()
        self._q0 = mbs.GetNodeODE2Index(self._node)
        self._solver = exu.MainSolverImplicitSecondOrder()
        self.build_time = _time.perf_counter() - t0
        self.signal_jacobian_update = True  # False only to measure what the signal saves
        self._error: Exception | None = None
        self.newton_iterations = 0
        self.jacobian_updates = 0
        self.solve_time = 0.0

    # ------------------------------------------------------------------ eigen-analysis

    def eigen(self) -> tuple[np.ndarray, np.ndarray]:
        """Undamped natural frequencies (Hz, ascending) and mode shapes (columns) by Exudyn.

        Clamped: the platform's three modes. Otherwise the mount is held still, the isolator has the
        stiffness of the last run (before any run: params.isolator_stiffness) and the shapes run over
        all tree coordinates (mount y, z, [isolator y, z,] platform).
        """
        values, vectors = self.mbs.ComputeODE2Eigenvalues(ignoreAlgebraicEquations=False)
        values = np.asarray(values)
        order = np.argsort(values)
        return np.sqrt(np.abs(values[order])) / (2 * np.pi), np.asarray(vectors)[:, order]

    # ------------------------------------------------------------------ simulation

    def _settings(self, end_time: float, steps: int) -> exu.SimulationSettings:
        ss = exu.SimulationSettings()
        ss.timeIntegration.endTime = end_time
        ss.timeIntegration.numberOfSteps = steps
        ss.timeIntegration.verboseMode = 0
        ss.timeIntegration.newton.useModifiedNewton = True
        ss.timeIntegration.newton.relativeTolerance = 1e-6  # changes results by < 1e-6 relative
        ss.timeIntegration.generalizedAlpha.spectralRadius = 0.9
        ss.solution.file.write = False
        ss.solution.sensors.writePeriod = self.params.time_step
        ss.show.computationTime = False
        ss.show.statistics = False
        return ss

    def _pre_step(self, mbs, t: float) -> bool:
        """Called by Exudyn before the step that ends at t; an exception stops the solver, re-raised by run."""
        try:
            return self._prepare_step(mbs, t)
        except Exception as error:  # noqa: BLE001 - kept and re-raised unchanged after the solver stops
            self._error = error
            return False

    def _prepare_step(self, mbs, t: float) -> bool:
        """Input offsets, damping update, servo I term for the step ending at t (state still at t - h)."""
        run = self._run
        n = int(round(t * run["inv_h"])) - 1  # the step runs from grid point n to n + 1
        mbs.SetObjectParameter(self._constraints[0], "offset", run["y_offsets"][n + 1])
        mbs.SetObjectParameter(self._constraints[1], "offset", run["z_offsets"][n + 1])
        if run["isolated"] and n > 0 and n % run["steps_per_update"] == 0:
            velocity = mbs.systemData.GetODE2Coordinates_t()[self._q0 : self._q0 + self._n]
            self._set_damping(self._damping_at(n, velocity))
        run["applied"][n] = run["c"]
        if run["servo_i"]:  # servos' I term, explicit: integrate the angle errors, hold for the step
            q = mbs.systemData.GetODE2Coordinates()
            force = run["force"]
            for j, ki in run["servo_i"]:
                run["integral"][j] += run["h"] * q[self._q0 + j]
                force[j] = -ki * run["integral"][j]
            mbs.SetObjectParameter(self._tree, "jointForceVector", force)
        return True

    def _set_damping(self, c: float) -> None:
        """Put C (N s m-1) on both isolator dampers; tell the solver to refresh its Jacobian."""
        if c == self._run["c"]:
            return
        self._run["c"] = c
        self._dvec[self.link_index["iso_y"]] = c
        self._dvec[self.link_index["iso_z"]] = c
        self.mbs.SetObjectParameter(self._tree, "jointDControlVector", self._dvec)
        if self.signal_jacobian_update:
            self.mbs.solverSignalJacobianUpdate = True

    def _damping_at(self, n: int, velocity: np.ndarray) -> float:
        """Clipped damping (N s m-1) for the update at grid point n; velocity: tree coordinates' rates."""
        run = self._run
        damping = run["damping"]
        p = self.params
        if callable(damping):
            i = self.link_index
            mount_v = np.array([velocity[i["mount_y"]], velocity[i["mount_z"]]])
            seen = Seen(
                time=run["time"][: n + 1],
                mount_y=run["y"][: n + 1],
                mount_z=run["z"][: n + 1],
                base_velocity=mount_v + np.array([velocity[i["iso_y"]], velocity[i["iso_z"]]]),
                mount_velocity=mount_v,
            )
            c = float(damping(float(run["time"][n]), seen))
        elif np.ndim(damping) == 0:
            c = float(damping)
        else:
            c = float(damping[min(n // run["steps_per_update"], len(damping) - 1)])
        if not math.isfinite(c):
            raise ValueError(f"damping: got non-finite value {c} at t = {run['time'][n]} s")
        return min(max(c, p.damping_min), p.damping_max)

    def run(
        self,
        time: Sequence[float],
        mount_y: Sequence[float],
        mount_z: Sequence[float],
        *,
        stiffness: float | None = None,
        damping: float | Sequence[float] | Decide | None = None,
        update_period: float | None = None,
    ) -> xr.Dataset:
        """Solve one run and return the response dataset (see `_dataset` for its variables).

        time (s, from 0, increasing), mount_y, mount_z (m): prescribed fuselage displacement at the
        mount, interpolated linearly onto the solver grid (step params.time_step, up to time[-1]).
        stiffness: isolator K, N m-1 (default params.isolator_stiffness).
        damping: isolator C, N s m-1 (required for the isolated mount), in one of three forms,
          clipped to [damping_min, damping_max]: a number (constant); a sequence (piecewise
          constant: value k on [k P, (k+1) P), the last one holds); or a function
          ``decide(t_now, seen) -> C`` called at t = 0, P, 2P, ... with a `Seen` of the signals so
          far. P = update_period (default params.update_period), s, a multiple of the time step.
          The value set at t_k acts from t_k on: the state at t_k is still that of the old C.
        Initial state: undeformed; the mount moves with the input's initial velocity, the base is at
        rest (isolated) or moves with the mount (rigid), the platform is at rest relative to the base.
        The rigid mount ignores stiffness and damping (its damping output is NaN).
        Raises ValueError for bad arguments, SolverFailed if the solver stops early; an exception
        raised by `decide` stops the run and is re-raised.
        """
        if self.clamped:
            raise ValueError("a clamped platform has no mount input: use eigen()")
        p = self.params
        h = p.time_step
        grid, y, z = _on_grid(time, mount_y, mount_z, h)
        steps = grid.size - 1
        stiffness = p.isolator_stiffness if stiffness is None else float(stiffness)
        if not (math.isfinite(stiffness) and stiffness > 0):
            raise ValueError(f"stiffness must be > 0, got {stiffness}")
        if damping is None:
            if self.mount == "isolated":
                raise ValueError("damping is required for the isolated mount")
            damping = math.nan
        if not callable(damping) and np.ndim(damping) > 0:
            damping = np.asarray(damping, dtype=float)
            if damping.ndim != 1 or damping.size == 0:
                raise ValueError("damping schedule must be a non-empty 1-D sequence")
        period = p.update_period if update_period is None else float(update_period)
        steps_per_update = int(round(period / h))
        if steps_per_update < 1 or abs(steps_per_update * h - period) > 1e-9 * max(period, 1.0):
            raise ValueError(f"update_period ({period} s) must be a positive multiple of time_step ({h} s)")

        isolated = self.mount == "isolated"
        i = self.link_index
        y.flags.writeable = z.flags.writeable = False  # a decision function sees views of these
        self._run = {
            "time": grid,
            "y": y,
            "z": z,
            "y_offsets": y.tolist(),  # Python floats: cheaper to hand to Exudyn once per step
            "z_offsets": z.tolist(),
            "h": h,
            "inv_h": 1.0 / h,
            "damping": damping,
            "steps_per_update": steps_per_update,
            "isolated": isolated,
            "c": math.nan,
            "applied": np.full(steps + 1, math.nan),
            "servo_i": [(j, ki) for j, ki in enumerate(self._servo_ki) if ki > 0],
            "integral": np.zeros(self._n),
            "force": np.zeros(self._n),
        }
        q = np.zeros(self._n)
        v = np.zeros(self._n)
        q[i["mount_y"]], q[i["mount_z"]] = y[0], z[0]
        v[i["mount_y"]], v[i["mount_z"]] = (y[1] - y[0]) / h, (z[1] - z[0]) / h
        if isolated:
            v[i["iso_y"]], v[i["iso_z"]] = -v[i["mount_y"]], -v[i["mount_z"]]
            self._pvec[i["iso_y"]] = self._pvec[i["iso_z"]] = stiffness
            self._set_damping(self._damping_at(0, v))
        mbs = self.mbs
        mbs.SetObjectParameter(self._tree, "jointPControlVector", self._pvec)
        mbs.SetObjectParameter(self._tree, "jointDControlVector", self._dvec)
        mbs.SetObjectParameter(self._tree, "jointForceVector", np.zeros(self._n))
        mbs.SetObjectParameter(self._constraints[0], "offset", float(y[0]))
        mbs.SetObjectParameter(self._constraints[1], "offset", float(z[0]))
        ode2 = np.zeros(mbs.systemData.ODE2Size())
        ode2_t = np.zeros_like(ode2)
        ode2[self._q0 : self._q0 + self._n] = q
        ode2_t[self._q0 : self._q0 + self._n] = v
        mbs.systemData.SetODE2Coordinates(ode2, configuration=exu.ConfigurationType.Initial)
        mbs.systemData.SetODE2Coordinates_t(ode2_t, configuration=exu.ConfigurationType.Initial)
        mbs.solverSignalJacobianUpdate = True

        self._error = None
        t0 = _time.perf_counter()
        success = self._solver.SolveSystem(mbs, self._settings(steps * h, steps))
        self.solve_time = _time.perf_counter() - t0
        self.newton_iterations = int(self._solver.it.newtonStepsCount)
        self.jacobian_updates = int(self._solver.it.newtonJacobiCount)
        if self._error is not None:
            raise self._error
        camera = np.asarray(mbs.GetSensorStoredData(self._s_camera))
        coords = np.asarray(mbs.GetSensorStoredData(self._s_coords))
        rates = np.asarray(mbs.GetSensorStoredData(self._s_rates))
        if not success or camera.shape[0] != steps + 1:
            raise SolverFailed(
                f"solver stopped at t = {self._solver.it.currentTime:.6g} s of {steps * h:.6g} s "
                f"({camera.shape[0]} of {steps + 1} samples)"
            )
        applied = self._run["applied"]
        applied[-1] = self._run["c"]
        if not isolated:
            applied[:] = math.nan
        return self._dataset(grid, camera, coords, rates, applied, stiffness if isolated else math.nan)

    def _dataset(self, grid, camera, coords, rates, applied, stiffness) -> xr.Dataset:
        """Camera displacement (axis, time) m, yaw and pitch rad, applied damping N s m-1, mount and
        base displacement (axis, time) m, isolator stroke rate (axis, time) m s-1."""
        i = self.link_index
        q = coords[:, 1:]  # sensor rows: time, then the tree's coordinates
        mount = np.stack([q[:, i["mount_y"]], q[:, i["mount_z"]]])  # as solved: the constraints' result
        base = mount.copy()
        stroke_rate = np.zeros((2, grid.size))
        if self.mount == "isolated":
            base += np.stack([q[:, i["iso_y"]], q[:, i["iso_z"]]])
            stroke_rate = np.stack([rates[:, 1 + i["iso_y"]], rates[:, 1 + i["iso_z"]]])
        camera_disp = (camera[:, 1:] - self._camera_local)[:, 1:3].T  # (axis, time), y and z
        angle = {name: (q[:, i[name]] if name in i else np.zeros(grid.size)) for name in ("yaw", "pitch")}
        ds = xr.Dataset(
            {
                "camera_displacement": (
                    ("axis", "time"),
                    camera_disp,
                    {"units": "m", "long_name": "camera displacement (inertial, from rest position)"},
                ),
                "camera_yaw": ("time", angle["yaw"], {"units": "rad", "long_name": "camera yaw angle"}),
                "camera_pitch": ("time", angle["pitch"], {"units": "rad", "long_name": "camera pitch angle"}),
                "damping": (
                    "time",
                    applied,
                    {"units": "N s m-1", "long_name": "isolator damping applied from this time on"},
                ),
                "mount_displacement": (
                    ("axis", "time"),
                    mount,
                    {"units": "m", "long_name": "prescribed fuselage displacement at the mount"},
                ),
                "base_displacement": (
                    ("axis", "time"),
                    base,
                    {"units": "m", "long_name": "platform base displacement (inertial)"},
                ),
                "isolator_velocity": (
                    ("axis", "time"),
                    stroke_rate,
                    {"units": "m s-1", "long_name": "isolator stroke rate (base velocity relative to the mount)"},
                ),
            },
            coords={
                "time": ("time", grid, {"units": "s", "long_name": "time"}),
                "axis": ("axis", list(AXES), {"units": "1", "long_name": "direction (y lateral, z up)"}),
            },
            attrs={
                "title": "Camera platform response to a prescribed fuselage displacement",
                "mount": self.mount,
                "body": self.body,
                "isolator_stiffness_N_m": stiffness,
                "time_step_s": self.params.time_step,
                "newton_iterations": self.newton_iterations,
                "jacobian_updates": self.jacobian_updates,
            },
        )
        return ds


# ---------------------------------------------------------------------------- helpers


def _on_grid(time, mount_y, mount_z, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Validated input resampled (linearly) onto the solver grid 0, h, 2h, ... <= time[-1]."""
    time = np.asarray(time, dtype=float)
    mount_y = np.asarray(mount_y, dtype=float)
    mount_z = np.asarray(mount_z, dtype=float)
    if time.ndim != 1 or time.size < 2 or not np.all(np.diff(time) > 0):
        raise ValueError("time must be 1-D, increasing, with at least 2 samples")
    if abs(time[0]) > 1e-12:
        raise ValueError(f"time must start at 0 s, got {time[0]}")
    if mount_y.shape != time.shape or mount_z.shape != time.shape:
        raise ValueError("mount_y and mount_z must have the shape of time")
    if not (np.all(np.isfinite(mount_y)) and np.all(np.isfinite(mount_z))):
        raise ValueError("mount_y and mount_z must be finite")
    steps = int(math.floor(time[-1] / h + 1e-9))
    if steps < 1:
        raise ValueError(f"time must reach at least one time_step ({h} s)")
    grid = np.arange(steps + 1) * h
    return grid, np.interp(grid, time, mount_y), np.interp(grid, time, mount_z)


def natural_frequencies(params: PlatformParams | dict) -> tuple[np.ndarray, np.ndarray]:
    """Undamped, base-clamped natural frequencies (Hz, ascending) and mode shapes by eigen-analysis.

    Mode shapes are columns over (displacement m, yaw rad, pitch rad), scaled to a largest
    component of magnitude 1 with that component positive.
    """
    freq_hz, shapes = PlatformSimulator(params, clamped=True).eigen()
    shapes = shapes / shapes[np.argmax(np.abs(shapes), axis=0), range(shapes.shape[1])]
    return freq_hz, shapes


def modes_dataset(params: PlatformParams | dict) -> xr.Dataset:
    """Natural frequencies beside the paper's targets, mode shapes and the designed stiffnesses."""
    p = params if isinstance(params, PlatformParams) else PlatformParams.from_config(params)
    freq_hz, shapes = natural_frequencies(p)
    k = design_stiffness(p)
    mode = np.arange(1, freq_hz.size + 1)
    return xr.Dataset(
        {
            "natural_frequency": (
                "mode",
                freq_hz,
                {"units": "Hz", "long_name": "undamped natural frequency, base clamped (Exudyn eigen-analysis)"},
            ),
            "target_frequency": (
                "mode",
                np.sort(p.natural_frequencies_hz),
                {"units": "Hz", "long_name": "target natural frequency (Marichal et al. 2014, Table 1)"},
            ),
            "mode_shape": (
                ("coordinate", "mode"),
                shapes,
                {
                    "units": "1",
                    "long_name": "mode shape, largest component scaled to 1 (displacement in m, angles in rad)",
                },
            ),
            "displacement_stiffness": ((), k[0], {"units": "N m-1", "long_name": "structural spring, designed"}),
            "yaw_servo_gain": ((), k[1], {"units": "N m rad-1", "long_name": "yaw servo P gain, designed"}),
            "pitch_servo_gain": ((), k[2], {"units": "N m rad-1", "long_name": "pitch servo P gain, designed"}),
            "total_mass": ((), p.total_mass, {"units": "kg", "long_name": "platform mass including camera"}),
        },
        attrs={"title": "Undamped natural frequencies and mode shapes of the camera platform, base clamped"},
        coords={
            "mode": ("mode", mode, {"units": "1", "long_name": "mode number, ascending frequency"}),
            "coordinate": (
                "coordinate",
                list(MODE_COORDINATES),
                {"units": "1", "long_name": "platform joint coordinate"},
            ),
        },
    )


def sine_input(freq_y_hz: float, freq_z_hz: float, amplitude: float, duration: float, time_step: float):
    """Mono-frequency mount input: (time s, y m, z m) with y = A sin(2 pi f_y t), z likewise."""
    t = np.arange(int(round(duration / time_step)) + 1) * time_step
    return t, amplitude * np.sin(2 * np.pi * freq_y_hz * t), amplitude * np.sin(2 * np.pi * freq_z_hz * t)
