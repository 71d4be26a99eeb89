"""The gimbal IMU and its complementary filter against closed forms and datasheet values."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate, signal
from scipy.spatial.transform import Rotation

from uavdamp.platform.imu import (
    ComplementaryFilter,
    ImuParams,
    noise_bandwidth_hz,
    quantise,
    read,
    read_scalar,
    sample_channel,
    tilt,
)
from uavdamp.settings import ConfigError


@pytest.mark.parametrize("order", [1, 2])
def test_noise_bandwidth_is_the_integral_of_the_squared_filter(order):
    """ENBW = integral over f > 0 of |F|^2, by quadrature of the Butterworth magnitude |F|^2 = 1 / (1 + (f/fc)^2n)."""
    p = ImuParams(filter_order=order)
    expected, _ = integrate.quad(lambda f: 1.0 / (1.0 + (f / p.bandwidth_hz) ** (2 * order)), 0, np.inf)
    assert noise_bandwidth_hz(p) == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("kind", ["gyro", "accel"])
def test_noise_std_is_density_times_root_bandwidth(order, kind):
    """Sampled at 1 kHz, a reading's noise std is N sqrt(B), B the equivalent noise bandwidth (closed form
    (pi/2n) / sin(pi/2n) f_c). Tolerance: the std estimate of n Gaussian samples with autocorrelation rho_k has
    relative std sqrt((1 + 2 sum rho_k^2) / (2 n)) (Bartlett); 6 of those, rho_k from the record (lags 1-20)."""
    p = ImuParams(filter_order=order)
    density = p.gyro_noise_density if kind == "gyro" else p.accel_noise_density
    n, period = 200_000, 1e-3
    time = np.arange(n) * period
    x = sample_channel(time, np.zeros(n), p, density, np.random.default_rng(7))
    x_over = math.pi / (2 * order)
    expected = density * math.sqrt(p.bandwidth_hz * x_over / math.sin(x_over))
    rho = np.array([np.corrcoef(x[:-k], x[k:])[0, 1] for k in range(1, 21)])
    tolerance = 6 * math.sqrt((1 + 2 * np.sum(rho**2)) / (2 * n))
    assert abs(x.std() / expected - 1) < tolerance
    assert tolerance < 0.015


def test_the_filter_passes_a_slow_signal_and_attenuates_at_its_bandwidth():
    """No noise: a sine at the -3 dB frequency of the first-order filter comes out at 1/sqrt(2) (steady state)."""
    p = ImuParams(filter_order=1, bandwidth_hz=50.0)
    h = 1e-5
    time = np.arange(0, 0.2, h)
    y = sample_channel(time, np.sin(2 * np.pi * 50.0 * time), p, 0.0, np.random.default_rng(0))
    tail = time > 0.1
    amplitude = math.sqrt(2) * y[tail].std()
    assert amplitude == pytest.approx(1 / math.sqrt(2), rel=1e-3)  # 5 whole periods: the std is exact to O(h)


def test_quantisation_step_is_the_datasheet_resolution():
    """+/-250 deg/s over 16 bit: 131.072 LSB per deg/s (the MPU-6050's 131 LSB/(deg/s)); +/-2 g: 16384 LSB/g."""
    p = ImuParams()
    assert p.gyro_step == pytest.approx(math.radians(1 / 131.072), rel=1e-12)
    assert p.accel_step == pytest.approx(p.accel_range / 2**15, rel=1e-12)
    assert p.accel_range / p.accel_step / 2 == pytest.approx(16384)
    ramp = np.linspace(-1e-2, 1e-2, 100_001)
    q = quantise(ramp, p.gyro_step, p.gyro_range)
    levels = np.unique(q)
    assert np.allclose(np.diff(levels), p.gyro_step, rtol=1e-9)
    assert np.max(np.abs(q - ramp)) <= p.gyro_step / 2 * (1 + 1e-9)
    assert read(np.array([10.0]), 0.0, p.gyro_step, p.gyro_range)[0] == p.gyro_range  # clipped to full scale
    assert np.array_equal(quantise(ramp, 0.0, 1.0), ramp)  # bits = 0: no quantisation


def test_tilt_reads_the_camera_attitude_from_gravity():
    """The specific force at rest, +g z in the inertial frame, seen from a camera rolled / pitched by known angles
    (scipy Rotation): tilt returns those angles (pitch positive nose down: a rotation about +y)."""
    g = 9.80665
    for roll, pitch in ((0.1, 0.0), (0.0, 0.2), (-0.05, -0.3)):
        for rot in (Rotation.from_rotvec([roll, 0, 0]), Rotation.from_rotvec([0, pitch, 0])):
            f_camera = rot.inv().apply([0.0, 0.0, g])
            est = tilt(f_camera)
            angle = rot.as_rotvec()
            assert est[0] == pytest.approx(angle[0], abs=1e-12)
            assert est[1] == pytest.approx(angle[1], abs=1e-12)


def _run(cf: ComplementaryFilter, gyro, tilt_rad, start=0.0):
    out, est = np.empty(len(gyro)), start
    for k, (g, a) in enumerate(zip(gyro, tilt_rad, strict=True)):
        est = cf.update(est, g, a)
        out[k] = est
    return out


def test_complementary_filter_update_is_its_transfer_function():
    """The recursion equals its stated transfer functions run by scipy's lfilter, for random inputs."""
    cf = ComplementaryFilter(0.5, 1e-3)
    rng = np.random.default_rng(3)
    gyro, tilt_rad = rng.standard_normal(500), rng.standard_normal(500)
    (gn, gd), (an, ad) = cf.transfer()
    expected = signal.lfilter(gn, gd, gyro) + signal.lfilter(an, ad, tilt_rad)
    assert np.allclose(_run(cf, gyro, tilt_rad), expected, rtol=0, atol=1e-12)


def test_complementary_filter_is_complementary():
    """A gyro consistent with the angle (its backward difference / T) and a true tilt give the angle exactly."""
    cf = ComplementaryFilter(2.0, 1e-3)
    angle = np.cumsum(np.random.default_rng(5).standard_normal(1000)) * 1e-3
    gyro = np.diff(angle, prepend=angle[0]) / cf.period
    assert np.allclose(_run(cf, gyro, angle, start=angle[0]), angle, atol=1e-15)


@pytest.mark.parametrize("freq_hz", [0.05, 0.5, 5.0])
def test_complementary_filter_against_its_continuous_closed_form(freq_hz):
    """Low-pass 1 / (1 + s tau) on the tilt, high-pass s tau / (1 + s tau) on the gyro's integral (tau =
    1 / (2 pi f_x)). The discrete filter is the backward-Euler form: its error is first order, within
    2 (w T + T / tau)."""
    cf = ComplementaryFilter(0.5, 1e-3)
    tau, w, period = 1 / (2 * math.pi * 0.5), 2 * math.pi * freq_hz, cf.period
    (gn, gd), (an, ad) = cf.transfer()
    _, h_gyro = signal.freqz(gn, gd, worN=[freq_hz], fs=1 / period)
    _, h_tilt = signal.freqz(an, ad, worN=[freq_hz], fs=1 / period)
    s = 1j * w
    low, high = 1 / (1 + s * tau), s * tau / (1 + s * tau)
    bound = 2 * (w * period + period / tau)
    assert abs(h_tilt[0] - low) <= bound * abs(low)
    assert abs(h_gyro[0] * s - high) <= bound * abs(high)  # the gyro of a sine angle is s times it


def test_gyro_only_estimator_integrates():
    cf = ComplementaryFilter(0.0, 1e-3)
    assert cf.alpha == 1.0
    assert _run(cf, np.ones(1000), np.full(1000, 5.0))[-1] == pytest.approx(1.0)


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [({"filter_order": 3}, "gimbal.imu.filter_order"), ({"bandwidth_hz": 0.0}, "gimbal.imu.bandwidth_hz")],
)
def test_bad_imu_parameters_name_the_key(kwargs, key):
    with pytest.raises(ConfigError, match=key):
        ImuParams(**kwargs)


def test_the_scalar_reading_is_the_array_reading():
    """`read_scalar`, the gimbal loop's per-sample path, gives `read`'s value to the bit: on random values, on exact
    half steps (both round half to even) and beyond the full scale (clipped)."""
    rng = np.random.default_rng(3)
    step, full_scale, bias = 0.061e-3 * 9.80665, 16 * 9.80665, 0.013
    values = np.concatenate([rng.normal(0, 5, 2000), (np.arange(-500, 500) + 0.5) * step - bias, [1e9, -1e9]])
    for v in values:
        assert read_scalar(v, bias, step, full_scale) == float(read(v, bias, step, full_scale))
    assert read_scalar(0.3, bias, 0.0, full_scale) == 0.3 + bias
