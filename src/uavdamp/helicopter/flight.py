"""Flight runs: the rotorcraft with blade-element aerodynamics, inflow and gravity, trimmed, then flown by its pilot.

A flight condition is "hover" or "forward" (advance ratio ``helicopter.flight.forward_advance_ratio`` along the
fuselage's x). The model is flown in a wind: the air moves past a helicopter that stays near the origin, so the
mount-motion contract of `uavdamp.helicopter.model` holds unchanged (frame: the fuselage axes at t = 0, which are
the trim attitude). The trim attitude (roll phi, pitch theta) enters as the directions of gravity and of the free
stream in those axes: gravity R^T (0, 0, -g), free stream R^T (-V, 0, 0), R = RotX(phi) RotY(theta) (no ground, so
this equals tilting the helicopter). The tail rotor turns at ``tail_rotor.omega_running_rad_s``.

`run`: `uavdamp.helicopter.trim.trim` on the held fuselage; then the free fuselage from the trimmed state (every
rotor coordinate, velocity and the inflow), released by `Tether` over ``flight.release_s`` with the pilot
`uavdamp.helicopter.hold.Hold` already flying; then the recorded ``solver.duration_s`` (times from its start).
"""

from __future__ import annotations

import math
from dataclasses import replace

import exudyn as exu
import numpy as np

from uavdamp.helicopter import model as H
from uavdamp.helicopter import trim as T
from uavdamp.helicopter.hold import Hold, revolution_samples
from uavdamp.helicopter.params import FlightRun, SolverOptions
from uavdamp.helicopter.rotorloads import RotorLoads, feather_offsets

FLIGHT_RUNS = ("hover", "forward")


def flight_helicopter(heli: FlightRun) -> FlightRun:
    """The helicopter of the flight runs: its tail rotor turning at omega_running_rad_s."""
    return heli.with_tail_rotor_speed(heli.tail_rotor.omega_running_rad_s)


def advance_ratio(heli: FlightRun, condition: str) -> float:
    """mu of a flight condition ("hover": 0; "forward": the config's), 1."""
    if condition not in FLIGHT_RUNS:
        raise ValueError(f"flight condition {condition!r}: not one of {list(FLIGHT_RUNS)}")
    return heli.flight.forward_advance_ratio if condition == "forward" else 0.0


def attitude_matrix(roll: float, pitch: float) -> np.ndarray:
    """R = RotX(roll) RotY(pitch): the fuselage's attitude in an inertial frame with z up."""
    cr, sr, cp, sp = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch)
    rot_x = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    rot_y = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    return rot_x @ rot_y


def environment(heli: FlightRun, speed: float, roll: float, pitch: float) -> tuple[np.ndarray, np.ndarray]:
    """(gravity m/s2, free stream m/s) in the fuselage axes at attitude (roll, pitch), flight speed `speed` m/s."""
    rot = attitude_matrix(roll, pitch)
    return rot.T @ [0.0, 0.0, -heli.flight.gravity], rot.T @ [-speed, 0.0, 0.0]


def flight_speed(heli: FlightRun, condition: str) -> float:
    """Flight speed, m/s: advance ratio times the main rotor's tip speed (hinge offset + blade length)."""
    main = heli.main_rotor
    return advance_ratio(heli, condition) * main.omega_rad_s * (main.hinge_offset + main.blade_length)


