"""The trim: controls and fuselage attitude that balance the helicopter, solved on the full Exudyn model.

Unknowns x = (collective theta_0, lateral cyclic theta_1c, longitudinal cyclic theta_1s, tail collective, roll,
pitch), rad. The fuselage is held at zero by six coordinate constraints while the rotors turn with aerodynamics,
inflow and gravity; the constraints' multipliers are the net applied generalized forces on the fuselage coordinates
(forces along x, y, z and moments about the joint axes, about the fuselage centre of mass, engine and tail drive
torques included). Their mean over two revolutions is the residual r(x): zero means thrust balances weight, the hub
moments and the rotor torque are balanced. The mean is the constant of a weighted least-squares fit of a constant
and the first HARMONICS multiples of the rotor azimuth (triangular weights over the two revolutions), so the
imbalanced rotor's 1/rev force of about 1e5 N does not leak into it; a plain triangular window of 2 x 142 steps
(a revolution is 141.5 steps at 1 ms) left about 1.2 N of it, circling (measured).

Newton's method in one continuing simulation: after `settle_s` from the start, the residual; then a finite-difference
Jacobian by stepping each unknown by `perturbation_rad` in turn (`step_settle_s` and a window each); then Newton
steps with Broyden updates of the Jacobian until max |r| (forces over the weight W, moments over W R) is below
`tolerance`. The attitude enters through the directions of gravity and free stream (`uavdamp.helicopter.flight`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from uavdamp.helicopter import inflow as rotor_inflow
from uavdamp.helicopter.aerodynamics import hover_collective, hover_loads
from uavdamp.helicopter.hold import revolution_samples
from uavdamp.helicopter.model import HUB_LINK
from uavdamp.helicopter.params import FlightRun
from uavdamp.helicopter.rotorloads import rotor_blades

HARMONICS = 4  # multiples of the rotor azimuth removed from the residual's mean (1/rev up to N/rev)
UNKNOWNS = ("collective", "lateral_cyclic", "longitudinal_cyclic", "tail_collective", "roll", "pitch")
MAX_STEP = 0.05  # rad, largest Newton change of any unknown (a choice: keeps the rotor out of stall while iterating)
# one row per step: held multipliers (6), main hub force (3), moment (3) in fuselage axes, tail force (3, global),
# drive torques (2), nu (3), tail inflow ratio (1)
ROW = 21


def initial_guess(heli: FlightRun, speed: float) -> tuple[np.ndarray, float, float]:
    """(x0, nu_0, tail inflow ratio): hover blade-element momentum theory for thrust = weight and the tail thrust
    that balances its torque; cyclics and attitude zero; speed only through Glauert's inflow (m/s)."""
    main_blade, tail_blade = rotor_blades(heli, heli.aerodynamics)
    rho, weight = heli.aerodynamics.air_density, heli.total_mass() * heli.flight.gravity
    omega, omega_t = heli.main_rotor.omega_rad_s, heli.tail_rotor.omega_rad_s
    theta_0, lam = hover_collective(main_blade, weight, omega, rho)
    torque = -hover_loads(main_blade, theta_0, lam, omega, rho)[2]
    arm = math.hypot(heli.tail_rotor.position[0], heli.tail_rotor.position[1])
    theta_t, lam_t = hover_collective(tail_blade, torque / arm, omega_t, rho)
    c_t = weight / (rho * main_blade.disc_area * (omega * main_blade.tip_radius) ** 2)
    nu_0 = rotor_inflow.uniform_inflow(c_t, speed / (omega * main_blade.tip_radius))
    return np.array([theta_0, 0.0, 0.0, -theta_t, 0.0, 0.0]), nu_0, -lam_t


@dataclass
class TrimResult:
    """The trim: unknowns x (UNKNOWNS, rad), scaled residual, Jacobian d r / d x (scaled), window means of ROW."""

    x: np.ndarray
    residual: np.ndarray
    jacobian: np.ndarray
    means: np.ndarray
    scale: np.ndarray  # N, N, N, N m, N m, N m: residual = multipliers / scale
    iterations: int
    converged: bool
    state: tuple[np.ndarray, np.ndarray]
    nu: np.ndarray
    tail_lambda: float
    time: float  # s simulated
    history: list  # (x, scaled residual) of every phase
    deviation: np.ndarray  # N, N m: the held multipliers at the end minus their mean (the 1/rev load on the fuselage)

    def control_jacobian(self, up: np.ndarray) -> np.ndarray:
        """(4, 4) d(force along `up` N, moments about the fuselage axes N m) / d(the four controls rad)."""
        raw = self.scale[:, None] * self.jacobian[:, :4]
        return np.vstack([up @ raw[:3], raw[3:]])


