"""The gimbal's discrete loop in closed form: loop transfer functions, margins, sensitivity, base-to-line-of-sight.

Per axis (`uavdamp.platform.gimbal`), with the blocks in z^-1 (P_g, P_a, P_theta the zero-order-hold plant from
the torque to gyro, tilt and angle; PI; E_g, E_a the complementary filter; z^-1 the computation delay):

    rate loop       L_r = z^-1 PI P_g                                   (broken at the torque, attitude loop open)
    attitude loop   L_a = K_a (E_g L_r + E_a z^-1 PI P_a) / (1 + L_r)   (broken at the rate reference)
    whole loop      L = z^-1 PI ((1 + K_a E_g) P_g + K_a E_a P_a)       (broken at the torque: the true margins)
    sensitivity     S = 1 / (1 + L)

The base's motion enters the continuous plant (friction, cable, imbalance torque, the accelerometer's lateral
reading), not through a sampler, so the line of sight's steady response to a sine e^{j w t} at the sample times is
the sampled-data closed form (exact for the continuous plant and the discrete controller):

    theta = theta_o - z^-1 P_theta (C_g m_g + C_a m_a) / (1 + L),   C_g = PI (1 + K_a E_g), C_a = PI K_a E_a,

theta_o, m_g, m_a the open-loop (motor off) angle, gyro and tilt at j w, the rest at z = e^{j w T}. For a base
rotation it is close to S(e^{j w T}) theta_o (equal when the sensors' own lag is negligible; `design_report`
gives both). Assumption (one-way coupling): the motor's reaction torque on the base is left out of the base's
motion; `design_report` gives its size per radian of base rotation to compare with an isolator's stiffness.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import xarray as xr

from uavdamp.platform.gimbal import (
    INPUTS,
    OUTPUTS,
    AxisGains,
    GimbalParams,
    axis_model,
    design,
    loop_parts,
    outer_per_gain,
    plant_tf,
)

if TYPE_CHECKING:
    from scipy import signal

REPORT_FREQ_HZ = (7.0, 28.0, 85.0)  # Hz, the default frequencies of the report's |S| (choice)


def _add(a, b):
    """Sum of two polynomials in z^-1."""
    n = max(len(a), len(b))
    return np.pad(a, (0, n - len(a))) + np.pad(b, (0, n - len(b)))


def _whole_loop_poly(p: GimbalParams, gains: AxisGains) -> tuple[np.ndarray, np.ndarray]:
    """L(z) as (num, den), coefficients in z^-1 of equal length."""
    period, model = p.period, axis_model(p, gains.axis)
    (ng, d), (na, _) = plant_tf(model, "gyro", period), plant_tf(model, "tilt", period)
    (eg, e_den), (ea, _) = gains.estimator.transfer()
    pi_num, pi_den = [gains.kp + gains.ki * period, -gains.kp], [1.0, -1.0]
    inner = _add(np.convolve(_add(e_den, gains.ka * np.asarray(eg)), ng), gains.ka * np.convolve(ea, na))
    num = np.convolve([0.0, 1.0], np.convolve(pi_num, inner))
    den = np.convolve(pi_den, np.convolve(e_den, d))
    n = max(len(num), len(den))
    return np.pad(num, (0, n - len(num))), np.pad(den, (0, n - len(den)))


def whole_loop(p: GimbalParams, gains: AxisGains) -> signal.dlti:
    """L(z), the whole loop broken at the torque (module docstring), as a scipy dlti."""
    from scipy import signal

    num, den = _whole_loop_poly(p, gains)
    return signal.dlti(np.trim_zeros(num, "f"), den, dt=p.period)  # equal lengths: z^-1 and z forms agree


def sensitivity(p: GimbalParams, gains: AxisGains) -> signal.dlti:
    """S(z) = 1 / (1 + L(z)) as a scipy dlti."""
    from scipy import signal

    num, den = _whole_loop_poly(p, gains)
    return signal.dlti(den, num + den, dt=p.period)


def is_stable(system: signal.dlti) -> bool:
    """All poles strictly inside the unit circle."""
    return bool(np.all(np.abs(system.poles) < 1.0 - 1e-12))


def responses(p: GimbalParams, gains: AxisGains, freq_hz) -> dict[str, np.ndarray]:
    """The rate, attitude and whole loops and S at freq_hz (complex)."""
    parts = loop_parts(p, gains, freq_hz)
    rate = parts["delay"] * parts["pi"] * parts["gyro"]
    loop = rate + parts["delay"] * parts["pi"] * gains.ka * (
        parts["est_gyro"] * parts["gyro"] + parts["est_tilt"] * parts["tilt"]
    )
    return {"rate": rate, "attitude": gains.ka * outer_per_gain(parts), "whole": loop, "sensitivity": 1 / (1 + loop)}


def margins(loop, f_max_hz: float, f_min_hz: float = 0.01, n: int = 20000) -> dict[str, float]:
    """Gain crossover (Hz, the highest |L| = 1), phase margin (deg, the least over the crossovers) and gain margin
    (dB, at the first -180 deg phase crossing above the crossover; inf if none) of a loop `loop(f) -> complex`."""
    from scipy import optimize

    f = np.geomspace(f_min_hz, f_max_hz, n)
    mag = np.abs(loop(f))
    cross = np.flatnonzero(np.diff(np.sign(mag - 1.0)) != 0)
    if cross.size == 0:
        raise ValueError("the loop has no gain crossover in the range")
    roots = [optimize.brentq(lambda x: abs(loop(np.array([x]))[0]) - 1.0, f[i], f[i + 1], xtol=1e-12) for i in cross]
    pm = [float(np.degrees(np.angle(-loop(np.array([r]))[0]))) for r in roots]  # 180 + arg L, in (-180, 180]
    phase = np.unwrap(np.angle(loop(f)))
    wrapped = (phase + np.pi) / (2 * np.pi)  # integer at -180 deg (mod 360)
    above = np.flatnonzero((np.diff(np.floor(wrapped)) != 0) & (f[:-1] > roots[-1]))
    gm = float("inf")
    if above.size:
        i = above[0]
        target = (np.floor(wrapped[i + 1]) if wrapped[i + 1] > wrapped[i] else np.floor(wrapped[i])) * 2 * np.pi - np.pi

        def arg(x):
            return np.interp(x, f[i : i + 2], phase[i : i + 2]) - target

        f180 = optimize.brentq(arg, f[i], f[i + 1])
        gm = float(-20 * np.log10(abs(loop(np.array([f180]))[0])))
    return {"crossover_hz": float(roots[-1]), "phase_margin_deg": float(min(pm)), "gain_margin_db": gm}


def _open_loop_states(p: GimbalParams, gains: AxisGains, freq_hz, inputs: np.ndarray) -> dict[str, np.ndarray]:
    """The motor-off outputs (angle, gyro, tilt) at j w for complex input amplitudes (len(INPUTS) - 1, nf) over
    (base_angle, base_rate, disturbance, lateral)."""
    model = axis_model(p, gains.axis)
    w = 2 * np.pi * np.atleast_1d(np.asarray(freq_hz, dtype=float))
    lhs = 1j * w[:, None, None] * np.eye(model.a.shape[0]) - model.a
    x = np.linalg.solve(lhs, (model.b[:, 1:] @ inputs).T[..., None])[..., 0]
    y = x @ model.c.T
    return {name: y[:, OUTPUTS.index(name)] for name in ("angle", "gyro", "tilt")}


def closed_loop(p: GimbalParams, gains: AxisGains, freq_hz, inputs: np.ndarray) -> dict[str, np.ndarray]:
    """Steady sine response at the sample times (sampled-data closed form, module docstring): line of sight
    (rad) and motor torque (N m), complex amplitudes per unit of the input amplitudes (INPUTS[1:], nf)."""
    parts = loop_parts(p, gains, freq_hz)
    o = _open_loop_states(p, gains, freq_hz, inputs)
    c_g = parts["pi"] * (1 + gains.ka * parts["est_gyro"])
    c_a = parts["pi"] * gains.ka * parts["est_tilt"]
    loop = parts["delay"] * (c_g * parts["gyro"] + c_a * parts["tilt"])
    torque = -parts["delay"] * (c_g * o["gyro"] + c_a * o["tilt"]) / (1 + loop)
    return {"line_of_sight": o["angle"] + parts["angle"] * torque, "torque": torque, "open_loop": o["angle"]}


def base_rotation_inputs(freq_hz) -> np.ndarray:
    """Input amplitudes of a unit base rotation e^{j w t} about the axis: angle 1 rad and rate j w."""
    w = 2 * np.pi * np.atleast_1d(np.asarray(freq_hz, dtype=float))
    inputs = np.zeros((len(INPUTS) - 1, w.size), dtype=complex)
    inputs[0], inputs[1] = 1.0, 1j * w
    return inputs


def base_to_los(p: GimbalParams, gains: AxisGains, freq_hz) -> np.ndarray:
    """Line of sight per radian of base rotation about the axis at freq_hz (complex, rad rad-1); divide by j w for
    the line of sight per base rate (s)."""
    return closed_loop(p, gains, freq_hz, base_rotation_inputs(freq_hz))["line_of_sight"]


def design_report(p: GimbalParams, freq_hz=REPORT_FREQ_HZ, isolator_stiffness: float = 1.0) -> xr.Dataset:
    """Per stabilised axis: gains, achieved crossovers and margins of the three loops (from the discrete loop
    transfer), |S| and |base -> line of sight| at freq_hz, and the motor torque per radian of base rotation
    relative to `isolator_stiffness` (N m rad-1; the one-way coupling's size)."""
    gains = design(p)
    f = np.asarray(freq_hz, dtype=float)
    f_max = 0.499 * p.loop_rate_hz
    rows: dict[str, list] = {}
    for axis, g in gains.items():
        r = {
            name: margins(lambda x, n=name, g=g: responses(p, g, x)[n], f_max) for name in ("rate", "attitude", "whole")
        }
        cl = closed_loop(p, g, f, base_rotation_inputs(f))
        values = {
            "inertia": axis_model(p, axis).inertia, "kp": g.kp, "ki": g.ki, "ka": g.ka,
            **{f"{n}_{k}": v for n, m in r.items() for k, v in m.items()},
            "stable": is_stable(sensitivity(p, g)),
            "sensitivity_magnitude": np.abs(responses(p, g, f)["sensitivity"]),
            "base_to_los_magnitude": np.abs(cl["line_of_sight"]),
            "open_loop_magnitude": np.abs(cl["open_loop"]),
            "torque_per_base_angle": np.abs(cl["torque"]) / isolator_stiffness,
            "net_torque_per_base_angle": _net_reaction(p, axis, f, cl["line_of_sight"]) / isolator_stiffness,
        }  # fmt: skip
        for k, v in values.items():
            rows.setdefault(k, []).append(v)
    return _report_dataset(rows, list(gains), f, isolator_stiffness)


def _net_reaction(p: GimbalParams, axis: str, f: np.ndarray, los: np.ndarray) -> np.ndarray:
    """|net torque of the axis on the base| per radian of base rotation: the camera's J theta'' - k_g theta (the
    motor, friction and cable torques on the camera react on the base; no imbalance torque for a rotation)."""
    model = axis_model(p, axis)
    stiffness = -model.a[1, 0] * model.inertia - p.cable_stiffness  # k_g
    return np.abs((-model.inertia * (2 * np.pi * f) ** 2 - stiffness) * los)


_REPORT = {
    "inertia": ("kg m2", "axis inertia"),
    "kp": ("N m s rad-1", "rate loop proportional gain"),
    "ki": ("N m rad-1", "rate loop integral gain"),
    "ka": ("s-1", "attitude loop gain"),
    "stable": ("1", "closed loop stable (all poles of S inside the unit circle)"),
    "sensitivity_magnitude": ("1", "|S(e^{j w T})|, the whole loop broken at the torque"),
    "base_to_los_magnitude": ("rad rad-1", "line of sight per base rotation (sampled-data closed form)"),
    "open_loop_magnitude": ("rad rad-1", "line of sight per base rotation with the motor off"),
    "torque_per_base_angle": ("1", "motor torque per base rotation over the isolator's rotational stiffness"),
    "net_torque_per_base_angle": ("1", "net torque on the base (motor, friction, cable) per base rotation over it"),
}


def _report_dataset(rows: dict, axes: list[str], f: np.ndarray, stiffness: float) -> xr.Dataset:
    data = {}
    for key, values in rows.items():
        loop, _, metric = key.partition("_")
        if key in _REPORT:
            units, long_name = _REPORT[key]
        else:
            units = {"crossover_hz": "Hz", "phase_margin_deg": "deg", "gain_margin_db": "dB"}[metric]
            long_name = f"{loop} loop {metric.rsplit('_', 1)[0].replace('_', ' ')} (discrete loop transfer)"
        dims = ("axis", "frequency") if np.ndim(values[0]) else ("axis",)
        data[key] = (dims, np.asarray(values), {"units": units, "long_name": long_name})
    coords = {
        "axis": ("axis", axes, {"units": "1", "long_name": "stabilised axis"}),
        "frequency": ("frequency", f, {"units": "Hz", "long_name": "frequency of the report's magnitudes"}),
    }
    return xr.Dataset(data, coords=coords, attrs={"isolator_rotational_stiffness_N_m_rad": stiffness})
