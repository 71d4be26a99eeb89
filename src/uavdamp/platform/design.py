"""Closed-form design of the camera platform: the pitch link's inertia, the mass matrix, the stiffnesses.

Stiffnesses are not config inputs: the displacement spring and the servos' proportional gains are designed
so that the undamped, base-clamped platform has the configured natural frequencies (paper Table 1: 6.7, 5.7,
4.5 Hz). The yaw mode is uncoupled (it takes the middle frequency); displacement and pitch are coupled
through the camera's forward offset and take the outer two. `uavdamp.platform.modes` checks the design by
Exudyn's eigen-analysis.
"""

from __future__ import annotations

import math

import numpy as np

from uavdamp.platform.params import Structure

COORDINATES = ("displacement", "yaw", "pitch")


def pitch_link(s: Structure) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass (kg), COM (m, pitch-axis frame) and inertia about that COM (kg m2) of pitch body + camera."""
    a, b, c = s.camera_size
    cam_inertia = s.camera_mass / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    cam_com = np.array([s.camera_com_x, 0.0, s.camera_com_z])
    mass = s.pitch_body_mass + s.camera_mass
    com = s.camera_mass * cam_com / mass  # the pitch body's COM is on the pitch axis (origin)

    def shifted(m, inertia, r):  # parallel-axis theorem, from the body's COM to `com`
        d = r - com
        return inertia + m * (d @ d * np.eye(3) - np.outer(d, d))

    inertia = shifted(s.camera_mass, cam_inertia, cam_com) + shifted(
        s.pitch_body_mass, s.pitch_body_inertia * np.eye(3), np.zeros(3)
    )
    return mass, com, inertia


def mass_matrix(s: Structure) -> np.ndarray:
    """Closed-form mass matrix of the clamped platform in (displacement, yaw, pitch) at rest.

    Units: kg, kg m, kg m2 (coordinates in m, rad, rad).
    """
    m_pl, com, inertia = pitch_link(s)
    x, _, z = com
    m = np.zeros((3, 3))
    m[0, 0] = s.intermediate_mass + m_pl
    m[1, 1] = s.intermediate_yaw_inertia + inertia[2, 2] + m_pl * x * x
    m[2, 2] = inertia[1, 1] + m_pl * (x * x + z * z)
    m[0, 2] = m[2, 0] = -m_pl * x  # pitching by theta moves a point at x down by x * theta
    return m


def design_stiffness(s: Structure, gravity: float = 0.0) -> np.ndarray:
    """Displacement spring (N m-1) and yaw, pitch servo P gains (N m rad-1) meeting the targets.

    With `gravity` (m s-2) the pitch gain also carries the pitch link's pendulum term: its centre of mass z_c
    above the pitch axis gives the stiffness -m g z_c (the weight's moment about the axis grows with the angle),
    so the servo's gain is the target stiffness plus m g z_c; the displacement spring and the yaw axis see no
    gravity stiffness (a constant force, a vertical axis).

    Closed form: yaw is uncoupled, k_yaw = omega_mid^2 J_yaw. For the coupled (displacement,
    pitch) pair with mass matrix [[m11, m12], [m12, m22]] and diagonal stiffness (k1, k2),
    det(K - lambda M) = 0 has the roots lambda_a, lambda_b (outer targets squared, rad2 s-2) iff
    k1 k2 = det(M) lambda_a lambda_b and k1 m22 + k2 m11 = det(M) (lambda_a + lambda_b).
    Of the two solutions, the one with the displacement mode the higher one is taken.
    """
    lam = np.sort((2 * np.pi * np.asarray(s.natural_frequencies_hz)) ** 2)
    m = mass_matrix(s)
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
            f"platform.structure.camera_com_x_m: the displacement-pitch coupling "
            f"{coupling:.3f} is too strong to place the modes at {s.natural_frequencies_hz} Hz"
        )
    k1 = (total + math.sqrt(disc)) / (2 * m22)
    k2 = prod / k1
    m_pl, com, _ = pitch_link(s)
    return np.array([k1, lam_mid * m[1, 1], k2 + m_pl * gravity * com[2]])
