"""Blade-element loads on the Exudyn rotorcraft, updated once per time step, with the rotors' inflow.

Before Exudyn solves a step (its pre-step function), `RotorLoads.update` takes every blade's frame from the tree's
coordinates, computes the section velocities from the blades' own motion (flap, lag and feather included) and the
air (free stream plus induced velocity), the blade-element loads, and sets their resultants on the blade links as
the tree's generalized forces (``jointForceVector``), so the loads lag the state by one step; all of that in one
compiled call (`uavdamp.helicopter.rotor_kernel`, the arithmetic of `uavdamp.helicopter.treekinematics` and
`uavdamp.helicopter.aerodynamics`, its tested reference). It then advances the inflow by one explicit step.

- Main blades: pitch = built-in twist only; collective and cyclic enter as the feather joints' position offsets
  against the pitch-link spring (`feather_offsets`), so the feather link's frame is the pitched blade frame.
- Tail blades: rigid on the tail hub (RevoluteY); blade k's frame is the hub's times RotY(2 pi k / N) RotX(-pi/2)
  (x along the blade, y the direction of rotation, z = the hub's +y), pitch = tail collective + twist. Positive
  pitch pushes along +y; the anti-torque of the counter-clockwise main rotor needs -y: a negative collective.
- Inflow (``helicopter.aerodynamics.inflow``): "uniform", Glauert's momentum inflow from the previous step's
  thrust, relaxed by half the difference each step (a choice: the bare fixed point alternates with a loop gain
  near -0.6); "pitt_peters", the three Pitt-Peters states integrated by explicit Euler (their time constants,
  about 0.05-0.1 s, are 50-100 steps). The tail rotor always has relaxed uniform inflow. The skew of the wake and
  the advance ratio come from the free stream only (the fuselage's own vibration enters the blade sections, not the
  wake), its direction taken along the hub's -x (no sideslip in the harmonics).

The tree's own ``linkForces`` and ``linkTorques`` are not used: in exudyn 1.13.6 a link torque acts with the
opposite sign, and a link force on a blade acts as the opposite force at the tree's base point, not at the link's
origin (a +z force on a main blade's feather link flapped it like a -y torque of 0.687 m times the force; checked on
this machine). Marker loads (LoadForceVector on MarkerKinematicTreeRigid) act correctly but cost a link Jacobian in
every Newton iteration; a global load vector held over a step also turns against a blade by Omega dt (0.044 rad
at 1 ms) and leaked about 2e2 N m of the flap moment into feathering (measured).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from uavdamp.helicopter import inflow as rotor_inflow
from uavdamp.helicopter import rotor_kernel
from uavdamp.helicopter.aerodynamics import BladeAero
from uavdamp.helicopter.model import HUB_LINK, Model
from uavdamp.helicopter.params import Aerodynamics, BladeSection, Helicopter
from uavdamp.helicopter.treekinematics import TreeKinematics

RELAXATION = 0.5  # 1, share of the quasi-steady uniform inflow's change taken per step
_RX = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])  # RotX(-pi/2)


def feather_link(blade: int) -> int:
    """Tree link of main blade `blade` (flap, lag, feather after the hub): its feather link, the blade body."""
    return HUB_LINK + 3 + 3 * blade


def blade_aero(section: BladeSection, n_blades: int, hinge_offset: float, length: float, n_stations: int):
    """The `BladeAero` of a config blade section on a rotor of the model's geometry (lengths in m)."""
    return BladeAero(
        n_blades=n_blades,
        hinge_offset=hinge_offset,
        length=length,
        chord=section.chord,
        twist_rad=section.twist,
        root_cutout=section.root_cutout,
        lift_slope=section.lift_slope,
        alpha_zero_lift=section.zero_lift_angle,
        cd0=section.drag_coefficient,
        cd2=section.drag_coefficient_quadratic,
        alpha_stall=section.stall_angle,
        n_stations=n_stations,
    )


def rotor_blades(heli: Helicopter, aero: Aerodynamics) -> tuple[BladeAero, BladeAero]:
    """(main, tail) blades of the config: the main ones from the flap hinge, the tail ones from the hub axis."""
    main, tail = heli.main_rotor, heli.tail_rotor
    return (
        blade_aero(aero.main_blade, main.n_blades, main.hinge_offset, main.blade_length, aero.n_stations),
        blade_aero(aero.tail_blade, tail.n_blades, 0.0, tail.blade_length, aero.n_stations),
    )


