"""Kinematics of the rotorcraft's kinematic tree from its coordinates, and loads as generalized forces.

The tree of `uavdamp.helicopter.model` (links 0-2 PrismaticX/Y/Z, 3-5 RevoluteX/Y/Z: the fuselage; 6 the hub,
RevoluteZ, `hub_height` up; per main blade flap RevoluteY at RotZ(psi_k) and the hinge offset, lag RevoluteZ,
feather RevoluteX; last, the tail hub RevoluteY at its position). A link's frame is its parent's times the joint's
fixed rotation times the joint rotation, its origin the parent's plus the parent's rotation times the joint offset
(the same as Exudyn's SensorKinematicTree: tests/test_helicopter_flight.py). All vectors are in the model's
inertial axes. The flight runs compute the same frames and generalized forces inside one compiled call per step
(`uavdamp.helicopter.rotor_kernel`); this module is its tested reference and gives it the tree's fixed geometry.

Loads become generalized forces Q = J^T w, for a force F at point p and a moment M on a link: a prismatic
ancestor joint with axis a gets a . F, a revolute one through o gets a . (M + (p - o) x F). Set once per step as the
tree's ``jointForceVector``, they are constant during the step like the loads (no Jacobian work in Newton's
iterations, which made marker loads six times slower than the vacuum model here, measured), and a joint's share
stays the same while the blade turns during the step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from uavdamp.helicopter.model import HUB_LINK
from uavdamp.helicopter.params import Helicopter

_PLANES = ((1, 2), (2, 0), (0, 1))  # the plane each coordinate axis rotates


def _rot(axis: int, angle) -> np.ndarray:
    """Rotation matrices (..., 3, 3) about coordinate axis 0, 1 or 2 by `angle` (rad, scalar or array)."""
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros((*angle.shape, 3, 3))
    i, j = _PLANES[axis]
    out[..., axis, axis] = 1.0
    out[..., i, i] = c
    out[..., j, j] = c
    out[..., i, j] = -s
    out[..., j, i] = s
    return out


def _rot1(axis: int, angle: float) -> np.ndarray:
    """The rotation matrix (3, 3) about coordinate axis 0, 1 or 2 by a scalar `angle` rad (faster than `_rot`)."""
    c, s = math.cos(angle), math.sin(angle)
    if axis == 0:
        return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    if axis == 1:
        return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b along the last axis (numpy's cross costs more for these small arrays)."""
    a, b = np.broadcast_arrays(a, b)
    out = np.empty(a.shape)
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


@dataclass
class Frames:
    """The tree's state that the loads need, from `TreeKinematics.frames`."""

    fuselage: np.ndarray  # (3, 3) rotation of the fuselage
    fuselage_velocity: np.ndarray  # (3,) m/s of its centre of mass (the tree's origin point)
    axes: np.ndarray  # (3, 3) rows: the fuselage's RevoluteX, Y, Z axes
    hub: np.ndarray  # (3,) m, hub centre relative to the fuselage centre of mass
    blades: np.ndarray  # (B, 3, 3) rotations of the feather links (the blade frames)
    hinges: np.ndarray  # (B, 3) m, hinge points relative to the fuselage centre of mass
    hinge_velocity: np.ndarray  # (B, 3) m/s
    blade_omega: np.ndarray  # (B, 3) rad/s
    hinge_axes: np.ndarray  # (B, 3, 3): each blade's flap, lag and feather axis
    tail: np.ndarray  # (3, 3) rotation of the tail hub
    tail_point: np.ndarray  # (3,) m, tail hub centre relative to the fuselage centre of mass
    tail_velocity: np.ndarray  # (3,) m/s
    tail_omega: np.ndarray  # (3,) rad/s


