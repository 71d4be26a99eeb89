"""A gyro-stabilised camera gimbal: parameters, axis inertias, the per-axis plant and the cascade's gains.

Axes (camera frame at the neutral pose: x forward along the line of sight, y left, z up): roll about x, pitch
about y (positive nose down, as `uavdamp.camera.optics`), yaw about z; two or three of them stabilised, nested pitch
(innermost), roll, yaw (outermost). Linearised about the neutral pose with all axes through the camera's
centre of mass when balanced, the axes decouple (assumption: products of inertia and gyroscopic terms, second
order in the angles, left out). Per stabilised axis, theta the camera's inertial angle about it:

    J theta'' = tau - c (theta' - omega_b) - k (theta - theta_b) + k_g theta + d,

tau the motor torque (ideal current drive, |tau| <= K_t I_max: assumption), c viscous friction and k a cable
harness stiffness to the base (assumption; 0 by default), theta_b and omega_b the base's rotation and rate about
the axis, k_g = m g r_z the pendulum stiffness of a centre of mass r above the axes (roll and pitch; 0 for yaw)
and d = -m (r x f)_axis the torque of the base's specific force f = a - g on the offset camera.

Control (per axis, every loop period T; choice after the EO/IR "rate mode" cascade: an inner gyro rate loop
inside an outer attitude loop): omega_ref = K_a (0 - theta_hat), u = PI(omega_ref - gyro) with
PI(z) = K_p + K_i T z / (z - 1), theta_hat the complementary filter's estimate (`uavdamp.platform.imu`); u computed
from the samples at k T is applied from (k + 1) T (one sample of computation delay, zero-order hold: choice).

Gain design (closed form, `design_axis`): the rate loop's crossover f_c and phase margin PM are specified; the
plant's zero-order-hold response P_g(e^{j w_c T}) (gyro per torque: 1 / (J s + c) and the gyro filter) fixes the
PI's value there, PI(e^{j w_c T}) = e^{j (PM - 180 deg)} e^{j w_c T} / P_g; with PI(e^{j v}) = K_p + K_i T / 2 -
j (K_i T / 2) cot(v / 2) the two real gains follow from its real and imaginary parts. The attitude loop's
crossover is a stated fraction of f_c; K_a = 1 / |X(e^{j w_a T})|, X the rate reference -> estimate with the rate
loop closed. The achieved margins are computed from the discrete loops (`uavdamp.platform.gimbal_loop`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from uavdamp.contract import STANDARD_GRAVITY
from uavdamp.platform.imu import ComplementaryFilter, ImuParams, lowpass
from uavdamp.settings import require

AXES = ("roll", "pitch", "yaw")  # about the camera's x, y, z
CHAIN = ("pitch", "roll", "yaw")  # innermost to outermost
TILT_SIGN = {"roll": 1.0, "pitch": -1.0, "yaw": 0.0}  # accelerometer: f_y = a_y + g roll, f_x = a_x - g pitch
LATERAL = {"roll": 1, "pitch": 0, "yaw": None}  # the specific-force component an axis's tilt reads


@dataclass(frozen=True)
class GimbalParams:
    """The gimbal (``gimbal``), SI units; per-axis tuples are in the order (roll, pitch, yaw)."""

    axes: tuple[str, ...] = ("roll", "pitch", "yaw")  # the stabilised axes, 2 or 3 of AXES
    camera_mass: float = 0.9  # kg
    camera_size: tuple[float, float, float] = (0.10, 0.06, 0.06)  # m, uniform box edges along x, y, z
    # kg m2 about (x, y, z) through the axes' intersection, of what each axis moves besides the camera and the
    # inner brackets (choices): pitch cradle + pitch rotor; roll arm + pitch stator; yaw arm + roll stator
    bracket_inertia: tuple[tuple[float, float, float], ...] = ((1.5e-4, 2.0e-4, 2.0e-4),
                                                              (6.0e-4, 4.0e-4, 5.0e-4),
                                                              (5.0e-4, 5.0e-4, 8.0e-4))  # fmt: skip
    torque_constant: float = 0.12  # N m A-1, direct-drive gimbal motor (choice)
    current_limit: float = 2.0  # A (choice): torque limit K_t I_max
    friction: float = 1e-3  # N m s rad-1, viscous, bearing + motor (assumption)
    cable_stiffness: float = 0.0  # N m rad-1, harness to the base (assumption: none)
    imbalance_m: tuple[float, float, float] = (0.0, 0.0, 0.0)  # m, camera COM from the axes, camera x, y, z
    gravity: float = STANDARD_GRAVITY  # m s-2, along -z
    loop_rate_hz: float = 1000.0  # Hz
    rate_crossover_hz: tuple[float, float, float] = (40.0, 40.0, 40.0)  # Hz, rate loop crossover per axis
    phase_margin_deg: tuple[float, float, float] = (50.0, 50.0, 50.0)  # deg, rate loop phase margin per axis
    attitude_fraction: float = 0.2  # attitude loop crossover / rate loop crossover
    # Hz, complementary filter (roll, pitch; yaw: gyro alone): 1 / (2 pi 7 s), the 7 s accelerometer time constant
    # open gimbal firmware (BruGi) defaults to (choice)
    estimator_crossover_hz: float = 1.0 / (2 * math.pi * 7.0)
    imu: ImuParams = field(default_factory=ImuParams)

    def __post_init__(self) -> None:
        w = "gimbal."
        require(
            2 <= len(self.axes) <= 3 and set(self.axes) <= set(AXES) and len(set(self.axes)) == len(self.axes),
            w + "axes",
            f"must be 2 or 3 distinct of {list(AXES)}, got {list(self.axes)}",
        )
        for key in ("camera_mass", "torque_constant", "current_limit", "loop_rate_hz", "attitude_fraction"):
            require(getattr(self, key) > 0, w + key, f"must be > 0, got {getattr(self, key)}")
        for key in ("friction", "cable_stiffness", "gravity", "estimator_crossover_hz"):
            require(getattr(self, key) >= 0, w + key, f"must be >= 0, got {getattr(self, key)}")
        require(min(self.camera_size) > 0, w + "camera_size_m", f"must be > 0, got {self.camera_size}")
        require(len(self.bracket_inertia) == 3 and all(len(b) == 3 and min(b) >= 0 for b in self.bracket_inertia),
                w + "bracket_inertia_kg_m2", "needs 3 rows (pitch, roll, yaw) of 3 values >= 0")  # fmt: skip
        require(len(self.imbalance_m) == 3, w + "imbalance_m", f"needs 3 values, got {self.imbalance_m}")
        nyquist = 0.5 * self.loop_rate_hz
        for key in ("rate_crossover_hz", "phase_margin_deg"):
            require(len(getattr(self, key)) == 3, w + key, "needs 3 values (roll, pitch, yaw)")
        for name, fc, pm in zip(AXES, self.rate_crossover_hz, self.phase_margin_deg, strict=True):
            require(0 < fc < 0.5 * nyquist, w + "rate_crossover_hz", f"{name}: must lie in (0, {0.5 * nyquist}) Hz")
            require(0 < pm < 90, w + "phase_margin_deg", f"{name}: must lie in (0, 90) deg, got {pm}")
        require(self.attitude_fraction < 1, w + "attitude_fraction", f"must be < 1, got {self.attitude_fraction}")

    @property
    def period(self) -> float:
        """Loop period T, s."""
        return 1.0 / self.loop_rate_hz

    @property
    def torque_limit(self) -> float:
        """Motor torque limit K_t I_max, N m."""
        return self.torque_constant * self.current_limit

    @property
    def stabilised(self) -> tuple[str, ...]:
        """The stabilised axes in the order of AXES."""
        return tuple(a for a in AXES if a in self.axes)


def camera_inertia(p: GimbalParams) -> np.ndarray:
    """Diagonal inertia (x, y, z) of the camera as a uniform box about its centre, kg m2."""
    a, b, c = p.camera_size
    return p.camera_mass / 12.0 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])


def axis_inertia(p: GimbalParams, axis: str) -> float:
    """Inertia about a stabilised axis, kg m2: the camera, plus the brackets of the stabilised axes at and inside
    it (the chain pitch -> roll -> yaw), plus the offset camera's m |r_perp|^2 (parallel axes)."""
    i = AXES.index(axis)
    inner = CHAIN[: CHAIN.index(axis) + 1]
    brackets = sum(p.bracket_inertia[CHAIN.index(b)][i] for b in inner if b in p.axes)
    r = np.asarray(p.imbalance_m, dtype=float)
    return float(camera_inertia(p)[i] + brackets + p.camera_mass * (r @ r - r[i] ** 2))


