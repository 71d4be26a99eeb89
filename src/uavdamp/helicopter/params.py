"""The helicopter's parameters: the config section ``helicopter`` as typed sections, SI units.

    Helicopter          the vehicle: fuselage, main and tail rotor, blade imbalance, platform mount point
    HelicopterRun       a Helicopter with its solver: what a vacuum run job sees (the paper's runs)
    FlightRun           a HelicopterRun with its aerodynamics and flight (gravity, trim, hold): a flight run's job
    HelicopterSection   the whole config section: a flight run plus the analyses' options (spectrum, campbell,
                        sensitivity)

Config keys carry their unit (``blade_mass_kg``, ``lag_damping_n_m_s_rad``); the Python names drop it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from uavdamp.settings import NAME, key_of, require, setting, unknown_key

_W = "helicopter."
INFLOW_MODELS = ("none", "uniform", "pitt_peters")  # none: no aerodynamics at all (the vacuum model)
FLIGHTS = ("vacuum", "hover", "forward")  # flight conditions: the paper's vacuum, trimmed hover, forward flight


SPEED_OF_SOUND = 340.3  # m s-1, ISA sea level (15 degC; the config's air density 1.225 kg m-3 is sea level): a choice
MAX_TIP_MACH = 0.95  # 1, largest advancing-tip Mach number: the quasi-steady incompressible sections' limit (choice)
MAX_ADVANCE_RATIO = 0.25  # 1, the range where the default trim converged (measured: 0.25 yes, 0.3 and 0.4 no)


def tip_mach(omega_rad_s: float, tip_radius_m: float, advance_ratio: float = 0.0) -> float:
    """Mach number of the advancing blade tip, Omega R (1 + mu) / SPEED_OF_SOUND, 1."""
    return omega_rad_s * tip_radius_m * (1.0 + advance_ratio) / SPEED_OF_SOUND


def max_hover_thrust(blade: BladeSection, n_blades: int, root_m: float, tip_m: float, omega: float, rho: float):
    """The most thrust the blade elements can make in hover, N: every section at its stall lift coefficient
    a alpha_stall, T = N rho c Omega^2 a alpha_stall (R^3 - r_0^3) / 6 (no inflow, no drag: an upper bound)."""
    c_l = blade.lift_slope * blade.stall_angle
    return n_blades * rho * blade.chord * omega**2 * c_l * (tip_m**3 - root_m**3) / 6.0


def _positive(value: float, where: str) -> None:
    require(value > 0, where, f"must be > 0, got {value}")


@dataclass(frozen=True)
class Fuselage:
    """Rigid fuselage (``helicopter.fuselage``)."""

    mass: float = setting("mass_kg")  # kg
    inertia: tuple[float, ...] = setting("inertia_kg_m2", length=3)  # Ixx, Iyy, Izz at the centre of mass, kg m2
    inertia_xz: float = setting("inertia_xz_kg_m2")  # inertia-tensor entry (x, z), kg m2

    def validate(self) -> None:
        _positive(self.mass, _W + "fuselage.mass_kg")
        _positive(min(self.inertia), _W + "fuselage.inertia_kg_m2")


@dataclass(frozen=True)
class MainRotor:
    """Articulated main rotor of uniform-rod blades (``helicopter.main_rotor``).

    blade_inertia: principal inertia at a blade's centre of mass in the paper's blade axes (x chordwise, y along
    the blade, z normal to the disc), kg m2. Hinge springs N m rad-1, dampers N m s rad-1.
    """

    n_blades: int = setting()
    blade_mass: float = setting("blade_mass_kg")  # kg
    blade_length: float = setting("blade_length_m")  # m, from the hinge to the tip
    blade_inertia: tuple[float, ...] = setting("blade_inertia_kg_m2", length=3)  # kg m2
    omega_rad_s: float = setting()  # rad s-1
    hub_height: float = setting("hub_height_m")  # m above the fuselage centre of mass
    hinge_offset: float = setting("hinge_offset_m")  # m, flap and lag hinges at the same radius
    flap_stiffness: float = setting("flap_stiffness_n_m_rad")
    flap_damping: float = setting("flap_damping_n_m_s_rad")
    lag_stiffness: float = setting("lag_stiffness_n_m_rad")
    lag_damping: float = setting("lag_damping_n_m_s_rad")
    feather_stiffness: float = setting("feather_stiffness_n_m_rad")  # pitch-link stiffness
    feather_damping: float = setting("feather_damping_n_m_s_rad")

    def validate(self) -> None:
        where = _W + "main_rotor."
        require(self.n_blades >= 2, where + "n_blades", f"must be >= 2, got {self.n_blades}")
        _blade(self, where)
        require(self.omega_rad_s > 0, where + "omega_rad_s", f"must be > 0, got {self.omega_rad_s}")
        require(self.hinge_offset >= 0, where + "hinge_offset_m", f"must be >= 0, got {self.hinge_offset}")
        for key in ("flap_stiffness", "flap_damping", "lag_stiffness", "lag_damping"):
            value = getattr(self, key)
            require(value >= 0, where + key_of(MainRotor, key), f"must be >= 0, got {value}")


@dataclass(frozen=True)
class TailRotor:
    """Tail rotor of rigid blades spinning about the lateral (y) axis (``helicopter.tail_rotor``)."""

    n_blades: int = setting()
    blade_mass: float = setting("blade_mass_kg")  # kg
    blade_length: float = setting("blade_length_m")  # m
    blade_inertia: tuple[float, ...] = setting("blade_inertia_kg_m2", length=3)  # kg m2, paper's blade axes
    omega_rad_s: float = setting()  # rad s-1, in the vibration runs (paper: stopped)
    omega_running_rad_s: float = setting()  # rad s-1, in the "both_rotors" run
    position: tuple[float, ...] = setting("position_m", length=3)  # m, hub in the fuselage frame

    def validate(self) -> None:
        where = _W + "tail_rotor."
        require(self.n_blades >= 1, where + "n_blades", f"must be >= 1, got {self.n_blades}")
        _blade(self, where)
        for key in ("omega_rad_s", "omega_running_rad_s"):
            value = getattr(self, key)
            require(value >= 0, where + key, f"must be >= 0, got {value}")


def _blade(rotor, where: str) -> None:
    """Blade mass, length and inertia positive, and a radius of gyration no longer than the blade."""
    _positive(rotor.blade_mass, where + "blade_mass_kg")
    _positive(rotor.blade_length, where + "blade_length_m")
    _positive(min(rotor.blade_inertia), where + "blade_inertia_kg_m2")
    gyration = float(np.sqrt(max(rotor.blade_inertia) / rotor.blade_mass))
    require(
        gyration <= rotor.blade_length,
        where + "blade_inertia_kg_m2",
        f"{max(rotor.blade_inertia)} kg m2 gives a radius of gyration {gyration:.3g} m longer than the blade "
        f"({rotor.blade_length} m)",
    )


@dataclass(frozen=True)
class Imbalance:
    """The imbalanced main blade (``helicopter.imbalance``): its index and its mass (and inertia) scale."""

    blade: int = setting()
    mass_factor: float = setting()  # 1

    def validate(self) -> None:
        require(self.blade >= 0, _W + "imbalance.blade", f"must be >= 0, got {self.blade}")
        require(self.mass_factor > 0, _W + "imbalance.mass_factor", f"must be > 0, got {self.mass_factor}")


@dataclass(frozen=True)
class SolverOptions:
    """Time integration (``helicopter.solver``): implicit generalized-alpha (explicit solvers ignore prescribed
    motion). newton_absolute_tolerance in N (N m for moments): the balanced rotor's residual is pure round-off of
    large cancelling centrifugal forces, below Exudyn's default 1e-10."""

    duration: float = setting("duration_s")  # s
    step: float = setting("step_s")  # s
    output_step: float = setting("output_step_s")  # s, sensor sampling period
    spectral_radius: float = setting()  # 1, generalized-alpha numerical damping at infinite frequency
    newton_tolerance: float = setting()  # 1, relative residual tolerance of (modified) Newton
    newton_absolute_tolerance: float = setting("newton_absolute_tolerance_n")  # N (N m)

    def validate(self) -> None:
        where = _W + "solver."
        for name, key in (("duration", "duration_s"), ("step", "step_s"), ("output_step", "output_step_s")):
            _positive(getattr(self, name), where + key)
        ratio = self.output_step / self.step
        require(
            abs(ratio - round(ratio)) <= 1e-9 and round(ratio) >= 1,
            where + "output_step_s",
            f"{self.output_step} s must be a whole multiple of {where}step_s {self.step} s (uniform sampling for "
            "the FFT)",
        )
        require(
            0 <= self.spectral_radius <= 1, where + "spectral_radius", f"must lie in [0, 1], got {self.spectral_radius}"
        )