@dataclass
class Loads:
    """The last step's aerodynamic resultants: main rotor in the fuselage axes at the hub centre, tail in global."""

    main_force: np.ndarray = field(default_factory=lambda: np.zeros(3))  # N, fuselage axes
    main_moment: np.ndarray = field(default_factory=lambda: np.zeros(3))  # N m about the hub centre, fuselage axes
    tail_force: np.ndarray = field(default_factory=lambda: np.zeros(3))  # N, global
    tail_moment: np.ndarray = field(default_factory=lambda: np.zeros(3))  # N m about the tail hub, global
    drag: np.ndarray = field(default_factory=lambda: np.zeros(3))  # N, fuselage drag, global
    total_force: np.ndarray = field(default_factory=lambda: np.zeros(3))  # N, every aerodynamic force, global


class RotorLoads:
    """Blade-element loads of both rotors and the fuselage drag on a built `Model`, as the tree's generalized forces."""

    def __init__(
        self, model: Model, heli: Helicopter, aero: Aerodynamics, wind, drag_area: float, step: float, nu=None
    ):
        self.mbs, self.heli, self.step = model.mbs, heli, step  # step: the solver's, s
        self.main, self.tail = rotor_blades(heli, aero)
        self.rho, self.model_name = aero.air_density, aero.inflow
        self.wind = np.asarray(wind, dtype=float)  # m/s, free stream in the model's (inertial) axes
        self.half_drag = 0.5 * aero.air_density * drag_area
        self.omega, self.radius = heli.main_rotor.omega_rad_s, self.main.tip_radius
        self.tip_speed = self.omega * self.radius
        self.tail_omega = heli.tail_rotor.omega_rad_s
        self.r_over_radius = (self.main.hinge_offset + self.main.stations) / self.radius
        self.nu = np.zeros(3) if nu is None else np.asarray(nu, dtype=float).copy()  # inflow states (ratios)
        self.tail_lambda = 0.0  # signed tail inflow ratio (positive along the tail hub's -y)
        self.tail_collective = 0.0  # rad
        tree = TreeKinematics(heli, len(model.mbs.GetObjectParameter(0, "jointTypes")))
        self.tail_frames = tail_frames(self.tail.n_blades)  # blade frames in the tail hub frame
        self._geometry = np.concatenate([tree.hub_offset, tree.tail_offset])  # m: the kernel's state
        self._loads = rotor_kernel.loads
        self._fixed = (  # the compiled loads' fixed inputs (`rotor_kernel.loads`)
            np.ascontiguousarray(tree.azimuth),
            np.ascontiguousarray(tree.hinge),
            np.array([HUB_LINK, HUB_LINK + 1], dtype=np.int64),
            _span(self.main),
            rotor_kernel.airfoil(self.main),
            _span(self.tail),
            rotor_kernel.airfoil(self.tail),
            self.tail_frames,
        )
        self.loads = Loads()

    def update(self, q: np.ndarray, q_t: np.ndarray) -> Loads:
        """Loads at coordinates q, velocities q_t set as the tree's generalized forces (for the next step); the
        inflow advanced one step. One compiled call (`uavdamp.helicopter.rotor_kernel.loads`)."""
        tail_vi = self.tail_lambda * self.tail_omega * self.tail.tip_radius
        state = np.concatenate([self._geometry, self.nu, [self.tip_speed], self.r_over_radius])
        state = np.concatenate([self.wind, state, [tail_vi, self.tail_collective, self.half_drag]])
        q, q_t = np.asarray(q, dtype=float), np.asarray(q_t, dtype=float)
        forces, force_f, moment_f, tail_force, tail_moment, drag, rot_f = self._loads(
            q, q_t, *self._fixed, state, self.rho
        )
        self.mbs.SetObjectParameter(0, "jointForceVector", forces)
        wind_hub = self.wind @ rot_f
        self._advance_inflow(force_f, moment_f, wind_hub)
        self._advance_tail_inflow(tail_force @ rot_f[:, 1], wind_hub)
        self.loads = Loads(force_f, moment_f, tail_force, tail_moment, drag, forces[:3].copy())
        return self.loads

    def coefficients(self, force_f: np.ndarray, moment_f: np.ndarray) -> tuple[float, float, float]:
        """(C_T, C_L, C_M) of the main rotor from its hub loads in fuselage axes (`inflow.rotor_coefficients`)."""
        return rotor_inflow.rotor_coefficients(force_f[2], moment_f[0], moment_f[1], self.rho, self.omega, self.radius)

    def free_stream(self, wind_hub: np.ndarray) -> tuple[float, float]:
        """(mu, mu_z) of the main rotor: in-plane free stream and free stream down through the disc over Omega R."""
        tip_speed = self.omega * self.radius
        return math.hypot(wind_hub[0], wind_hub[1]) / tip_speed, -wind_hub[2] / tip_speed

    def _advance_inflow(self, force_f, moment_f, wind_hub) -> None:
        if self.model_name == "none":
            return
        c_t, c_l, c_m = self.coefficients(force_f, moment_f)
        mu, mu_z = self.free_stream(wind_hub)
        if self.model_name == "uniform":
            target = rotor_inflow.uniform_inflow(c_t, mu, mu_z) - mu_z if c_t > 0 else 0.0
            self.nu[0] += RELAXATION * (target - self.nu[0])
            return
        self.nu += (self.omega * self.step) * rotor_inflow.pitt_peters_rhs(self.nu, c_t, c_l, c_m, mu, mu_z)

    def _advance_tail_inflow(self, thrust: float, wind_hub) -> None:
        blade, omega = self.tail, self.tail_omega
        if omega <= 0.0:
            return
        tip_speed = omega * blade.tip_radius
        c_t = abs(thrust) / (self.rho * blade.disc_area * tip_speed**2)
        mu = math.hypot(wind_hub[0], wind_hub[2]) / tip_speed
        target = math.copysign(rotor_inflow.uniform_inflow(c_t, mu), thrust) if c_t > 0 else 0.0
        self.tail_lambda += RELAXATION * (target - self.tail_lambda)

    def induced_velocity(self) -> float:
        """Mean induced velocity of the main rotor, m/s (nu_0 Omega R, positive down through the disc)."""
        return float(self.nu[0] * self.omega * self.radius)


