"""The gimbal's IMU (gyro and accelerometer on the camera) and its attitude estimator, SI units.

Sensor model (per channel): the true signal plus white noise passes a low-pass of the stated bandwidth, is sampled
at the loop rate, gets a constant bias, and is quantised to the converter's step and clipped to its range:

    reading_k = Q( [F(s) (x + w)](k T) + bias ),   F: Butterworth of order 1 or 2, -3 dB at bandwidth_hz.

Choices and assumptions: F is a continuous filter sampled at the loop rate (assumption: a MEMS part's digital
low-pass runs at an internal rate above the loop's and is taken as continuous against it). The noise w
has the one-sided density N (rad s-1 Hz^-1/2, m s-2 Hz^-1/2), so a reading's noise std is N sqrt(B), B the
filter's equivalent noise bandwidth (`noise_bandwidth_hz`: pi/2 f_c for order 1, 1.111 f_c for Butterworth
order 2). The defaults are those of an MPU-6050-class gimbal IMU (choice): +/-250 deg/s and +/-2 g over 16 bits,
256 Hz filter, 0.005 deg/s/sqrt(Hz) and 400 ug/sqrt(Hz) noise.

Estimator: a complementary filter per axis, theta_k = alpha (theta_{k-1} + T gyro_k) + (1 - alpha) tilt_k with
alpha = tau / (tau + T), tau = 1 / (2 pi f_x): the gyro's integral high-passed and the accelerometer's tilt
low-passed at the crossover f_x. The yaw axis has no gravity reference (no magnetometer: assumption) and
integrates the gyro alone (alpha = 1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm

from uavdamp.contract import STANDARD_GRAVITY
from uavdamp.platform.statespace import Discrete, StateSpace, discretise, lift, propagate
from uavdamp.settings import require

DEG = math.pi / 180.0


@dataclass(frozen=True)
class ImuParams:
    """The IMU (``gimbal.imu``): filter, noise, bias, range and resolution of both sensors."""

    bandwidth_hz: float = 256.0  # Hz, -3 dB frequency of both sensors' low-pass
    filter_order: int = 1  # 1 or 2 (Butterworth)
    gyro_noise_density: float = 0.005 * DEG  # rad s-1 Hz^-1/2, one-sided
    accel_noise_density: float = 400e-6 * STANDARD_GRAVITY  # m s-2 Hz^-1/2, one-sided
    gyro_bias: tuple[float, float, float] = (0.0, 0.0, 0.0)  # rad s-1, constant, camera axes x, y, z
    accel_bias: tuple[float, float, float] = (0.0, 0.0, 0.0)  # m s-2, constant, camera axes x, y, z
    gyro_range: float = 250.0 * DEG  # rad s-1, full scale +/-
    accel_range: float = 2.0 * STANDARD_GRAVITY  # m s-2, full scale +/-
    bits: int = 16  # converter resolution; 0: no quantisation (and no clipping)

    def __post_init__(self) -> None:
        w = "gimbal.imu."
        require(self.bandwidth_hz > 0, w + "bandwidth_hz", f"must be > 0, got {self.bandwidth_hz}")
        require(self.filter_order in (1, 2), w + "filter_order", f"must be 1 or 2, got {self.filter_order}")
        for key in ("gyro_noise_density", "accel_noise_density"):
            require(getattr(self, key) >= 0, w + key, f"must be >= 0, got {getattr(self, key)}")
        for key in ("gyro_range", "accel_range"):
            require(getattr(self, key) > 0, w + key, f"must be > 0, got {getattr(self, key)}")
        for key in ("gyro_bias", "accel_bias"):
            require(len(getattr(self, key)) == 3, w + key, f"needs 3 values (x, y, z), got {getattr(self, key)}")
        require(self.bits >= 0, w + "bits", f"must be >= 0 (0: no quantisation), got {self.bits}")

    @property
    def gyro_step(self) -> float:
        """Gyro quantisation step, rad s-1: 2 range / 2^bits (0 without quantisation)."""
        return 2.0 * self.gyro_range / 2**self.bits if self.bits else 0.0

    @property
    def accel_step(self) -> float:
        """Accelerometer quantisation step, m s-2 (0 without quantisation)."""
        return 2.0 * self.accel_range / 2**self.bits if self.bits else 0.0

    def noiseless(self) -> ImuParams:
        """The same IMU without noise, bias and quantisation (the linear, deterministic sensor)."""
        zero = (0.0, 0.0, 0.0)
        return ImuParams(self.bandwidth_hz, self.filter_order, 0.0, 0.0, zero, zero, self.gyro_range,
                         self.accel_range, 0)  # fmt: skip


def lowpass(p: ImuParams) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The sensor low-pass F(s) in state space (a 1/s, b, c), unit DC gain, Butterworth of p.filter_order."""
    from scipy import signal

    num, den = signal.butter(p.filter_order, 2 * math.pi * p.bandwidth_hz, analog=True)
    a, b, c, _ = signal.tf2ss(num, den)
    return np.asarray(a), np.asarray(b), np.asarray(c)


def noise_bandwidth_hz(p: ImuParams) -> float:
    """Equivalent noise bandwidth of F, Hz: integral of |F(j 2 pi f)|^2 over f > 0, (pi/2n) / sin(pi/2n) f_c."""
    x = math.pi / (2 * p.filter_order)
    return p.bandwidth_hz * x / math.sin(x)