def pendulum_stiffness(p: GimbalParams, axis: str) -> float:
    """Gravity's stiffness on the axis, N m rad-1 (positive: destabilising): m g r_z for roll and pitch, 0 yaw."""
    return 0.0 if axis == "yaw" else p.camera_mass * p.gravity * p.imbalance_m[2]


def imbalance_torque(p: GimbalParams, axis: str, specific_force: np.ndarray) -> np.ndarray:
    """Torque about the axis, N m, of the base's specific force (3, ...) m s-2 on the offset camera: -m (r x f)."""
    r = np.asarray(p.imbalance_m, dtype=float)
    f = np.asarray(specific_force, dtype=float)
    torque = -p.camera_mass * np.cross(r, f, axis=0)
    return torque[AXES.index(axis)]


@dataclass(frozen=True)
class AxisModel:
    """One axis in continuous state space: x = (theta, omega, gyro filter, accelerometer filter (roll, pitch)).

    Inputs (b columns): tau N m, theta_b rad, omega_b rad s-1, d N m, a_lat m s-2 (the lateral specific force
    the tilt reads: a_y roll, a_x pitch); outputs (c rows): theta rad, gyro rad s-1, tilt rad (linearised:
    sign f_lat / g), f_lat m s-2.
    """

    axis: str
    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    inertia: float