@dataclass(frozen=True)
class Helicopter:
    """The vehicle (SI units): fuselage, rotors, the blade imbalance and the platform mount points by name (m,
    fuselage frame: x forward, y left, z up, origin at the fuselage centre of mass)."""

    fuselage: Fuselage
    main_rotor: MainRotor
    tail_rotor: TailRotor
    imbalance: Imbalance
    mount_points: dict[str, tuple[float, ...]] = setting("mount_points_m")

    def validate(self) -> None:
        require(bool(self.mount_points), _W + "mount_points_m", "needs at least one mount point {name: [x, y, z]}")
        for name, point in self.mount_points.items():
            where = f"{_W}mount_points_m.{name}"
            require(NAME.fullmatch(name) is not None, where, f"a name must match {NAME.pattern} (it names files)")
            require(len(point) == 3, where, f"needs 3 values (x, y, z m), got {list(point)}")
        n = self.main_rotor.n_blades
        require(
            0 <= self.imbalance.blade < n,
            _W + "imbalance.blade",
            f"must lie in [0, {n - 1}] (helicopter.main_rotor.n_blades = {n}), got {self.imbalance.blade}",
        )

    def balanced(self) -> Helicopter:
        """The same helicopter with every main blade at its nominal mass."""
        return replace(self, imbalance=replace(self.imbalance, mass_factor=1.0))

    def with_tail_rotor_speed(self, omega_rad_s: float) -> Helicopter:
        """The same helicopter with the tail rotor turning at `omega_rad_s`."""
        return replace(self, tail_rotor=replace(self.tail_rotor, omega_rad_s=float(omega_rad_s)))

    def blade_masses(self) -> np.ndarray:
        """Mass of each main rotor blade, kg (the imbalanced one scaled)."""
        masses = np.full(self.main_rotor.n_blades, self.main_rotor.blade_mass)
        masses[self.imbalance.blade] *= self.imbalance.mass_factor
        return masses

    def total_mass(self) -> float:
        """Mass of the whole helicopter, kg."""
        tail = self.tail_rotor
        return self.fuselage.mass + self.blade_masses().sum() + tail.n_blades * tail.blade_mass