def noise_covariance(a: np.ndarray, b: np.ndarray, density: float, h: float) -> np.ndarray:
    """Covariance added to the filter's state over one step h (s) by white noise of one-sided density `density`
    (intensity density^2 / 2, two-sided), exact (Van Loan): integral of e^{A t} B q B^T e^{A^T t} dt over [0, h]."""
    n = a.shape[0]
    q = 0.5 * density**2 * (b @ b.T)
    big = np.zeros((2 * n, 2 * n))
    big[:n, :n], big[:n, n:], big[n:, n:] = -a, q, a.T
    e = expm(big * h)
    phi_t = e[n:, n:]
    cov = phi_t.T @ e[:n, n:]
    return 0.5 * (cov + cov.T)


def quantise(x: np.ndarray, step: float, full_scale: float) -> np.ndarray:
    """x rounded to the converter's step and clipped to +/- full_scale (step 0: x unchanged)."""
    if step == 0:
        return np.asarray(x, dtype=float)
    # rint: round half to even, as numpy.round; minimum / maximum: numpy.clip's values at half its call's cost
    return np.minimum(np.maximum(step * np.rint(np.asarray(x, dtype=float) / step), -full_scale), full_scale)


def read(filtered: np.ndarray, bias: np.ndarray, step: float, full_scale: float) -> np.ndarray:
    """A reading from the filtered signal (noise included): bias added, then quantised and clipped."""
    return quantise(np.asarray(filtered) + bias, step, full_scale)


def read_scalar(filtered: float, bias: float, step: float, full_scale: float) -> float:
    """`read` of one sample in Python floats (the gimbal loop's per-sample path; numpy's scalar calls cost ten
    times more): the same value, round half to even as numpy's."""
    x = float(filtered) + float(bias)
    if step == 0:
        return x
    return min(max(step * round(x / step), -full_scale), full_scale)


def sample_channel(
    time: np.ndarray, x: np.ndarray, p: ImuParams, density: float, rng: np.random.Generator
) -> np.ndarray:
    """One sensor channel's filtered, noisy signal (before bias and quantisation) on a uniform grid `time` (s):
    x (n,) piecewise linear between samples, the noise of one-sided density `density` exact per step."""
    a, b, c = lowpass(p)
    h = float(time[1] - time[0])
    n_states = a.shape[0]
    plant = StateSpace(a, np.hstack([b, np.zeros_like(b)]), c, np.zeros((1, 1)), np.zeros((1, 1)))
    step = discretise(plant, h)
    x = np.asarray(x, dtype=float)
    slope = np.diff(x) / h
    noise = np.zeros((x.size - 1, n_states))
    if density > 0:
        noise = rng.standard_normal(noise.shape) @ np.linalg.cholesky(noise_covariance(a, b, density, h)).T
    step = Discrete(step.phi, np.hstack([step.gamma_u, np.eye(n_states)]), step.gamma_v)
    z0 = -np.linalg.solve(a, b[:, 0]) * x[0]  # the filter at rest on the first value
    z = propagate(step, z0, np.hstack([x[:-1, None], noise]), slope[:, None], lift(step.phi))
    return z @ c[0]


def tilt(accel: np.ndarray) -> np.ndarray:
    """(roll, pitch) rad from accelerometer readings (3, ...) in camera axes (x forward, y left, z up): the
    specific force at rest is +g z, so roll = atan2(f_y, f_z) and pitch (positive nose down) = atan2(-f_x, f_z)."""
    f = np.asarray(accel, dtype=float)
    return np.stack([np.arctan2(f[1], f[2]), np.arctan2(-f[0], f[2])])


@dataclass(frozen=True)
class ComplementaryFilter:
    """Attitude estimate of one axis from its gyro (rad s-1) and its accelerometer tilt (rad), at period T (s).

    crossover_hz: f_x, where gyro and accelerometer weigh equally (0: the gyro alone, e.g. yaw).
    """

    crossover_hz: float
    period: float

    def __post_init__(self) -> None:
        require(self.crossover_hz >= 0, "gimbal.estimator.crossover_hz", f"must be >= 0, got {self.crossover_hz}")
        require(self.period > 0, "gimbal.loop_rate_hz", f"the period must be > 0, got {self.period}")

    @property
    def alpha(self) -> float:
        """Weight of the propagated estimate, tau / (tau + T), 1 for the gyro alone."""
        if self.crossover_hz == 0:
            return 1.0
        tau = 1.0 / (2 * math.pi * self.crossover_hz)
        return tau / (tau + self.period)

    def update(self, estimate: float, gyro: float, tilt_rad: float) -> float:
        """The estimate after one sample: alpha (estimate + T gyro) + (1 - alpha) tilt."""
        a = self.alpha
        return a * (estimate + self.period * gyro) + (1.0 - a) * tilt_rad

    def transfer(self) -> tuple[tuple[list[float], list[float]], tuple[list[float], list[float]]]:
        """(gyro -> estimate, tilt -> estimate) as discrete transfer functions (num, den in z^-1):
        alpha T / (1 - alpha z^-1) (a leaky integrator) and (1 - alpha) / (1 - alpha z^-1) (unit DC gain)."""
        a, t = self.alpha, self.period
        return ([a * t], [1.0, -a]), ([1.0 - a], [1.0, -a])
