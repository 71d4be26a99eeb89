"""`uavdamp.platform.gimbal_cascade.cascade` (the compiled loop) against the same cascade written out here per
sample in Python floats from the Exudyn check's `cascade_step` and `imu.read_scalar`: readings quantised on a
coarse step (so that rounding half to even against a floor shows), a torque limit the demand exceeds (so that the
integral's hold shows), the tilt's sign per axis and one sample of delay."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uavdamp.platform.gimbal import AxisGains
from uavdamp.platform.gimbal_cascade import cascade
from uavdamp.platform.gimbal_exudyn import cascade_step
from uavdamp.platform.imu import ComplementaryFilter, read_scalar

PERIOD = 1e-3  # s
SENSORS = (2e-3, 5e-3, 4.0, 0.05, 0.02, 19.6)  # gyro bias, step, range; accelerometer bias, step, range


def _reference(base, f_z, hold, c_gyro, c_force, phi, gamma, tilt_sign, g: AxisGains, limit):
    """The cascade of one run, sample by sample: (held torque, saturated, estimate) each (K,)."""
    z = np.zeros(phi.shape[0])
    integral = applied = hold
    estimate = tilt = 0.0
    out = []
    for k in range(base.shape[0]):
        held = applied
        state = base[k] + z
        gyro = read_scalar(float(state @ c_gyro), *SENSORS[:3])
        if tilt_sign:
            tilt = math.atan2(tilt_sign * read_scalar(float(state @ c_force), *SENSORS[3:]), f_z[k])
        estimate, integral, applied, saturated = cascade_step(g, estimate, integral, gyro, tilt, limit, PERIOD)
        out.append((held, saturated, estimate))
        z = phi @ z + gamma * held
    return np.array(out).T


@pytest.mark.parametrize(("tilt_sign", "crossover_hz"), [(1.0, 0.5), (-1.0, 0.5), (0.0, 0.0)])
def test_the_compiled_cascade_is_the_sample_by_sample_one(tilt_sign, crossover_hz):
    """Three runs of 400 samples on a 3-state axis (a stable map, random base states, a vertical reading near g):
    the held torques, saturation flags and estimates equal the sample-by-sample cascade's within 1e-9 of their
    ranges, a flag differing nowhere; the demand saturates on some samples and not on others, and some readings
    sit where rounding and a floor differ. Seen failing with the integral updated while saturated, the tilt's sign
    dropped, the filter's tilt weight alpha instead of 1 - alpha, the readings floored, and the held torque taken
    after the new demand."""
    rng = np.random.default_rng(5)
    k_count, n_runs, n_states = 400, 3, 3
    phi = 0.9 * np.linalg.qr(rng.normal(size=(n_states, n_states)))[0]  # spectral radius 0.9
    gamma, c_gyro, c_force = rng.normal(size=n_states), rng.normal(size=n_states), rng.normal(size=n_states)
    base = rng.normal(scale=0.5, size=(k_count, n_runs, n_states))
    f_z = 9.81 + rng.normal(scale=0.3, size=(k_count, n_runs))
    hold = rng.normal(scale=0.01, size=n_runs)
    g = AxisGains("roll", 0.3, 4.0, 20.0, ComplementaryFilter(crossover_hz, PERIOD))
    limit = 0.25
    gains = np.array([g.kp, g.ki, g.ka, g.estimator.alpha])
    held, flags, estimates = cascade(base, f_z, hold, c_gyro, c_force, phi.T.copy(), gamma, np.array(SENSORS),
                                     tilt_sign, gains, limit, PERIOD)  # fmt: skip
    for r in range(n_runs):
        ref = _reference(base[:, r], f_z[:, r], hold[r], c_gyro, c_force, phi, gamma, tilt_sign, g, limit)
        for got, want in ((held[:, r], ref[0]), (estimates[:, r], ref[2])):
            assert np.abs(got - want).max() <= 1e-9 * np.abs(want).max()
        np.testing.assert_array_equal(flags[:, r], ref[1].astype(bool))
    assert 0.05 < flags.mean() < 0.95  # saturated on some samples, not on others