class Simulation:
    """One flight model: the tree (fuselage held or free), its rotor loads, a pilot called every step.

    pilot(sim, q, q_t) -> controls (collective, theta_1c, theta_1s, tail collective) rad, or None to stop.
    Every output step the record keeps the time, controls, inflow and loads (`samples`).
    """

    def __init__(self, heli: FlightRun, options: SolverOptions, speed: float, *, held: bool, initial=None, nu=None):
        self.heli, self.options, self.speed = heli, options, speed
        self.model = H.build(heli, fix_fuselage=held, initial=initial)
        self.mbs = self.model.mbs
        self.gravity, wind = environment(heli, speed, 0.0, 0.0)
        self.loads = RotorLoads(
            self.model, heli, heli.aerodynamics, wind, heli.flight.fuselage_drag_area, options.step, nu
        )
        self.mbs.SetObjectParameter(0, "gravity", list(self.gravity))
        self.mbs.Assemble()
        n = len(self.mbs.GetObjectParameter(0, "jointTypes"))
        self.offsets, self.rates = np.zeros(n), np.zeros(n)
        self.feathers = [H.HUB_LINK + 3 + 3 * k for k in range(heli.main_rotor.n_blades)]
        self.controls = np.zeros(4)
        self.pilot = None
        self.count, self.samples, self.next_sample = 0, [], 0.0
        self.time, self.step = 0.0, options.step  # s: the state's time and the step being taken (may be cut)
        self._inflow = (self.loads.nu.copy(), 0.0)  # the inflow at the start of the step being taken
        ae, held_coordinates = self.mbs.systemData.GetObjectLTGAE, self.model.constraints
        self.drive_index = [ae(held_coordinates[c])[0] for c in (H.HUB_LINK, n - 1)]
        self.held_index = [ae(held_coordinates[c])[0] for c in range(6)] if held else []

    def set_attitude(self, roll: float, pitch: float) -> None:
        """Gravity and free stream of the trim attitude (module docstring), from the next step on."""
        self.gravity, self.loads.wind = environment(self.heli, self.speed, roll, pitch)
        self.mbs.SetObjectParameter(0, "gravity", list(self.gravity))

    def multipliers(self) -> tuple[np.ndarray, np.ndarray]:
        """(held fuselage coordinates 0-5, drives of the main and tail hub): the applied generalized force each
        constraint holds, N or N m (checked against gravity in tests/test_helicopter_flight.py); the drives are the
        torques on the hubs' coordinates that keep the rotor speeds."""
        ae = np.asarray(self.mbs.systemData.GetAECoordinates())
        return ae[self.held_index], ae[self.drive_index]

    def pre_step(self, mbs, t: float) -> bool:
        """Exudyn's pre-step function: `t` is the end of the step, the state at its start. When Newton's iterations
        fail, Exudyn retries the step shorter and calls this again from the same start: the controls are kept, the
        inflow goes back to the start's and advances over the shorter step."""
        start = mbs.systemData.GetTime(exu.ConfigurationType.StartOfStep)
        retry, self.time, self.step = start == self.time and self.count > 0, start, t - start
        q = np.asarray(mbs.systemData.GetODE2Coordinates())
        q_t = np.asarray(mbs.systemData.GetODE2Coordinates_t())
        if retry:
            self.loads.nu[:], self.loads.tail_lambda = self._inflow
            self.loads.step = self.step
            self.loads.update(q, q_t)
            return True
        self._inflow = (self.loads.nu.copy(), self.loads.tail_lambda)
        controls = self.pilot(self, q, q_t)
        if controls is None:
            return False
        self.controls = controls
        self.loads.tail_collective = controls[3]
        offsets, rates = feather_offsets(self.heli, controls, q[H.HUB_LINK], self.step)
        self.offsets[self.feathers], self.rates[self.feathers] = offsets, rates
        mbs.SetObjectParameter(0, "jointPositionOffsetVector", self.offsets)
        mbs.SetObjectParameter(0, "jointVelocityOffsetVector", self.rates)
        self.loads.step = self.step
        loads = self.loads.update(q, q_t)
        if self.time >= self.next_sample - 1e-3 * self.options.step:
            self._record(self.time, loads)
        self.count += 1
        return True

    def _record(self, t: float, loads) -> None:
        """A sample of the record at state time `t` s, every output step (the sensors' times)."""
        row = [[t], self.controls, self.loads.nu, loads.main_force, loads.main_moment, loads.total_force]
        self.samples.append(np.concatenate(row))
        self.next_sample += self.options.output_step

    def solve(self, duration: float, pilot) -> dict:
        """Integrate `duration` s (or until the pilot stops); solver statistics. The record gets the final state."""
        self.pilot = pilot
        self.mbs.SetPreStepUserFunction(self.pre_step)
        stats = H.solve(self.model, replace(self.options, duration=duration))
        self.time = self.mbs.systemData.GetTime()  # the end of the last step
        if self.time >= self.next_sample - 1e-3 * self.options.step:
            self._record(self.time, self.loads.update(*self.state()))
        return stats

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        """(coordinates, velocities) of the tree now."""
        data = self.mbs.systemData
        return np.asarray(data.GetODE2Coordinates()), np.asarray(data.GetODE2Coordinates_t())