def harmonic_mean(rows: np.ndarray, azimuth: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Mean of each column of `rows` (n, m) with the 1..HARMONICS multiples of `azimuth` (n,) rad fitted out."""
    k = np.arange(1, HARMONICS + 1)
    design = np.column_stack([np.ones_like(azimuth), np.cos(np.outer(azimuth, k)), np.sin(np.outer(azimuth, k))])
    root = np.sqrt(weights)[:, None]
    return np.linalg.lstsq(design * root, rows * root, rcond=None)[0][0]


class TrimPilot:
    """The trim's state machine, called every step by `flight.Simulation` (module docstring)."""

    def __init__(self, sim, x0, nu0: float, tail_lambda: float):
        heli, options = sim.heli, sim.heli.flight.trim
        step = sim.options.step
        n = revolution_samples(heli.main_rotor.omega_rad_s, step)
        self.window = np.convolve(np.ones(n), np.ones(n)) / (n * n)
        weight = heli.total_mass() * heli.flight.gravity
        radius = heli.main_rotor.hinge_offset + heli.main_rotor.blade_length
        self.scale = np.array([weight] * 3 + [weight * radius] * 3)
        self.options, self.x = options, np.asarray(x0, dtype=float).copy()
        self.rows, self.azimuth = np.zeros((self.window.size, ROW)), np.zeros(self.window.size)
        self.settle = round(options.settle / step)
        self.step_settle = round(options.step_settle / step)
        self.phase_end, self.k = self.settle + self.window.size, 0
        self.stage, self.iterations, self.done = -1, 0, False  # stage -1: first residual, 0-5: Jacobian columns
        self.jacobian = np.zeros((6, 6))
        self.residual = self.previous = self.means = None
        self.last_step = np.zeros(6)
        self.history = []  # (x, scaled residual) of every phase
        sim.loads.nu[0], sim.loads.tail_lambda = nu0, tail_lambda
        sim.set_attitude(self.x[4], self.x[5])

    def __call__(self, sim, q, q_t):
        if self.done:
            return None
        start = self.phase_end - self.window.size
        if self.k >= start:
            held, drive = sim.multipliers()
            loads = sim.loads.loads
            self.azimuth[self.k - start] = q[HUB_LINK]
            self.rows[self.k - start] = np.concatenate(
                [
                    held,
                    loads.main_force,
                    loads.main_moment,
                    loads.tail_force,
                    drive,
                    sim.loads.nu,
                    [sim.loads.tail_lambda],
                ]
            )
        self.k += 1
        if self.k == self.phase_end:
            self.means = harmonic_mean(self.rows, self.azimuth, self.window)
            self._next(self.means[:6] / self.scale)
            sim.set_attitude(self.x[4], self.x[5])
            self.k, self.phase_end = 0, self.step_settle + self.window.size
        return None if self.done else self.x[:4]

    def _next(self, residual: np.ndarray) -> None:
        """The unknowns for the next phase from the residual just measured."""
        delta = self.options.perturbation
        self.history.append((self.x.copy(), residual))
        if 0 <= self.stage <= 5:
            self.jacobian[:, self.stage] = (residual - self.previous) / delta
        elif self.stage == 6:  # a Newton step was taken: converged, or Broyden's update
            self.iterations += 1
            step = self.last_step
            self.jacobian += np.outer(residual - self.previous - self.jacobian @ step, step) / (step @ step)
        self.residual, self.previous = residual, residual
        if self.stage == 6 and (
            np.abs(residual).max() <= self.options.tolerance or self.iterations >= self.options.max_iterations
        ):
            self.done = True
            return
        if self.stage < 5:
            self.stage += 1
            self.x[self.stage] += delta
            return
        self.stage = 6
        step = -np.linalg.solve(self.jacobian, residual)
        self.last_step = step * min(1.0, MAX_STEP / np.abs(step).max())
        self.x += self.last_step


def trim(sim, x0, nu0: float, tail_lambda: float) -> TrimResult:
    """Solve the trim on a held-fuselage `flight.Simulation` (module docstring); the simulation ends trimmed."""
    options = sim.heli.flight.trim
    pilot = TrimPilot(sim, x0, nu0, tail_lambda)
    phases = 7 + options.max_iterations
    duration = options.settle + phases * (options.step_settle + 2 * pilot.window.size * sim.options.step)
    sim.solve(duration, pilot)
    if pilot.means is None or not pilot.done:
        raise RuntimeError("helicopter trim: the simulation ended before the trim's last residual")
    converged = bool(np.abs(pilot.residual).max() <= options.tolerance)
    return TrimResult(
        x=pilot.x.copy(),
        residual=pilot.residual,
        jacobian=pilot.jacobian,
        means=pilot.means,
        scale=pilot.scale,
        iterations=pilot.iterations,
        converged=converged,
        state=sim.state(),
        nu=sim.loads.nu.copy(),
        tail_lambda=sim.loads.tail_lambda,
        time=float(sim.mbs.systemData.GetTime()),
        history=pilot.history,
        deviation=sim.multipliers()[0] - pilot.means[:6],
    )