INPUTS = ("torque", "base_angle", "base_rate", "disturbance", "lateral")
OUTPUTS = ("angle", "gyro", "tilt", "specific_force")


def axis_model(p: GimbalParams, axis: str) -> AxisModel:
    """The axis's continuous model (module docstring), the IMU filter from `p.imu`."""
    j, c_f, k = axis_inertia(p, axis), p.friction, p.cable_stiffness
    af, bf, cf = lowpass(p.imu)
    nf = af.shape[0]
    tilt = axis != "yaw"
    n = 2 + nf + (nf if tilt else 0)
    a, b, c = np.zeros((n, n)), np.zeros((n, len(INPUTS))), np.zeros((len(OUTPUTS), n))
    a[0, 1] = 1.0
    a[1, 0], a[1, 1] = (pendulum_stiffness(p, axis) - k) / j, -c_f / j
    b[1, :4] = 1.0 / j, k / j, c_f / j, 1.0 / j
    g = slice(2, 2 + nf)
    a[g, g], a[g, 1] = af, bf[:, 0]
    c[0, 0], c[1, g] = 1.0, cf[0]
    if tilt:
        s = slice(2 + nf, n)
        sign = TILT_SIGN[axis]
        a[s, s], a[s, 0], b[s, 4] = af, sign * p.gravity * bf[:, 0], bf[:, 0]
        c[3, s] = cf[0]
        c[2, s] = sign * cf[0] / p.gravity if p.gravity > 0 else 0.0
    return AxisModel(axis, a, b, c, j)


@dataclass(frozen=True)
class AxisGains:
    """An axis's cascade: rate PI (K_p N m s rad-1, K_i N m rad-1), attitude P (K_a s-1), its estimator."""

    axis: str
    kp: float
    ki: float
    ka: float
    estimator: ComplementaryFilter


def tf_response(num, den, freq_hz: np.ndarray, period: float) -> np.ndarray:
    """Frequency response of a discrete transfer function (coefficients in z^-1) at freq_hz (scipy freqz)."""
    from scipy import signal

    _, h = signal.freqz(num, den, worN=np.atleast_1d(np.asarray(freq_hz, dtype=float)), fs=1.0 / period)
    return h