def start_state(heli: FlightRun, collective: float) -> tuple[np.ndarray, np.ndarray]:
    """(coordinates, velocities) of the trim's start: rotors at speed, feathers at `collective` rad, all else 0."""
    n = len(H.tree_links(heli))
    q, q_t = np.zeros(n), np.zeros(n)
    q[[H.HUB_LINK + 3 + 3 * k for k in range(heli.main_rotor.n_blades)]] = collective
    q_t[H.HUB_LINK], q_t[-1] = heli.main_rotor.omega_rad_s, heli.tail_rotor.omega_rad_s
    return q, q_t


def trimmed(heli: FlightRun, condition: str):
    """(flight helicopter, speed m/s, `trim.TrimResult`) of a flight condition."""

    heli = flight_helicopter(heli)
    speed = flight_speed(heli, condition)
    x0, nu0, tail_lambda = T.initial_guess(heli, speed)
    sim = Simulation(heli, heli.solver, speed, held=True, initial=start_state(heli, x0[0]))
    return heli, speed, T.trim(sim, x0, nu0, tail_lambda)


TETHER_START = 100.0  # 1, the tether's first stiffness over I Omega^2 (fuselage held: its natural frequency 10/rev)
TETHER_END = 1e-5  # 1, ... and its last before it is removed (natural frequency 0.003/rev)
TETHER_DAMPING = 0.7  # 1, damping ratio of each tether (crosses 1/rev resonance with an amplification near 0.7)


class Tether:
    """The release of the fuselage from the trim: its six tree coordinates on spring-dampers (the tree's PD terms)
    of stiffness TETHER_START I Omega^2 decaying exponentially to TETHER_END I Omega^2 over `duration` s, then
    removed. The fuselage settles onto its forced motion with its mean held where the trim had it (a choice: a
    sudden release from the held state started a 45 mrad roll offset and a drift, measured)."""

    def __init__(self, sim: Simulation, inertia: np.ndarray, duration: float):
        self.sim, self.inertia, self.duration = sim, np.asarray(inertia, dtype=float), duration
        self.stiffness = np.asarray(sim.mbs.GetObjectParameter(0, "jointPControlVector"), dtype=float)
        self.damping = np.asarray(sim.mbs.GetObjectParameter(0, "jointDControlVector"), dtype=float)
        self.rate = math.log(TETHER_START / TETHER_END) / duration
        self.omega = sim.heli.main_rotor.omega_rad_s
        self.on = True

    def __call__(self, t: float) -> None:
        """Set the tether for time `t` s after the release (a Jacobian update every 16 steps while it changes)."""
        if not self.on:
            return
        ratio = TETHER_START * math.exp(-self.rate * t) if t < self.duration else 0.0
        k = ratio * self.inertia * self.omega**2
        self.stiffness[:6], self.damping[:6] = k, 2 * TETHER_DAMPING * np.sqrt(k * self.inertia)
        mbs = self.sim.mbs
        mbs.SetObjectParameter(0, "jointPControlVector", self.stiffness)
        mbs.SetObjectParameter(0, "jointDControlVector", self.damping)
        if self.sim.count % 16 == 0 or ratio == 0.0:  # every 16 steps while it changes
            mbs.solverSignalJacobianUpdate = True
        self.on = ratio > 0.0


