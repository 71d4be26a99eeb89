"""The gimbal as a nested three-body mechanism in Exudyn (`uavdamp.platform.gimbal_exudyn`) against the linear,
decoupled per-axis run (`uavdamp.platform.gimbal_sim.simulate`, sensor_errors=False) on the same base motion.

Measure (all tests): per stabilised axis, the rms over the settled part (t >= 0.1 s of 0.4 s) of Exudyn's line of
sight minus the linear one, divided by the rms of the linear one there; an axis the motion leaves still (linear
line of sight 0) is held to the same 1 % of the moving axes' rms."""

from __future__ import annotations

import numpy as np
import pytest

from uavdamp.platform.gimbal import AXES, GimbalParams
from uavdamp.platform.gimbal_exudyn import run, tait_bryan_rates
from uavdamp.platform.gimbal_sim import simulate

P = GimbalParams()
H = P.period / 10  # the input grid; Exudyn's step is the default, T / 10, here the same
TIME = np.arange(0.0, 0.4 + H / 2, H)
SETTLED = TIME >= 0.1


def _sines(freq_hz, amplitude):
    """Base rotation A sin(2 pi f t) about each axis (freq_hz per axis, 0: still) and its rate, no translation."""
    w = 2 * np.pi * np.asarray(freq_hz, dtype=float)[:, None]
    return amplitude * np.sin(w * TIME), amplitude * w * np.cos(w * TIME), np.zeros((3, TIME.size))


def _gaps(rotation, rate, acceleration, variable="line_of_sight"):
    """{variable: (gap per axis, linear rms per axis)} for the line of sight and the motor torque: the module
    docstring's measure (a still axis's gap over the moving axes' rms)."""
    linear = simulate(P, TIME, rotation, rate, acceleration, sensor_errors=False)
    exudyn = run(P, TIME, rotation, rate, acceleration)
    out = {}
    for name in ("line_of_sight", "motor_torque"):
        a, b = linear[name].values[:, SETTLED], exudyn[name].values[:, SETTLED]
        rms = np.sqrt(np.mean(a**2, axis=1))
        scale = np.where(rms > 0, rms, np.sqrt(np.mean(rms[rms > 0] ** 2)))
        out[name] = (np.sqrt(np.mean((b - a) ** 2, axis=1)) / scale, rms)
    return out if variable is None else out[variable]


@pytest.mark.parametrize("freq_hz", [3.0, 20.0, 80.0])
@pytest.mark.parametrize("axis", AXES)
def test_a_small_base_rotation_moves_the_line_of_sight_as_the_linear_run(axis, freq_hz):
    """10 urad about one axis: every axis's line of sight and motor torque within 1 % (measured on each axis: 3 Hz
    2.9e-7, 20 Hz 1.3e-5, 80 Hz 2.1e-4, about the trapezoidal rule's (w h)^2 / 12; the still axes exactly still)."""
    freqs = [freq_hz if a == axis else 0.0 for a in AXES]
    both = _gaps(*_sines(freqs, 10e-6), variable=None)
    gap, rms = both["line_of_sight"]
    assert rms[AXES.index(axis)] > 1e-10  # the loop leaves a measurable residue to compare
    assert np.all(gap < 0.01), dict(zip(AXES, gap, strict=True))
    torque_gap, _ = both["motor_torque"]
    assert np.all(torque_gap < 0.01), dict(zip(AXES, torque_gap, strict=True))


def test_the_small_motion_gap_is_the_solvers_second_order_step_error():
    """The gap at small motion is Exudyn's trapezoidal step error: halving the step quarters it (measured at 80 Hz
    pitch: 2.1e-4 at T / 10, 5.3e-5 at T / 20). An error of the sampled loop's timing (a torque or a reading half a
    solver step off) would be first order, halving only."""
    rotation, rate, acceleration = _sines([0.0, 80.0, 0.0], 10e-6)
    linear = simulate(P, TIME, rotation, rate, acceleration, sensor_errors=False).line_of_sight.values[1, SETTLED]
    gaps = []
    for step in (P.period / 10, P.period / 20):
        exudyn = run(P, TIME, rotation, rate, acceleration, step=step).line_of_sight.values[1, SETTLED]
        gaps.append(np.sqrt(np.mean((exudyn - linear) ** 2) / np.mean(linear**2)))
    assert 3.0 < gaps[0] / gaps[1] < 5.0, gaps


