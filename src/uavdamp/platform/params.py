"""Platform, isolator and solver parameters: the config section ``platform`` as typed sections, SI units.

Config keys carry their unit (``base_mass_kg``, ``time_step_s``); the Python names drop it where it is SI base.
"""

from __future__ import annotations

from dataclasses import dataclass

from uavdamp.settings import require, setting

BACKENDS = ("exudyn", "linear")
WEIGHT_SUPPORTS = ("spring", "preloaded")


@dataclass(frozen=True)
class StrokeBudget:
    """The isolator's stroke budget (``platform.stroke``; `uavdamp.platform.stroke`): reported, the dynamics do not
    depend on it, so an edit reruns the study's budget, not the grid."""

    weight_support: str = setting()  # "spring" (the spring carries the weight: static sag m g / K) or "preloaded"
    max_stroke: float = setting("max_stroke_m")  # m, the stroke allowed each way from the unloaded length
    manoeuvre_g: float = setting()  # 1, quasi-static manoeuvre load factor the stroke must also take

    def validate(self) -> None:
        where = "platform.stroke."
        require(
            self.weight_support in WEIGHT_SUPPORTS,
            where + "weight_support",
            f"must be one of {list(WEIGHT_SUPPORTS)}, got {self.weight_support!r}",
        )
        require(self.max_stroke > 0, where + "max_stroke_m", f"must be > 0, got {self.max_stroke}")
        require(self.manoeuvre_g >= 0, where + "manoeuvre_g", f"must be >= 0, got {self.manoeuvre_g}")


@dataclass(frozen=True)
class Structure:
    """Bodies, targets and damping ratios (``platform.structure``)."""

    base_mass: float = setting("base_mass_kg")  # kg, base riding on the isolator
    intermediate_mass: float = setting("intermediate_mass_kg")  # kg, yaw body (pan bracket + yaw servo)
    intermediate_yaw_inertia: float = setting("intermediate_yaw_inertia_kg_m2")  # kg m2, about the yaw axis
    pitch_body_mass: float = setting("pitch_body_mass_kg")  # kg, tilt bracket + pitch servo, COM on the pitch axis
    pitch_body_inertia: float = setting("pitch_body_inertia_kg_m2")  # kg m2, about its COM (pitch and yaw axes)
    camera_mass: float = setting("camera_mass_kg")  # kg (paper: 0.9 kg)
    camera_size: tuple[float, ...] = setting("camera_size_m", length=3)  # m, (x, y, z) edges of a uniform box
    camera_com_x: float = setting("camera_com_x_m")  # m, camera COM forward of the pitch axis
    camera_com_z: float = setting("camera_com_z_m")  # m, camera COM above the pitch axis
    natural_frequencies_hz: tuple[float, ...] = setting(length=3)  # Hz, undamped clamped-base targets
    structural_damping_ratio: float = setting()  # 1, of the displacement spring
    servo_damping_ratio: float = setting()  # 1, servo D terms
    servo_integral_time: float = setting("servo_integral_time_s")  # s, Ki = Kp / servo_integral_time

    def validate(self) -> None:
        where = "platform.structure."
        for name, key in (
            ("base_mass", "base_mass_kg"),
            ("intermediate_mass", "intermediate_mass_kg"),
            ("intermediate_yaw_inertia", "intermediate_yaw_inertia_kg_m2"),
            ("pitch_body_mass", "pitch_body_mass_kg"),
            ("pitch_body_inertia", "pitch_body_inertia_kg_m2"),
            ("camera_mass", "camera_mass_kg"),
            ("servo_integral_time", "servo_integral_time_s"),
        ):
            require(getattr(self, name) > 0, where + key, f"must be > 0, got {getattr(self, name)}")
        require(min(self.camera_size) > 0, where + "camera_size_m", f"must be > 0, got {self.camera_size}")
        freqs = self.natural_frequencies_hz
        require(min(freqs) > 0, where + "natural_frequencies_hz", f"must be > 0, got {freqs}")
        require(len(set(freqs)) == 3, where + "natural_frequencies_hz", f"must be distinct, got {freqs}")
        for name in ("structural_damping_ratio", "servo_damping_ratio"):
            require(getattr(self, name) >= 0, where + name, f"must be >= 0, got {getattr(self, name)}")

    @property
    def total_mass(self) -> float:
        """Mass of base, intermediate body, pitch body and camera, kg."""
        return self.base_mass + self.intermediate_mass + self.pitch_body_mass + self.camera_mass