def tail_frames(n_blades: int) -> np.ndarray:
    """The tail blades' frames (B, 3, 3) in the tail hub's: RotY(2 pi k / N) RotX(-pi/2) (module docstring)."""
    psi = 2 * np.pi * np.arange(n_blades) / n_blades
    c, s = np.cos(psi), np.sin(psi)
    rot_y = np.zeros((psi.size, 3, 3))
    rot_y[:, 0, 0], rot_y[:, 0, 2], rot_y[:, 1, 1], rot_y[:, 2, 0], rot_y[:, 2, 2] = c, s, 1.0, -s, c
    return rot_y @ _RX


def _span(blade: BladeAero) -> np.ndarray:
    """(4, S): a blade's stations, quadrature weights, first-moment weights and twist (the kernel's layout)."""
    return np.ascontiguousarray(np.vstack([blade.stations, blade.weights, blade.moment_weights, blade.twist]))


def feather_offsets(heli: Helicopter, controls, hub_angle: float, step: float):
    """(position offsets rad, velocity offsets rad/s) of the main blades' feather joints for the next step.

    controls: (collective, lateral cyclic theta_1c, longitudinal cyclic theta_1s, ...), rad; blade pitch
    theta_0 + theta_1c cos psi + theta_1s sin psi at the Peters azimuth psi of mid-step (0 over the tail).
    """
    omega, n = heli.main_rotor.omega_rad_s, heli.main_rotor.n_blades
    psi = hub_angle + 0.5 * omega * step - math.pi + (2 * math.pi / n) * np.arange(n)  # `inflow.blade_azimuth`
    c, s = np.cos(psi), np.sin(psi)
    theta_0, theta_1c, theta_1s = controls[0], controls[1], controls[2]
    return theta_0 + theta_1c * c + theta_1s * s, omega * (theta_1s * c - theta_1c * s)