@dataclass(frozen=True, kw_only=True)
class HelicopterRun(Helicopter):
    """A helicopter with its solver: the view a simulation job receives (the section without the analyses)."""

    solver: SolverOptions


@dataclass(frozen=True)
class Spectrum:
    """Dominant-line search of the vibration stage (``helicopter.spectrum``)."""

    min_omega_rad_s: float = setting()  # rad s-1, the dominant line is searched above this
    zero_padding: int = setting()  # FFT length as a multiple of the record length

    def validate(self) -> None:
        _positive(self.min_omega_rad_s, _W + "spectrum.min_omega_rad_s")
        require(self.zero_padding >= 1, _W + "spectrum.zero_padding", f"must be >= 1, got {self.zero_padding}")


@dataclass(frozen=True)
class Campbell:
    """Coupled modes against rotor speed, Floquet of the imbalanced rotor (``helicopter.campbell``)."""

    max_speed_ratio: float = setting()  # 1, rotor speeds from 0 to this times main_rotor.omega_rad_s
    n_speeds: int = setting()
    check_azimuths_rad: tuple[float, ...] = setting()  # rad
    floquet_steps: int = setting()  # azimuth steps per revolution of the monodromy matrix

    def validate(self) -> None:
        _positive(self.max_speed_ratio, _W + "campbell.max_speed_ratio")
        require(self.n_speeds >= 2, _W + "campbell.n_speeds", f"must be >= 2, got {self.n_speeds}")
        require(self.floquet_steps >= 4, _W + "campbell.floquet_steps", f"must be >= 4, got {self.floquet_steps}")