def plant_tf(model: AxisModel, output: str, period: float) -> tuple[np.ndarray, np.ndarray]:
    """Zero-order-hold transfer function (num, den in z^-1) from the torque to an output (scipy cont2discrete)."""
    from scipy import signal

    row = OUTPUTS.index(output)
    ad, bd, cd, dd, _ = signal.cont2discrete(
        (model.a, model.b[:, :1], model.c[row : row + 1], np.zeros((1, 1))), period, method="zoh"
    )
    num, den = signal.ss2tf(ad, bd, cd, dd)
    num = np.asarray(num[0], dtype=float)
    num[0] = 0.0  # strictly proper: no direct torque -> output path
    return num, np.asarray(den)


def pi_gains(required: complex, w_c: float, period: float) -> tuple[float, float]:
    """(K_p, K_i) with K_p + K_i T z / (z - 1) = required at z = e^{j w_c T} (real and imaginary parts)."""
    v = w_c * period
    ki = -2.0 * required.imag * math.tan(v / 2) / period
    return required.real - ki * period / 2, ki


def design_axis(p: GimbalParams, axis: str) -> AxisGains:
    """The axis's gains by the closed-form method of the module docstring; ValueError (naming the key) when the
    specified crossover and phase margin need a PI with a negative gain (too little phase left)."""
    i, period = AXES.index(axis), p.period
    model = axis_model(p, axis)
    f_c, pm = p.rate_crossover_hz[i], math.radians(p.phase_margin_deg[i])
    w_c = 2 * math.pi * f_c
    pg = tf_response(*plant_tf(model, "gyro", period), f_c, period)[0]
    delay = np.exp(-1j * w_c * period)
    kp, ki = pi_gains(complex(np.exp(1j * (pm - math.pi)) / (delay * pg)), w_c, period)
    require(
        kp > 0 and ki >= 0,
        "gimbal.phase_margin_deg",
        f"{axis}: {math.degrees(pm):.1f} deg at {f_c} Hz needs K_p = {kp:.3g}, K_i = {ki:.3g} (both must be >= 0): "
        "lower the crossover or the margin",
    )
    estimator = ComplementaryFilter(0.0 if axis == "yaw" else p.estimator_crossover_hz, period)
    f_a = p.attitude_fraction * f_c
    parts = loop_parts(p, AxisGains(axis, kp, ki, 1.0, estimator), f_a)
    return AxisGains(axis, kp, ki, float(1.0 / abs(outer_per_gain(parts)[0])), estimator)


def loop_parts(p: GimbalParams, gains: AxisGains, freq_hz) -> dict[str, np.ndarray]:
    """The loop's blocks at z = e^{j 2 pi f T}: plant (torque -> angle, gyro, tilt; zero-order hold), the delay
    z^-1, the PI and the estimator (gyro -> estimate, tilt -> estimate)."""
    period, model = p.period, axis_model(p, gains.axis)
    f = np.atleast_1d(np.asarray(freq_hz, dtype=float))
    z = np.exp(2j * np.pi * f * period)
    e_gyro, e_tilt = gains.estimator.transfer()
    out = {name: tf_response(*plant_tf(model, name, period), f, period) for name in ("angle", "gyro", "tilt")}
    out["delay"] = 1.0 / z
    out["pi"] = gains.kp + gains.ki * period * z / (z - 1.0)
    out["est_gyro"] = tf_response(*e_gyro, f, period)
    out["est_tilt"] = tf_response(*e_tilt, f, period)
    return out


def outer_per_gain(parts: dict[str, np.ndarray]) -> np.ndarray:
    """The attitude loop per unit K_a, broken at the rate reference with the rate loop closed: the estimate per
    rate reference, E_g T_g + E_a T_a, T the rate reference -> gyro and -> tilt."""
    forward = parts["delay"] * parts["pi"]
    closed = 1.0 + forward * parts["gyro"]
    return (parts["est_gyro"] * forward * parts["gyro"] + parts["est_tilt"] * forward * parts["tilt"]) / closed


def design(p: GimbalParams) -> dict[str, AxisGains]:
    """The gains of every stabilised axis."""
    return {axis: design_axis(p, axis) for axis in p.stabilised}
