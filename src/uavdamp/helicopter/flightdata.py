"""A flight run's outputs: the mount motion (the vacuum runs' contract), the pilot's record and the trim.

`run(heli, condition)` -> (run dataset, trim dataset). The run dataset has `mount_displacement`, `mount_rotation`
(`uavdamp.helicopter.model.motion_dataset`, from the start of the record) and the record of the controls, inflow
and loads over the same time. The trim dataset holds scalars: the trim (thrust, weight, induced velocity,
collective, cyclics, tail collective, power, attitude, its residual) and how the pilot held it during the record
(per-revolution vertical aerodynamic force over the weight, per-revolution attitude).
"""

from __future__ import annotations

import json
import math

import numpy as np
import xarray as xr

from uavdamp.helicopter import model as H
from uavdamp.helicopter.flight import Simulation, advance_ratio, flight_speed, fly, trim_failure
from uavdamp.helicopter.params import FlightRun
from uavdamp.helicopter.rotorloads import rotor_blades
from uavdamp.helicopter.trim import TrimResult

SAMPLE_VARIABLES = (
    ("collective", "rad", "main rotor collective pitch on the shaft axis"),
    ("lateral_cyclic", "rad", "lateral cyclic theta_1c (pitch theta_1c cos psi, psi = 0 over the tail)"),
    ("longitudinal_cyclic", "rad", "longitudinal cyclic theta_1s (pitch theta_1s sin psi)"),
    ("tail_collective", "rad", "tail rotor collective pitch (negative: thrust to the right, -y)"),
    ("inflow_uniform", "1", "main rotor inflow ratio nu_0 (induced velocity over Omega R)"),
    ("inflow_sine", "1", "main rotor inflow ratio nu_s (Pitt-Peters sine state)"),
    ("inflow_cosine", "1", "main rotor inflow ratio nu_c (Pitt-Peters cosine state)"),
)
_AXIS = {"units": "1", "long_name": "axis (x forward, y left, z up)"}


def samples_dataset(sim: Simulation, start: float) -> xr.Dataset:
    """The pilot's record from `start` s on (time from 0): controls, inflow, main rotor hub loads, all loads."""
    data = np.array(sim.samples)
    data = data[data[:, 0] >= start - 0.5 * sim.options.step]
    out = {
        name: ("time", data[:, 1 + k], {"units": u, "long_name": d}) for k, (name, u, d) in enumerate(SAMPLE_VARIABLES)
    }
    loads = (
        ("hub_force", 8, "N", "main rotor aerodynamic force, fuselage axes"),
        ("hub_moment", 11, "N m", "main rotor aerodynamic moment about the hub centre, fuselage axes"),
        ("aerodynamic_force", 14, "N", "every aerodynamic force (main, tail, fuselage drag), the model's axes"),
    )
    for name, col, unit, text in loads:
        out[name] = (("time", "axis"), data[:, col : col + 3], {"units": unit, "long_name": text})
    time = ("time", data[:, 0] - start, {"units": "s", "long_name": "simulation time"})
    return xr.Dataset(out, coords={"time": time, "axis": ("axis", list(H.AXES), _AXIS)})


FLIGHT_ROTATION = (
    "rotation vector of R(t), the fuselage attitude relative to its trim attitude (the frame's axes are the fuselage "
    "axes at the trim attitude; gravity and free stream are tilted in it, trim.nc holds the attitude)"
)


def held(record: xr.Dataset, angles: np.ndarray, heli: FlightRun, up: np.ndarray) -> dict[str, float]:
    """How the pilot held the trim over whole revolutions of the record: extremes of the per-revolution mean
    vertical aerodynamic force over the weight, and the largest per-revolution mean of the fuselage's tree angles
    (roll, pitch, yaw from the trim attitude: `angles` (3, n) rad at the record's times)."""
    time = record.time.values
    period = 2 * math.pi / heli.main_rotor.omega_rad_s
    revolution = np.floor((time + 1e-9) / period).astype(int)
    whole = revolution < revolution.max()
    vertical = record.aerodynamic_force.values @ up / (heli.total_mass() * heli.flight.gravity)
    means = np.array([vertical[revolution == k].mean() for k in np.unique(revolution[whole])])
    attitude = np.array([np.abs(angles[:, revolution == k].mean(axis=1)).max() for k in np.unique(revolution[whole])])
    return {
        "thrust_ratio_min": float(means.min()),
        "thrust_ratio_max": float(means.max()),
        "attitude_deviation_max": float(attitude.max()),
    }


