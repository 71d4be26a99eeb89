"""Blade-element aerodynamics of rigid rotor blades: section velocities, section loads, span integration.

Pure NumPy, no Exudyn: the caller reads each blade's frame from the multibody state, calls
`section_velocities`, adds the pitch, calls `blade_loads` and applies the per-blade resultant. The flight runs do
the same arithmetic in one compiled call per step (`uavdamp.helicopter.rotor_kernel`, tested against these
functions); the trim's hover loads (`hover_loads`) call them directly.

Frames and signs (the uavdamp model, `helicopter.py`: x forward, y left, z up, main hub a RevoluteZ about +z,
so the main rotor turns counter-clockwise seen from above):

- Blade frame: x along the blade from its reference point (the hinge) to the tip, y the direction of rotation
  (the leading edge at zero pitch), z = x cross y (up for an unflapped main blade). The uavdamp lag link
  (before the feather rotation) is such a frame; the feather link is one too if its rotation is then left out
  of `pitch`. Positive flap coordinate of the model's RevoluteY flap hinge turns the tip DOWN; positive
  feather (RevoluteX) is nose-up pitch.
- Velocities of the air relative to a section, in the blade frame (w = v_air - v_section):
  U_T = -w.y (positive for a blade moving into still air), U_P = -w.z (positive when the air passes down
  through the disc: inflow, climb, flap-up rate), U_R = w.x (outward; Johnson's u_R = mu cos psi).
- Section angle of attack alpha = pitch - atan2(U_P, U_T); pitch is the chord's nose-up angle from the frame's
  y axis about +x (collective + cyclic + twist + feather deflection, rad).

Section model (no loops, independence principle): C_l = a (alpha - alpha_0) clipped at +-alpha_stall (lift
stops growing beyond the stall angle and stays there: no post-stall drop, chosen for robustness in
reversed or strongly inclined flow near the root); C_d = C_d0 + C_d2 alpha^2. Lift is normal to the in-plane
(U_T, U_P) flow, drag along it; the radial drag component C_d U U_R (yawed flow, Johnson) is included.
The aerodynamic centre lies on the feather axis and there is no pitching moment, tip loss or unsteady
(Theodorsen) lift: the inflow models (`uavdamp.helicopter.inflow`) carry the wake.

Span integration: Gauss-Legendre on [root cut-out, tip] by default (exact for polynomials of degree
2n - 1: on the uavdamp blade 4 stations give the hover thrust to 5e-6, 10 to 1e-10), midpoint rule
optional (second order: 1e-4 at 10 stations).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np

from uavdamp.helicopter import inflow as rotor_inflow

AIR_DENSITY = 1.225  # kg m-3, ISA sea level (Padfield's Bo-105 data are sea-level)
QUADRATURES = ("gauss", "midpoint")


@dataclass(frozen=True)
class BladeAero:
    """Geometry and airfoil of one rotor's blades; defaults: the Bo-105 main rotor on the uavdamp geometry.

    Lengths are from the blade's reference point (the flap hinge, `hinge_offset` from the shaft), so the tip
    radius is hinge_offset + length (5.597 m for uavdamp: hinge 0.687 m + the paper's blade length 4.91 m;
    Padfield's R = 4.91 m is that blade length, kept here as the blade length, with his chord: the solidity is
    then N c / (pi R) = 0.0614 rather than Padfield's 0.070). The values and their sources: config/config.yaml.
    """

    n_blades: int = 4
    hinge_offset: float = 0.687  # m, shaft to hinge (uavdamp config)
    length: float = 4.91  # m, hinge to tip (uavdamp config, the paper's blade length)
    chord: float = 0.27  # m
    twist_rad: float = -0.1082  # linear twist, pitch change from the shaft axis to the tip (Padfield's theta_tw)
    root_cutout: float = 0.0  # m from the hinge to the first lifting section
    lift_slope: float = 6.113  # rad-1
    alpha_zero_lift: float = 0.0  # rad
    cd0: float = 0.0074  # 1
    cd2: float = 0.0  # rad-2
    alpha_stall: float = 0.25  # rad, lift clipped beyond +-this angle
    n_stations: int = 10
    quadrature: str = "gauss"

    def __post_init__(self):
        checks = {
            "n_blades": self.n_blades >= 1,
            "hinge_offset": self.hinge_offset >= 0,
            "length": self.length > self.root_cutout,
            "chord": self.chord > 0,
            "root_cutout": self.root_cutout >= 0,
            "lift_slope": self.lift_slope > 0,
            "alpha_stall": self.alpha_stall > 0,
            "n_stations": self.n_stations >= 1,
            "quadrature": self.quadrature in QUADRATURES,
        }
        for name, ok in checks.items():
            if not ok:
                raise ValueError(f"BladeAero.{name}: invalid value {getattr(self, name)!r}")

    @property
    def tip_radius(self) -> float:
        """Rotor radius R, m (shaft to tip)."""
        return self.hinge_offset + self.length

    @property
    def disc_area(self) -> float:
        """pi R^2, m^2."""
        return np.pi * self.tip_radius**2

    @property
    def solidity(self) -> float:
        """N c / (pi R), 1."""
        return self.n_blades * self.chord / (np.pi * self.tip_radius)

    @cached_property
    def _quadrature(self) -> tuple[np.ndarray, np.ndarray]:
        lo, span = self.root_cutout, self.length - self.root_cutout
        if self.quadrature == "gauss":
            x, w = np.polynomial.legendre.leggauss(self.n_stations)
            return lo + 0.5 * span * (x + 1.0), 0.5 * span * w
        h = span / self.n_stations
        return lo + h * (np.arange(self.n_stations) + 0.5), np.full(self.n_stations, h)

    @property
    def stations(self) -> np.ndarray:
        """Station positions along the blade from the hinge, m, shape (S,)."""
        return self._quadrature[0]

    @property
    def weights(self) -> np.ndarray:
        """Quadrature weights, m, shape (S,): the integral of f over the span is f(stations) @ weights."""
        return self._quadrature[1]

    @cached_property
    def moment_weights(self) -> np.ndarray:
        """stations * weights, m^2: f(stations) @ moment_weights is the first moment about the hinge."""
        return self.stations * self.weights

    @cached_property
    def twist(self) -> np.ndarray:
        """Built-in twist at the stations, rad, (S,): twist_rad r / R, zero on the shaft axis (Padfield)."""
        return self.twist_rad * (self.hinge_offset + self.stations) / self.tip_radius

    def lock_number(self, flap_inertia: float, rho: float = AIR_DENSITY) -> float:
        """rho a c L^4 / I_beta with L the hinge-to-tip length, 1; flap_inertia about the hinge, kg m^2.

        With a hinge offset e the flap mode's aerodynamic damping ratio is (gamma / 16) (1 + 4 e / (3 L)) / nu_beta
        (uniform inflow, no stall); Padfield's gamma uses R = 4.91 m, which is this L.
        """
        return rho * self.lift_slope * self.chord * self.length**4 / flap_inertia


BO105_MAIN = BladeAero()
BO105_TAIL = BladeAero(
    n_blades=2,
    hinge_offset=0.0,  # m, the uavdamp tail blades start on the tail hub axis
    length=0.982,  # m, uavdamp config (paper); Padfield's tail radius is 0.95 m
    chord=0.18,
    twist_rad=0.0,
    lift_slope=5.7,
)
# The sourced values live in config/config.yaml (helicopter.aerodynamics.main_blade, tail_blade) with their sources;
# these defaults are the same numbers (tests/test_helicopter_flight.py checks it) for this module's standalone use.


class BladeLoads(NamedTuple):
    """Aerodynamic loads of B blades with S stations, in each blade's frame (x span, y rotation, z normal)."""

    force_per_length: np.ndarray  # N/m, (B, S, 3)
    force: np.ndarray  # N, (B, 3), integrated over the span
    moment: np.ndarray  # N m, (B, 3), about the blade frame's origin (the hinge)
    alpha: np.ndarray  # rad, (B, S), angle of attack before the stall clip


def section_velocities(
    blade: BladeAero,
    rotation: np.ndarray,
    origin_velocity: np.ndarray,
    angular_velocity: np.ndarray,
    air_velocity: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """U_T, U_P, U_R (m/s, each (B, S)) at the blade's stations from rigid-body kinematics, v = v_0 + omega x r.

    rotation: (B, 3, 3), columns the blade frame's axes in a common frame (Exudyn's link rotation matrix);
    origin_velocity: (B, 3), m/s, velocity of the blade frame's origin (hinge); angular_velocity: (B, 3), rad/s,
    of the blade; air_velocity: m/s, wind plus induced velocity in the common frame, (3,), (B, 3) or (B, S, 3).
    All vectors in the common frame (inertial, or any frame in which the velocities are taken).
    """
    rotation = np.asarray(rotation, dtype=float)
    air = np.asarray(air_velocity, dtype=float)
    s = blade.stations
    omega_b = (np.asarray(angular_velocity, dtype=float)[:, None, :] @ rotation)[:, 0, :]  # A^T omega, (B, 3)
    if air.ndim < 3:
        air = air.reshape((-1, 1, 3))
    relative = (np.asarray(origin_velocity, dtype=float)[:, None, :] - air) @ rotation  # A^T (v_0 - v_air)
    u_t = relative[..., 1] + omega_b[:, 2:3] * s
    u_p = relative[..., 2] - omega_b[:, 1:2] * s
    u_r = 0.0 * s - relative[..., 0]  # (B, S) also when the air velocity is one per blade
    return u_t, u_p, u_r


def blade_loads(
    blade: BladeAero,
    u_t: np.ndarray,
    u_p: np.ndarray,
    u_r: np.ndarray,
    pitch: np.ndarray,
    rho: float = AIR_DENSITY,
) -> BladeLoads:
    """Section forces and their span resultants for B blades at the blade's S stations (vectorised).

    u_t, u_p, u_r: (B, S), m/s, as `section_velocities`; pitch: rad, broadcastable to (B, S), including the
    twist (`blade.twist`); rho: kg/m^3. Moment about the hinge: M = integral of (s e_x) x f ds, so its y
    component is -integral s f_z ds (lift gives a negative moment about y: it lifts the tip against the
    model's tip-down flap coordinate) and its z component integral s f_y ds (drag gives a negative torque).
    """
    speed = np.sqrt(u_t * u_t + u_p * u_p)
    alpha = pitch - np.arctan2(u_p, u_t) - blade.alpha_zero_lift
    cl = blade.lift_slope * np.minimum(np.maximum(alpha, -blade.alpha_stall), blade.alpha_stall)
    cd = blade.cd0 + blade.cd2 * alpha * alpha if blade.cd2 else blade.cd0
    q = (0.5 * rho * blade.chord) * speed  # N s m-3 times the velocity components below give N/m
    f = np.empty((*speed.shape, 3))
    f[..., 0] = q * cd * u_r
    f[..., 1] = -q * (cl * u_p + cd * u_t)
    f[..., 2] = q * (cl * u_t - cd * u_p)
    per_component = f.transpose(0, 2, 1)  # (B, 3, S), a view
    first = per_component[:, 1:] @ blade.moment_weights  # (B, 2): integral of s f_y, s f_z
    moment = np.zeros((speed.shape[0], 3))
    moment[:, 1] = -first[:, 1]
    moment[:, 2] = first[:, 0]
    return BladeLoads(f, per_component @ blade.weights, moment, alpha)


def blade_rotations(hub_angle: float, n_blades: int) -> np.ndarray:
    """Rotation matrices (B, 3, 3) of unflapped blades at the model's hub angle (rad, about +z): RotZ(Psi_k).

    Psi_k = hub_angle + 2 pi k / N, measured from +x (forward) counter-clockwise, as the uavdamp tree places
    blade k. The Pitt-Peters azimuth is psi_k = Psi_k - pi (`inflow.blade_azimuth`).
    """
    psi = hub_angle + 2 * np.pi * np.arange(n_blades) / n_blades
    c, s = np.cos(psi), np.sin(psi)
    rot = np.zeros((n_blades, 3, 3))
    rot[:, 0, 0], rot[:, 0, 1], rot[:, 1, 0], rot[:, 1, 1], rot[:, 2, 2] = c, -s, s, c, 1.0
    return rot


def hover_loads(blade: BladeAero, collective: float, inflow_ratio: float, omega_rad_s: float, rho: float = AIR_DENSITY):
    """Loads of all blades of an unflapped rotor in hover with uniform inflow (lambda = v_i / (Omega R)).

    collective: pitch on the shaft axis, rad (the twist is added). Returns (BladeLoads, thrust N, shaft torque
    N m): thrust along +z, torque the aerodynamic moment about the shaft (negative: it opposes the rotation).
    """
    s = blade.stations
    u_t = np.broadcast_to(omega_rad_s * (blade.hinge_offset + s), (blade.n_blades, s.size))
    u_p = np.full_like(u_t, inflow_ratio * omega_rad_s * blade.tip_radius)
    loads = blade_loads(blade, u_t, u_p, np.zeros_like(u_t), collective + blade.twist, rho)
    thrust = float(loads.force[:, 2].sum())
    torque = float((loads.moment[:, 2] + blade.hinge_offset * loads.force[:, 1]).sum())
    return loads, thrust, torque


def hover_collective(
    blade: BladeAero, thrust: float, omega_rad_s: float, rho: float = AIR_DENSITY, iterations: int = 20
) -> tuple[float, float]:
    """Collective (rad, on the shaft axis) and inflow ratio that give `thrust` (N) in hover, uniform inflow.

    The inflow is momentum theory's for that thrust (`inflow.uniform_inflow`); the collective solves
    blade-element thrust = `thrust` by the secant method. The pitch at 0.75 R is collective + 0.75 twist_rad.
    """
    c_t = thrust / (rho * blade.disc_area * (omega_rad_s * blade.tip_radius) ** 2)
    lam = rotor_inflow.uniform_inflow(c_t, 0.0)
    theta = [0.0, 0.1]
    err = [hover_loads(blade, t, lam, omega_rad_s, rho)[1] - thrust for t in theta]
    for _ in range(iterations):
        if abs(err[1]) <= 1e-9 * abs(thrust) or err[1] == err[0]:
            break
        theta = [theta[1], theta[1] - err[1] * (theta[1] - theta[0]) / (err[1] - err[0])]
        err = [err[1], hover_loads(blade, theta[1], lam, omega_rad_s, rho)[1] - thrust]
    return theta[1], lam