def release(heli: FlightRun, speed: float, result) -> tuple[Simulation, np.ndarray]:
    """The free-fuselage simulation started from a trim's final state (fuselage at rest at zero, every rotor
    coordinate, velocity and the inflow as trimmed); (sim, mass matrix M of the tree there)."""
    q, q_t = (v.copy() for v in result.state)
    q[:6], q_t[:6] = 0.0, 0.0
    sim = Simulation(heli, heli.solver, speed, held=False, initial=(q, q_t), nu=result.nu)
    sim.loads.tail_lambda = result.tail_lambda
    sim.set_attitude(result.x[4], result.x[5])
    mass = np.asarray(
        sim.mbs.ComputeLinearizedSystem(exu.SimulationSettings(), projectIntoConstraintNullspace=False)[0]
    )
    return sim, mass


def pilot_of(sim: Simulation, result, mass: np.ndarray):
    """The hold for a released simulation: trim controls, the trim's control Jacobian, inertias from `mass`."""

    heli = sim.heli
    up = -sim.gravity / np.linalg.norm(sim.gravity)
    inertia = np.array([heli.total_mass(), mass[3, 3], mass[4, 4], mass[5, 5]])
    samples = revolution_samples(heli.main_rotor.omega_rad_s, sim.options.step)
    return Hold(
        heli.flight.hold, result.x[:4], result.control_jacobian(up), inertia, sim.gravity, samples, sim.options.step
    )


def fly_trimmed(heli: FlightRun, speed: float, result):
    """Release the trimmed helicopter and fly it (release, then the record); (simulation, solver statistics)."""
    sim, mass = release(heli, speed, result)
    hold = pilot_of(sim, result, mass)
    tether = Tether(sim, np.diag(mass)[:6], heli.flight.release)

    def pilot(s, q, q_t):
        tether(s.time)
        return hold(q, q_t, s.step)

    return sim, sim.solve(heli.flight.release + heli.solver.duration, pilot)


# the config keys that set a trim: what a failed trim's message names
TRIM_KEYS = (
    "helicopter.fuselage.mass_kg",
    "helicopter.main_rotor.omega_rad_s",
    "helicopter.flight.forward_advance_ratio",
    "helicopter.flight.trim.tolerance",
    "helicopter.flight.trim.max_iterations",
)


class TrimError(RuntimeError):
    """A trim that did not meet helicopter.flight.trim.tolerance (and helicopter.flight.allow_unconverged is false)."""


def trim_failure(heli: FlightRun, condition: str, result) -> str:
    """The text of an unconverged trim: condition, residual against its tolerance, the keys that set it."""
    options = heli.flight.trim
    worst = int(np.argmax(np.abs(result.residual)))
    return (
        f"helicopter {condition} trim did not converge: largest residual {np.abs(result.residual).max():.3g} "
        f"(component {worst}: {'force' if worst < 3 else 'moment'}; forces / W, moments / W R) above "
        f"helicopter.flight.trim.tolerance = {options.tolerance:g} after {result.iterations} Newton steps "
        f"(helicopter.flight.trim.max_iterations = {options.max_iterations}; last controls and attitude "
        f"{dict(zip(T.UNKNOWNS, np.round(result.x, 4).tolist(), strict=True))} rad). The trim is set by "
        f"{', '.join(TRIM_KEYS)}: fuselage.mass_kg = {heli.fuselage.mass:g}, main_rotor.omega_rad_s = "
        f"{heli.main_rotor.omega_rad_s:g}, advance ratio {advance_ratio(heli, condition):g}"
    )


def fly(heli: FlightRun, condition: str):
    """Trim, release and fly one flight condition; (simulation, trim result, solver statistics). TrimError
    (`trim_failure`) when the trim did not converge, unless helicopter.flight.allow_unconverged is true: then the
    run is flown and the datasets record it (`uavdamp.helicopter.flightdata`)."""
    heli, speed, result = trimmed(heli, condition)
    if not result.converged and not heli.flight.allow_unconverged:
        raise TrimError(
            trim_failure(heli, condition, result) + "; set helicopter.flight.allow_unconverged: true to fly it "
            "anyway (the run records trim_converged = 0 and every case taking it is flagged)"
        )
    sim, stats = fly_trimmed(heli, speed, result)
    return sim, result, stats