@dataclass(frozen=True)
class BladeSection:
    """Airfoil and planform of one rotor's blades (``helicopter.aerodynamics.main_blade`` and ``tail_blade``).

    twist: linear, pitch change from the shaft axis to the tip, rad; root_cutout from the hinge (tail: hub axis), m.
    Lift a (alpha - alpha_0) clipped at +-stall_angle; drag C_d0 + C_d2 alpha^2 (`uavdamp.helicopter.aerodynamics`).
    """

    chord: float = setting("chord_m")  # m
    twist: float = setting("twist_rad")  # rad
    root_cutout: float = setting("root_cutout_m")  # m
    lift_slope: float = setting("lift_slope_per_rad")  # rad-1
    zero_lift_angle: float = setting("zero_lift_angle_rad")  # rad
    drag_coefficient: float = setting()  # 1, C_d0
    drag_coefficient_quadratic: float = setting("drag_coefficient_quadratic_per_rad2")  # rad-2, C_d2
    stall_angle: float = setting("stall_angle_rad")  # rad

    def validate(self, where: str) -> None:
        for key in ("chord", "lift_slope", "stall_angle"):
            _positive(getattr(self, key), f"{where}.{key_of(BladeSection, key)}")
        for key in ("root_cutout", "drag_coefficient", "drag_coefficient_quadratic"):
            value = getattr(self, key)
            require(value >= 0, f"{where}.{key_of(BladeSection, key)}", f"must be >= 0, got {value}")


@dataclass(frozen=True)
class Aerodynamics:
    """Blade-element loads of the flight runs (``helicopter.aerodynamics``); inflow "none" is the vacuum model."""

    inflow: str = setting()  # none | uniform | pitt_peters
    air_density: float = setting("air_density_kg_m3")  # kg m-3
    n_stations: int = setting()  # Gauss stations per blade
    main_blade: BladeSection = setting()
    tail_blade: BladeSection = setting()

    def validate(self) -> None:
        where = _W + "aerodynamics."
        require(self.inflow in INFLOW_MODELS, where + "inflow", f"must be one of {list(INFLOW_MODELS)}")
        _positive(self.air_density, where + "air_density_kg_m3")
        require(self.n_stations >= 1, where + "n_stations", f"must be >= 1, got {self.n_stations}")

    @property
    def enabled(self) -> bool:
        """False for inflow "none": no aerodynamics, no gravity, no flight runs."""
        return self.inflow != "none"


@dataclass(frozen=True)
class TrimOptions:
    """The trim solve (``helicopter.flight.trim``): Newton on the revolution-averaged loads on the held fuselage."""

    settle: float = setting("settle_s")  # s from the start before the first residual
    step_settle: float = setting("step_settle_s")  # s after each change of the unknowns before the next residual
    perturbation: float = setting("perturbation_rad")  # rad, finite-difference step of controls and attitude
    tolerance: float = setting()  # 1, forces over the weight, moments over weight x rotor radius
    max_iterations: int = setting()  # Newton steps after the finite-difference Jacobian

    def validate(self) -> None:
        where = _W + "flight.trim."
        for key in ("settle", "step_settle", "perturbation", "tolerance"):
            _positive(getattr(self, key), where + key_of(TrimOptions, key))
        require(self.max_iterations >= 1, where + "max_iterations", f"must be >= 1, got {self.max_iterations}")


