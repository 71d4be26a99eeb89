"""The gimbal's discrete cascade on one axis, stepped at the loop rate, compiled with numba: the loop of
`uavdamp.platform.gimbal_sim` (module docstring there) for many runs side by side.

At each loop sample: the torque of the last demand applied (one sample of computation delay); the gyro and the
lateral accelerometer read off the axis's state (bias added, quantised to the converter's step, clipped to its
range: `uavdamp.platform.imu.read`); the tilt atan2(+/- f_lateral, f_z); the complementary filter
(`imu.ComplementaryFilter`), the attitude P and the rate PI, the integral held while the demand saturates
(anti-windup, choice), the demand clipped to the torque limit; the axis's torque response stepped over the period
(its exact map at a held torque). The Exudyn check (`uavdamp.platform.gimbal_exudyn`) writes the same arithmetic in
Python per sample (`cascade_step`), on its own multibody plant: `tests/test_gimbal_cascade.py` compares the two
cascades, `tests/test_gimbal_exudyn.py` the two plants.
"""

from __future__ import annotations

import math

import numpy as np

from uavdamp import compiled

COMPILED = ("_read", "_cascade")  # numba on first use (`uavdamp.compiled`), callees first


def _read(x, bias, step, full_scale):
    """A sensor's reading: bias added, rounded (half to even) to the converter's step, clipped (step 0: as is)."""
    x = x + bias
    if step == 0.0:
        return x
    return min(max(step * np.rint(x / step), -full_scale), full_scale)


def cascade(base_loop, f_z, hold, c_gyro, c_force, phi_t, gamma, sensors, tilt_sign, gains, limit, period):
    """The cascade of each run: base_loop (K, runs, states) the axis's state driven by the base and the noise at
    the loop samples, f_z (K, runs) m s-2 the vertical reading, hold (runs,) N m the integral's start (and the first
    torque); c_gyro, c_force (states,) the gyro's and lateral specific force's rows; phi_t (states, states) the
    torque response's map over a period, transposed, gamma (states,) its torque column; sensors (gyro bias, step,
    range, accelerometer bias, step, range); tilt_sign +1 (roll: atan2(f_y, f_z)), -1 (pitch: atan2(-f_x, f_z)) or
    0 (yaw: the gyro alone); gains (K_p N m s rad-1, K_i N m rad-1, K_a s-1, the filter's alpha); limit N m; period
    s. Returns (the torque applied over each period, its saturation flag at the demand's sample, the estimate),
    each (K, runs)."""
    compiled.jit(globals(), COMPILED)
    return _cascade(base_loop, f_z, hold, c_gyro, c_force, phi_t, gamma, sensors, tilt_sign, gains, limit, period)


def _cascade(base_loop, f_z, hold, c_gyro, c_force, phi_t, gamma, sensors, tilt_sign, gains, limit, period):
    k_count, n_runs, n_states = base_loop.shape
    kp, ki, ka, alpha = gains[0], gains[1], gains[2], gains[3]
    held = np.empty((k_count, n_runs))
    flags = np.zeros((k_count, n_runs), dtype=np.bool_)
    estimates = np.empty((k_count, n_runs))
    z, z_next = np.zeros(n_states), np.zeros(n_states)
    for r in range(n_runs):
        # element loops, not slice assignments: numba compiles a slice assignment with its shape check's error
        # path, 2.3 s of this kernel's compilation (docs/getting-started.md: numba)
        for i in range(n_states):
            z[i] = 0.0
        integral, applied, estimate, tilt = hold[r], hold[r], 0.0, 0.0
        for k in range(k_count):
            held[k, r] = applied
            rate, force = 0.0, 0.0
            for s in range(n_states):
                state = base_loop[k, r, s] + z[s]
                rate += state * c_gyro[s]
                force += state * c_force[s]
            gyro = _read(rate, sensors[0], sensors[1], sensors[2])
            if tilt_sign != 0:
                tilt = math.atan2(tilt_sign * _read(force, sensors[3], sensors[4], sensors[5]), f_z[k, r])
            estimate = alpha * (estimate + period * gyro) + (1.0 - alpha) * tilt
            error = -ka * estimate - gyro
            candidate = integral + ki * period * error
            demand = kp * error + candidate
            flags[k, r] = abs(demand) > limit
            if not flags[k, r]:
                integral = candidate
            applied = min(max(demand, -limit), limit)
            estimates[k, r] = estimate
            for i in range(n_states):
                total = 0.0
                for s in range(n_states):
                    total += z[s] * phi_t[s, i]
                z_next[i] = total + held[k, r] * gamma[i]
            for i in range(n_states):
                z[i] = z_next[i]
    return held, flags, estimates
