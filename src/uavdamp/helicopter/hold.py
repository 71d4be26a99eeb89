"""The pilot of the flight runs: height hold on collective, attitude hold on cyclic and tail collective, and a slow
position hold that sets the roll and pitch the attitude hold holds.

Channels (h, phi, theta, psi): the height along "up" (against gravity) and the fuselage's RotX, RotY, RotZ tree
coordinates (roll, pitch, yaw relative to the trim attitude). Per channel a PID law asks for a generalized force
(N along up, N m about the joint axes)

    f = -(I w^2) e - (2 zeta w I) e' - (I w^2 / T_i) integral e,   w = 2 pi bandwidth_hz,

on the filtered error e; with the plant I e'' = f (I the channel's inertia: the helicopter's mass, the mass-matrix
diagonal of the fuselage rotations) that places the closed-loop poles at natural frequency w and damping ratio zeta
(the integral adds a slow pole near 1 / T_i). The four demands are mapped to control changes by the inverse of the
trim's control Jacobian (d generalized force / d control, `uavdamp.helicopter.trim`), which decouples collective,
cyclic and tail collective to first order.

Position hold (outer loop): the horizontal position p_h (the plane normal to "up") asks for an acceleration
a = -w_p^2 p_h - 2 zeta w_p p_h', w_p = 2 pi position_bandwidth_hz, and the attitude hold tracks pitch a_x / g and
roll -a_y / g (small tilts of the thrust). Without it the held attitude leaves the free helicopter accelerating
sideways at g times the difference between its mean thrust tilt and the held trim's (about 1 mrad, measured). The
outer loop is slow on purpose: at 0.05 Hz (with the attitude at 0.2 Hz) a 0.09 Hz oscillation of position, roll,
pitch and yaw grew over a 50 s hover run; at 0.02 Hz it did not (measured; the config's choice).

The errors and rates pass a moving average over one rotor revolution taken twice (a triangular window of two
revolutions): a double zero at every multiple of Omega (1/rev and the N/rev lines are not fed back, above about
-80 dB at 1/rev for the step's rounding of the revolution), a delay of one revolution (0.14 s, 15 degrees at
0.2 Hz). The bandwidth (config ``helicopter.flight.hold``) is a choice well below 1/rev (7.07 Hz).
"""

from __future__ import annotations

import math

import numpy as np

from uavdamp.helicopter.params import HoldOptions


class RevolutionFilter:
    """Two cascaded moving averages of `n` samples over vectors (a triangular window of 2 n - 1 samples)."""

    def __init__(self, n: int, initial: np.ndarray):
        self.n, self.i = int(n), 0
        x = np.asarray(initial, dtype=float)
        self.buffers = [np.tile(x, (self.n, 1)), np.tile(x, (self.n, 1))]
        self.sums = [self.n * x, self.n * x]

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """The filtered value after sample `x`."""
        y = np.asarray(x, dtype=float)
        for buffer, total in zip(self.buffers, self.sums, strict=True):
            total += y - buffer[self.i]
            buffer[self.i] = y
            y = total / self.n
        self.i = (self.i + 1) % self.n
        return y


def revolution_samples(omega_rad_s: float, step: float) -> int:
    """Steps in one rotor revolution, rounded (at least 1)."""
    return max(1, round(2 * math.pi / (omega_rad_s * step)))


class Hold:
    """The pilot: controls = trim controls + J^-1 f(filtered errors) (module docstring)."""

    def __init__(
        self, options: HoldOptions, trim_controls, control_jacobian, inertia, gravity, samples: int, step: float
    ):
        """control_jacobian: (4, 4) d(f_up, M_x, M_y, M_z)/d controls; inertia: (4,) kg, kg m2; gravity (3,) m/s2."""
        w, w_p = 2 * math.pi * options.bandwidth_hz, 2 * math.pi * options.position_bandwidth_hz
        inertia = np.asarray(inertia, dtype=float)
        self.kp, self.kd = inertia * w * w, 2 * options.damping_ratio * w * inertia
        self.ki = self.kp / options.integral_time
        self.position_gains = (w_p * w_p, 2 * options.damping_ratio * w_p)
        self.enabled, self.step = options.enabled, step
        self.trim = np.asarray(trim_controls, dtype=float)
        self.allocation = np.linalg.inv(control_jacobian)
        self.g = float(np.linalg.norm(gravity))
        self.up = -np.asarray(gravity, dtype=float) / self.g
        forward = np.array([1.0, 0.0, 0.0]) - self.up[0] * self.up
        forward /= np.linalg.norm(forward)
        self.horizontal = np.stack([forward, np.cross(self.up, forward)])  # (2, 3): horizontal x and y
        self.filter = RevolutionFilter(samples, np.zeros(12))
        self.integral = np.zeros(4)
        self.controls = self.trim.copy()

    def errors(self, q: np.ndarray, q_t: np.ndarray) -> np.ndarray:
        """(h, phi, theta, psi, their rates, horizontal position (2), velocity (2)) from the tree's coordinates and
        velocities (the fuselage's first)."""
        position, velocity = q[:3], q_t[:3]
        return np.concatenate(
            [
                [self.up @ position],
                q[3:6],
                [self.up @ velocity],
                q_t[3:6],
                self.horizontal @ position,
                self.horizontal @ velocity,
            ]
        )

    def __call__(self, q: np.ndarray, q_t: np.ndarray, step: float | None = None) -> np.ndarray:
        """The controls (collective, theta_1c, theta_1s, tail collective), rad, for the next step (of `step` s, the
        solver's by default; the filter counts samples, so a cut step shortens its window a little)."""
        filtered = self.filter(self.errors(q, q_t))
        if not self.enabled:
            return self.controls
        e, rate = filtered[:4].copy(), filtered[4:8]
        k_p, k_d = self.position_gains
        accel = -(k_p * filtered[8:10] + k_d * filtered[10:12])
        e[1] += accel[1] / self.g  # roll error against the reference -a_y / g
        e[2] -= accel[0] / self.g  # pitch error against the reference a_x / g
        self.integral += e * (self.step if step is None else step)
        demand = -(self.kp * e + self.kd * rate + self.ki * self.integral)
        self.controls = self.trim + self.allocation @ demand
        return self.controls