class TreeKinematics:
    """Frames, velocities and generalized forces of the helicopter's tree (module docstring)."""

    def __init__(self, heli: Helicopter, n_coordinates: int):
        main = heli.main_rotor
        self.n = n_coordinates
        self.psi = 2 * np.pi * np.arange(main.n_blades) / main.n_blades
        self.azimuth = _rot(2, self.psi)  # (B, 3, 3) fixed joint rotations of the flap hinges
        self.hinge = main.hinge_offset * np.stack([np.cos(self.psi), np.sin(self.psi), 0 * self.psi], axis=1)
        self.hub_offset = np.array([0.0, 0.0, main.hub_height])
        self.tail_offset = np.asarray(heli.tail_rotor.position, dtype=float)
        self.flap = HUB_LINK + 1 + 3 * np.arange(main.n_blades)  # flap, lag, feather coordinates follow
        self.hinge_coordinates = (self.flap[:, None] + np.arange(3)).ravel()

    def frames(self, q: np.ndarray, q_t: np.ndarray) -> Frames:
        """The frames and velocities at coordinates `q` (rad, m) and velocities `q_t` (the tree's order)."""
        f, lag, feather = self.flap, self.flap + 1, self.flap + 2
        r3 = _rot1(0, q[3])
        r4 = r3 @ _rot1(1, q[4])
        r5 = r4 @ _rot1(2, q[5])
        axes = np.array([r3[:, 0], r4[:, 1], r5[:, 2]])
        omega_f = axes.T @ q_t[3:6]
        v_f = q_t[0:3]
        hub = r5 @ self.hub_offset
        r6 = r5 @ _rot1(2, q[HUB_LINK])
        omega_h = omega_f + r5[:, 2] * q_t[HUB_LINK]
        v_h = v_f + cross(omega_f, hub)
        base = r6 @ self.azimuth  # (B, 3, 3)
        r_flap = base @ _rot(1, q[f])
        r_lag = r_flap @ _rot(2, q[lag])
        blades = r_lag @ _rot(0, q[feather])
        hinge = self.hinge @ r6.T  # (B, 3): r6 @ hinge_k
        hinge_axes = np.stack([r_flap[:, :, 1], r_flap[:, :, 2], r_lag[:, :, 0]], axis=1)  # (B, 3 joints, 3)
        rates = q_t[self.hinge_coordinates].reshape(-1, 3)
        omega_b = omega_h + np.einsum("bki,bk->bi", hinge_axes, rates)
        v_hinge = v_h + cross(omega_h, hinge)
        tail_point = r5 @ self.tail_offset
        return Frames(
            fuselage=r5,
            fuselage_velocity=v_f,
            axes=axes,
            hub=hub,
            blades=blades,
            hinges=hub + hinge,
            hinge_velocity=v_hinge,
            blade_omega=omega_b,
            hinge_axes=hinge_axes,
            tail=r5 @ _rot1(1, q[-1]),
            tail_point=tail_point,
            tail_velocity=v_f + cross(omega_f, tail_point),
            tail_omega=omega_f + r5[:, 1] * q_t[-1],
        )

    def generalized_forces(self, frames: Frames, blade_force, blade_moment, tail_force, tail_moment, drag):
        """Q (n,) of forces (B, 3) at the hinges with moments (B, 3) on the blades, a force and moment on the tail hub
        (at its centre) and a force `drag` at the fuselage centre of mass; N, N m, global."""
        q = np.zeros(self.n)
        rotor_force = blade_force.sum(axis=0)
        q[0:3] = rotor_force + tail_force + drag
        about_hub = (blade_moment + cross(frames.hinges - frames.hub, blade_force)).sum(axis=0)
        about_cg = (
            about_hub
            + tail_moment
            + cross(np.array([frames.hub, frames.tail_point]), np.array([rotor_force, tail_force])).sum(axis=0)
        )
        q[3:6] = frames.axes @ about_cg
        q[HUB_LINK] = frames.fuselage[:, 2] @ about_hub
        # flap, lag and feather axes (B, 3, 3) against each blade's moment: the blades' hinge coordinates in order
        q[self.hinge_coordinates] = np.einsum("bki,bi->bk", frames.hinge_axes, blade_moment).ravel()
        q[-1] = frames.fuselage[:, 1] @ tail_moment
        return q
