"""The payload stage's config sections for the gimbal (``payload.gimbal``), the six-axis isolator
(``payload.six_axis``), its wire-rope elements (``payload.wire_rope``) and its MR dampers (``payload.mr``), SI
units; `uavdamp.study.payload` holds the section ``payload`` that carries them."""

from __future__ import annotations

import math
from dataclasses import dataclass

from uavdamp.contract import STANDARD_GRAVITY
from uavdamp.platform.gimbal import GimbalParams, design
from uavdamp.platform.imu import ImuParams
from uavdamp.platform.six_axis import KINDS
from uavdamp.platform.wire_rope import WireRope
from uavdamp.settings import ConfigError, attached, require, setting


@dataclass(frozen=True)
class GimbalSection:
    """The gimbal (``payload.gimbal``): `uavdamp.platform.gimbal.GimbalParams`' defaults for the keys not here."""

    axes: tuple[str, ...] = setting(default=("roll", "pitch", "yaw"))
    loop_rate_hz: float = setting(default=1000.0)  # Hz
    rate_crossover_hz: tuple[float, ...] = setting(default=(40.0, 40.0, 40.0), length=3)  # Hz, roll, pitch, yaw
    phase_margin_deg: tuple[float, ...] = setting(default=(50.0, 50.0, 50.0), length=3)  # deg, roll, pitch, yaw
    attitude_fraction: float = setting(default=0.2)  # 1, attitude crossover / rate crossover
    torque_constant: float = setting("torque_constant_n_m_a", default=0.12)  # N m A-1
    current_limit: float = setting("current_limit_a", default=2.0)  # A
    imbalance_m: tuple[float, ...] = setting(default=(0.0, 0.0, 0.0), length=3)  # m, camera COM from the axes
    sensor_errors: bool = setting(default=True)  # the IMU's noise, bias and quantisation
    # Hz, the complementary filter's crossover (accelerometer below, gyro above): BruGi's 7 s by default
    estimator_crossover_hz: float = setting(default=1.0 / (2 * math.pi * 7.0))
    accel_range_g: float = setting(default=2.0)  # g, the IMU accelerometer's full scale +/-
    gyro_bias: tuple[float, ...] = setting("gyro_bias_rad_s", default=(0.0, 0.0, 0.0), length=3)  # rad s-1, x y z
    camera_mass: float = attached(0.9)  # kg, the platform's camera (platform.structure): `with_camera`
    camera_size: tuple[float, ...] = attached((0.10, 0.06, 0.06))  # m, its box's x, y, z edges, the same

    def params(self) -> GimbalParams:
        """The `GimbalParams` of this section (its own checks)."""
        return GimbalParams(
            axes=tuple(self.axes),
            loop_rate_hz=self.loop_rate_hz,
            rate_crossover_hz=tuple(self.rate_crossover_hz),
            phase_margin_deg=tuple(self.phase_margin_deg),
            attitude_fraction=self.attitude_fraction,
            torque_constant=self.torque_constant,
            current_limit=self.current_limit,
            imbalance_m=tuple(self.imbalance_m),
            estimator_crossover_hz=self.estimator_crossover_hz,
            imu=ImuParams(accel_range=self.accel_range_g * STANDARD_GRAVITY, gyro_bias=tuple(self.gyro_bias)),
            camera_mass=self.camera_mass,
            camera_size=tuple(self.camera_size),
        )

    def validate(self, where: str) -> None:
        try:
            design(self.params())  # GimbalParams' checks and a gain design that exists
        except ConfigError as error:  # its messages start "gimbal.<key>"
            raise ConfigError(f"{where.rsplit('.', 1)[0]}.{error}") from None


@dataclass(frozen=True)
class SixAxisSection:
    """The six-axis isolator (``payload.six_axis``): four equal elements on a square (`square_layout`)."""

    kind: str = setting(default="rubber_ball")  # of uavdamp.platform.six_axis.KINDS
    half_spacing: float = setting("half_spacing_m", default=0.05)  # m
    stiffness: tuple[float, ...] = setting("stiffness_n_m", default=(250.0, 250.0, 500.0), length=3)  # N m-1
    plate_mass: float = setting("plate_mass_kg", default=0.3)  # kg, isolated plate + gimbal base
    com_height: float = setting("com_height_m", default=0.06)  # m, payload COM above the elements (< 0: below)

    def validate(self, where: str) -> None:
        require(self.kind in KINDS, f"{where}.kind", f"must be one of {list(KINDS)}, got {self.kind!r}")
        require(self.half_spacing > 0, f"{where}.half_spacing_m", f"must be > 0, got {self.half_spacing}")
        require(min(self.stiffness) > 0, f"{where}.stiffness_n_m", f"must be > 0, got {list(self.stiffness)}")
        require(self.plate_mass >= 0, f"{where}.plate_mass_kg", f"must be >= 0, got {self.plate_mass}")


@dataclass(frozen=True)
class WireRopeSection:
    """The six-axis isolator's wire-rope variant (``payload.wire_rope``, the mount ``wire_rope``): the same elements
    (``payload.six_axis``) with a Bouc-Wen hysteresis along ``axes`` (`uavdamp.platform.wire_rope.WireRope`)."""

    axes: tuple[str, ...] = setting(default=("x", "y"))  # the hysteretic axes (wire rope: lateral)
    alpha: float = setting(default=0.5)  # 1, post-yield over initial stiffness
    yield_stroke: float = setting("yield_stroke_m", default=1.0e-3)  # m, z_max
    exponent: float = setting(default=1.0)  # 1, n
    beta_share: float = setting(default=0.5)  # 1, beta / (beta + gamma)

    def params(self) -> WireRope:
        """The `WireRope` of this section (its checks name payload.wire_rope.<key>)."""
        return WireRope(tuple(self.axes), self.alpha, self.yield_stroke, self.exponent, self.beta_share)

    def validate(self, where: str) -> None:
        try:
            self.params()
        except ValueError as error:  # its messages name payload.wire_rope.<key>
            raise ConfigError(str(error)) from None


@dataclass(frozen=True)
class MRSection:
    """The Spencer MR dampers on the six-axis isolator's elements (``payload.mr``; `uavdamp.platform.six_axis_force`):
    the published damper scaled (`uavdamp.damping.dampers.SpencerParams.for_platform`) to span
    ``damping_range_n_s_m`` (equivalent damping at 0 V and 2.25 V at the reference stroke, 8 Hz and 0.05 m/s: the
    benchmark's)."""

    enabled: bool = setting(default=True)  # run the MR dampers beside the ideal ones
    damping_range: tuple[float, ...] = setting("damping_range_n_s_m", default=(1.0, 6.0), length=2)  # N s m-1
    max_substep: float = setting("max_substep_s", default=5.0e-4)  # s, the Spencer model's internal sub-step

    def validate(self, where: str) -> None:
        lo, hi = self.damping_range
        require(0 < lo < hi, f"{where}.damping_range_n_s_m", f"need 0 < c_off < c_on N s m-1, got {[lo, hi]}")
        ok = math.isfinite(self.max_substep) and self.max_substep > 0
        require(ok, f"{where}.max_substep_s", f"must be > 0, got {self.max_substep}")