@dataclass(frozen=True)
class HoldOptions:
    """The pilot (``helicopter.flight.hold``): attitude hold on cyclic and tail collective, height hold on
    collective, PID per axis with closed-loop natural frequency 2 pi bandwidth_hz; a position hold (PD) of natural
    frequency 2 pi position_bandwidth_hz sets the attitude's roll and pitch (`uavdamp.helicopter.hold`)."""

    enabled: bool = setting()  # false: the controls stay at the trim (open loop)
    bandwidth_hz: float = setting()  # Hz
    position_bandwidth_hz: float = setting()  # Hz
    damping_ratio: float = setting()  # 1
    integral_time: float = setting("integral_time_s")  # s, Ki = Kp / integral_time

    def validate(self) -> None:
        where = _W + "flight.hold."
        ok = self.position_bandwidth_hz < self.bandwidth_hz
        require(
            ok, where + "position_bandwidth_hz", f"must be below bandwidth_hz ({self.bandwidth_hz}): the outer loop"
        )
        for key in ("bandwidth_hz", "position_bandwidth_hz", "damping_ratio", "integral_time"):
            _positive(getattr(self, key), where + key_of(HoldOptions, key))


@dataclass(frozen=True)
class Flight:
    """Gravity, the free stream, the trim and the pilot of the flight runs (``helicopter.flight``)."""

    gravity: float = setting("gravity_m_s2")  # m s-2
    fuselage_drag_area: float = setting("fuselage_drag_area_m2")  # m2, equivalent flat plate
    forward_advance_ratio: float = setting()  # 1, free stream over the main rotor tip speed, "forward" run
    release: float = setting("release_s")  # s of tethered then free flight after the trim, before the record
    trim: TrimOptions = setting()
    hold: HoldOptions = setting()
    # false: a trim above trim.tolerance fails its job; true: flown, recorded (trim_converged = 0) and flagged
    allow_unconverged: bool = setting(default=False)

    def validate(self) -> None:
        where = _W + "flight."
        _positive(self.gravity, where + "gravity_m_s2")
        require(self.fuselage_drag_area >= 0, where + "fuselage_drag_area_m2", "must be >= 0")
        ratio = self.forward_advance_ratio
        require(
            0 < ratio <= MAX_ADVANCE_RATIO,
            where + "forward_advance_ratio",
            f"must lie in (0, {MAX_ADVANCE_RATIO}], got {ratio}: the quasi-steady blade-element trim with uniform "
            f"inflow converged up to mu = {MAX_ADVANCE_RATIO} (residual 1.2e-5, the config's trim; measured), not at "
            "0.3 (5.9e-4 after 6 Newton steps) or 0.4 (0.083)",
        )
        _positive(self.release, where + "release_s")


@dataclass(frozen=True, kw_only=True)
class FlightRun(HelicopterRun):
    """A run with aerodynamics, gravity, trim and pilot: the view a flight (hover, forward) job receives."""

    aerodynamics: Aerodynamics
    flight: Flight


# the parameters a sensitivity run may change (how: `uavdamp.helicopter.sensitivity.PARAMETERS`)
SENSITIVITY_PARAMETERS = (
    "lag_stiffness_n_m_rad",
    "lag_damping_n_m_s_rad",
    "hinge_offset_m",
    "feather_stiffness_n_m_rad",
    "imbalance_mass_factor",
    "fuselage_inertia_scale",
    "fuselage_ixx_scale",
)


@dataclass(frozen=True)
class Sensitivity:
    """One-at-a-time runs of the imbalanced helicopter (``helicopter.sensitivity``): values per parameter
    (SENSITIVITY_PARAMETERS), the run length and the flight condition (FLIGHTS) of every run."""

    duration: float = setting("duration_s")  # s
    flight: str = setting()  # vacuum | hover | forward
    parameters: dict[str, tuple[float, ...]] = setting()

    def validate(self) -> None:
        _positive(self.duration, _W + "sensitivity.duration_s")
        require(self.flight in FLIGHTS, _W + "sensitivity.flight", f"must be one of {list(FLIGHTS)}")
        for name in self.parameters:
            if name not in SENSITIVITY_PARAMETERS:
                raise unknown_key(_W + "sensitivity.parameters", name, list(SENSITIVITY_PARAMETERS))


@dataclass(frozen=True, kw_only=True)
class HelicopterSection(FlightRun):
    """The config section ``helicopter``: a flight run and the options of the vibration, Campbell and sensitivity
    stages."""

    spectrum: Spectrum
    campbell: Campbell
    sensitivity: Sensitivity