def trim_dataset(heli: FlightRun, condition: str, result: TrimResult, hold: dict) -> xr.Dataset:
    """Scalars of the trim and of the held flight (module docstring), with units."""
    main_blade, _ = rotor_blades(heli, heli.aerodynamics)
    m = result.means
    rho, omega = heli.aerodynamics.air_density, heli.main_rotor.omega_rad_s
    thrust, weight = m[8], heli.total_mass() * heli.flight.gravity
    x = result.x
    values = {
        "thrust": (thrust, "N", "main rotor thrust (aerodynamic force along the shaft), trim mean"),
        "weight": (weight, "N", "weight of the whole helicopter"),
        "induced_velocity": (
            m[17] * omega * main_blade.tip_radius,
            "m s-1",
            "main rotor mean induced velocity nu_0 Omega R",
        ),
        "momentum_induced_velocity": (
            math.sqrt(max(thrust, 0.0) / (2 * rho * main_blade.disc_area)),
            "m s-1",
            "momentum theory's hover induced velocity sqrt(T / (2 rho A)) for that thrust",
        ),
        "collective": (x[0], "rad", "main rotor collective pitch on the shaft axis"),
        "collective_75": (x[0] + 0.75 * main_blade.twist_rad, "rad", "main rotor collective pitch at 0.75 R"),
        "lateral_cyclic": (x[1], "rad", "lateral cyclic theta_1c (psi = 0 over the tail)"),
        "longitudinal_cyclic": (x[2], "rad", "longitudinal cyclic theta_1s"),
        "tail_collective": (x[3], "rad", "tail rotor collective pitch"),
        "roll_attitude": (x[4], "rad", "fuselage roll attitude of the trim (RotX; right side down is positive)"),
        "pitch_attitude": (x[5], "rad", "fuselage pitch attitude of the trim (RotY; nose down is positive)"),
        "main_power": (-m[15] * omega, "W", "main rotor shaft power (drive torque x Omega)"),
        "tail_power": (-m[16] * heli.tail_rotor.omega_rad_s, "W", "tail rotor shaft power"),
        "tail_thrust": (m[13], "N", "tail rotor force along the fuselage y (negative: to the right)"),
        "advance_ratio": (advance_ratio(heli, condition), "1", "free stream over the main rotor tip speed"),
        "flight_speed": (flight_speed(heli, condition), "m s-1", "free stream speed"),
        "trim_residual": (
            float(np.abs(result.residual).max()),
            "1",
            "largest trim residual (forces / W, moments / W R)",
        ),
        "trim_iterations": (result.iterations, "1", "Newton steps after the finite-difference Jacobian"),
        "trim_converged": (int(result.converged), "1", "1 if the residual met helicopter.flight.trim.tolerance"),
        "held_thrust_ratio_min": (
            hold["thrust_ratio_min"],
            "1",
            "smallest per-revolution vertical aerodynamic force / W",
        ),
        "held_thrust_ratio_max": (
            hold["thrust_ratio_max"],
            "1",
            "largest per-revolution vertical aerodynamic force / W",
        ),
        "held_attitude_deviation_max": (
            hold["attitude_deviation_max"],
            "rad",
            "largest per-revolution mean attitude angle",
        ),
    }
    data = {k: ((), float(v), {"units": u, "long_name": d}) for k, (v, u, d) in values.items()}
    return xr.Dataset(data, attrs={"flight": condition, "inflow": heli.aerodynamics.inflow})


def trim_attrs(heli: FlightRun, condition: str, result: TrimResult) -> dict:
    """The trim's verdict every consumer of the run reads: trim_converged (1 or 0), trim_residual and, when it did
    not converge (flown only with helicopter.flight.allow_unconverged), a ``warning`` with the reason."""
    attrs = {"trim_converged": int(result.converged), "trim_residual": float(np.abs(result.residual).max())}
    if not result.converged:
        attrs["warning"] = trim_failure(heli, condition, result) + " (flown: helicopter.flight.allow_unconverged)"
    return attrs


def run(heli: FlightRun, condition: str) -> tuple[xr.Dataset, xr.Dataset]:
    """(run dataset, trim dataset) of one flight condition ("hover" or "forward"; module docstring)."""
    sim, result, stats = fly(heli, condition)
    heli, start = sim.heli, sim.heli.flight.release
    time, displacement, rotation = H.mount_motion(sim.model, heli, start=start, from_start=False)
    q = np.asarray(sim.mbs.GetSensorStoredData(sim.model.sensors["coordinates"]))
    q = q[int(np.searchsorted(q[:, 0], start - 1e-9)) :]
    angle_error = float(q[-1, 1 + H.HUB_LINK] - q[0, 1 + H.HUB_LINK] - heli.main_rotor.omega_rad_s * time[-1])
    attrs = {"flight": condition, "rotor_angle_error_rad": angle_error, **stats, **trim_attrs(heli, condition, result)}
    motion = H.motion_dataset(heli, time, displacement, rotation, attrs)
    motion.mount_rotation.attrs["rotation"] = FLIGHT_ROTATION
    motion.mount_displacement.attrs["rotation"] = FLIGHT_ROTATION
    record = samples_dataset(sim, start)
    if record.time.size != time.size or np.abs(record.time.values - time).max() > 0.5 * heli.solver.step:
        raise RuntimeError("helicopter flight: the pilot's record and the sensors' samples disagree in time")
    record = record.assign_coords(time=motion.time)
    up = -sim.gravity / np.linalg.norm(sim.gravity)
    trim = trim_dataset(heli, condition, result, held(record, q[:, 4:7].T, heli, up))
    trim.attrs.update({k: v for k, v in attrs.items() if k == "warning"})
    trim.attrs["trim_history"] = json.dumps([[list(x), list(r)] for x, r in result.history])
    return xr.merge([motion, record], combine_attrs="override", join="exact"), trim