@dataclass(frozen=True)
class Isolator:
    """Semi-active spring-damper between fuselage and base (``platform.isolator``)."""

    stiffness: float = setting("stiffness_n_m")  # N m-1, default K (paper: 10 N/m)
    damping_min: float = setting("damping_min_n_s_m")  # N s m-1, damper lower bound
    damping_max: float = setting("damping_max_n_s_m")  # N s m-1, damper upper bound
    update_period: float = setting("update_period_s")  # s, damping update period (paper: 0.5 s)

    def validate(self) -> None:
        where = "platform.isolator."
        require(self.stiffness > 0, where + "stiffness_n_m", f"must be > 0, got {self.stiffness}")
        require(self.damping_min >= 0, where + "damping_min_n_s_m", f"must be >= 0, got {self.damping_min}")
        require(
            self.damping_max >= self.damping_min,
            where + "damping_max_n_s_m",
            f"({self.damping_max}) must be >= {where}damping_min_n_s_m ({self.damping_min})",
        )
        require(self.update_period > 0, where + "update_period_s", f"must be > 0, got {self.update_period}")


@dataclass(frozen=True)
class Solver:
    """Time integration (``platform.solver``)."""

    time_step: float = setting("time_step_s")  # s, solver step
    # 1, input frequencies must stay below this x Nyquist (uavdamp.config.checks)
    max_frequency_fraction: float = setting()

    def validate(self) -> None:
        require(self.time_step > 0, "platform.solver.time_step_s", f"must be > 0, got {self.time_step}")
        require(
            0 < self.max_frequency_fraction <= 1,
            "platform.solver.max_frequency_fraction",
            f"must lie in (0, 1], got {self.max_frequency_fraction}",
        )


@dataclass(frozen=True)
class Response:
    """The platform stage's response figure (``platform.response``): a mono-frequency input per axis."""

    freq_y_hz: float  # Hz, y input frequency
    freq_z_hz: float  # Hz, z input frequency
    amplitude: float = setting("amplitude_m")  # m, input amplitude (paper: 1.3 mm)
    duration: float = setting("duration_s")  # s, run length
    damping: float = setting("damping_n_s_m")  # N s m-1, isolator damping of the isolated run

    def validate(self) -> None:
        for name, key in (
            ("freq_y_hz", "freq_y_hz"),
            ("freq_z_hz", "freq_z_hz"),
            ("amplitude", "amplitude_m"),
            ("duration", "duration_s"),
        ):
            value = getattr(self, name)
            require(value > 0, f"platform.response.{key}", f"must be > 0, got {value}")


@dataclass(frozen=True)
class PlatformParams:
    """The platform the plants build: structure, isolator, solver and the plant of the isolated runs (``backend``:
    "linear" or "exudyn", `uavdamp.platform.plants`). The config section without ``response``: what the grid,
    study and benchmark jobs receive, so that a figure edit does not rerun them."""

    structure: Structure
    isolator: Isolator
    solver: Solver
    backend: str
    gravity: float = setting("gravity_m_s2")  # m s-2, along -z of the inertial frame (0: the weightless platform)

    def validate(self) -> None:
        require(self.gravity >= 0, "platform.gravity_m_s2", f"must be >= 0, got {self.gravity}")
        require(self.backend in BACKENDS, "platform.backend", f"must be one of {list(BACKENDS)}, got {self.backend!r}")
        require(
            self.isolator.update_period >= self.solver.time_step,
            "platform.isolator.update_period_s",
            f"({self.isolator.update_period}) must be >= platform.solver.time_step_s ({self.solver.time_step})",
        )

    # the values every plant and law needs, by their short names
    @property
    def time_step(self) -> float:
        return self.solver.time_step

    @property
    def update_period(self) -> float:
        return self.isolator.update_period

    @property
    def damping_min(self) -> float:
        return self.isolator.damping_min

    @property
    def damping_max(self) -> float:
        return self.isolator.damping_max

    @property
    def isolator_stiffness(self) -> float:
        return self.isolator.stiffness


@dataclass(frozen=True, kw_only=True)
class PlatformSection(PlatformParams):
    """The config section ``platform``: the platform, its stroke budget and the platform stage's response figure."""

    stroke: StrokeBudget
    response: Response

    def validate(self) -> None:
        super().validate()
        c = self.response.damping
        require(
            self.isolator.damping_min <= c <= self.isolator.damping_max,
            "platform.response.damping_n_s_m",
            f"{c} must lie within the damper bounds [{self.isolator.damping_min}, {self.isolator.damping_max}] N s m-1",
        )