def test_a_lateral_acceleration_tilts_the_accelerometer_as_in_the_linear_run():
    """0.02 m s-2 sines forward (5 Hz), left (9 Hz) and 0.5 m s-2 up (4 Hz) on the balanced gimbal: no torque on
    the camera, only the accelerometer's tilt through the complementary filter moves roll and pitch; within 1 %
    (measured: roll 3.2e-4, pitch 3.8e-4, yaw 5e-6), the torques alike."""
    w = 2 * np.pi * np.array([[5.0], [9.0], [4.0]])
    acceleration = np.array([[0.02], [0.02], [0.5]]) * np.sin(w * TIME)
    zeros = np.zeros((3, TIME.size))
    both = _gaps(zeros, zeros, acceleration, variable=None)
    gap, rms = both["line_of_sight"]
    assert rms[0] > 1e-7 and rms[1] > 1e-7 and rms[2] == 0.0
    assert np.all(gap < 0.01), dict(zip(AXES, gap, strict=True))
    torque_gap, _ = both["motor_torque"]
    assert np.all(torque_gap < 0.01), dict(zip(AXES, torque_gap, strict=True))


def test_a_motion_about_one_axis_stays_linear_at_large_amplitude():
    """From the neutral pose a base turning about one gimbal axis turns every body about that fixed axis only: the
    mechanism's equation is the linear one exactly (the accelerometer's atan2 of the filtered sine and cosine
    differs at third order), so 10 mrad of roll at 20 Hz agrees as 10 urad does (measured: 1.3e-5 both)."""
    gap, _ = _gaps(*_sines([20.0, 0.0, 0.0], 10e-3))
    assert np.all(gap < 0.01), dict(zip(AXES, gap, strict=True))


def test_the_gap_grows_with_the_amplitude_of_a_three_axis_motion():
    """Roll 20 Hz, pitch 13 Hz and yaw 7 Hz together, amplitude A each. The linear run drops every term of second
    order in the angles; its gap to Exudyn is the solver's at small A and grows as A (the dropped terms as A^2)
    beyond. Measured gap (roll, pitch, yaw): 10 urad (1.3e-5, 6.4e-6, 1.0e-3), 100 urad (3.2e-5, 3.2e-5, 1.0e-2),
    1 mrad (2.9e-4, 3.2e-4, 0.10), 10 mrad (4.1e-3, 3.2e-3, 1.04). Yaw goes first: its line of sight is the
    smallest (0.06 % of A against 0.27 % and 0.23 %) and its error 0.061 A^2 rad rms, of which products of inertia
    and gyroscopic torques are the lesser part: with every body's inertia made isotropic (neither left) it is still
    0.058 A^2; the rest is the joints' geometry (the base's roll and pitch tilt the yaw joint's axis, about which the
    base then turns at second order). Asserted: within 1 % at 10 urad, growing with A."""
    amplitudes = [10e-6, 100e-6, 1e-3, 10e-3]
    gaps = np.array([_gaps(*_sines([20.0, 13.0, 7.0], a))[0] for a in amplitudes])
    for a, g in zip(amplitudes, gaps, strict=True):
        print(f"A = {a:.0e} rad: gap roll {g[0]:.2e}, pitch {g[1]:.2e}, yaw {g[2]:.2e}")
    assert np.all(gaps[0] < 0.01)
    assert np.all(np.diff(gaps, axis=0) > 0)


def test_the_base_must_start_at_the_neutral_pose_and_the_step_divide_the_grid():
    rotation, rate, acceleration = _sines([3.0, 0.0, 0.0], 1e-5)
    with pytest.raises(ValueError, match="neutral pose"):
        run(P, TIME, rotation + 1e-6, rate, acceleration)
    with pytest.raises(ValueError, match="must divide"):
        run(P, TIME, rotation, rate, acceleration, step=0.3 * H)


def test_tait_bryan_rates_integrate_to_the_rotation():
    """The base's constraint rates: for a rotation vector path and its exact angular velocity (finite-differenced
    rotation matrices), the Tait-Bryan rates equal the angles' own derivative (central differences)."""
    t = np.linspace(0.0, 1.0, 2001)
    rotation = np.stack([0.3 * np.sin(2 * t), 0.2 * np.cos(3 * t) - 0.2, 0.4 * t])
    matrices = np.array([_matrix(r) for r in rotation.T])
    dt = t[1] - t[0]
    skew = np.einsum("nij,nkj->nik", np.gradient(matrices, dt, axis=0), matrices)  # R' R^T = [w]x
    rate = np.stack([skew[:, 2, 1], skew[:, 0, 2], skew[:, 1, 0]])
    angles = np.stack([np.arctan2(-matrices[:, 1, 2], matrices[:, 2, 2]), np.arcsin(matrices[:, 0, 2])])
    angles = np.vstack([angles, np.arctan2(-matrices[:, 0, 1], matrices[:, 0, 0])])
    expected = np.gradient(angles, dt, axis=1)
    got = tait_bryan_rates(rotation, rate)
    assert np.allclose(got[:, 5:-5], expected[:, 5:-5], atol=1e-5)


def _matrix(r):
    phi = np.linalg.norm(r)
    if phi == 0:
        return np.eye(3)
    k = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]]) / phi
    return np.eye(3) + np.sin(phi) * k + (1 - np.cos(phi)) * k @ k
