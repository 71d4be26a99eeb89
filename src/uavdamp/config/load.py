"""The one config layer: the whole config as typed, frozen sections, loaded with every key checked before any job.

`load(mapping)` parses every section of a merged config (Snakemake's `config`) into `Config`, refusing unknown,
renamed, missing and ill-typed keys with the dotted key and the rule it breaks (`uavdamp.settings`). Each rule
receives the part of a section its job uses through `params:`; the job parses that view with the same section
class (`view` keeps exactly a class's keys), so the config means the same in the Snakefile and in every job.

Sections (module: class): helicopter (`uavdamp.helicopter`: HelicopterSection), platform (`uavdamp.platform`:
PlatformSection), reference_table (`uavdamp.reference_table`: ReferenceTableSection), anfis (`uavdamp.anfis`:
AnfisSection), study (`uavdamp.study.comparison`: StudySection), camera (`uavdamp.camera.optics`: CameraModel), budget
(`uavdamp.config.budget`: Budget), benchmark (`BenchmarkSection` here: the scenarios', the runs' and the split's views),
flight_logs (`uavdamp.sources.flight_log`: FlightLogSource per name), sources (`uavdamp.sources.stated`:
StatedSource per name), levels (`uavdamp.sources.levels_survey`: LevelsSection), payload
(`uavdamp.study.payload`: PayloadSection).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from uavdamp.anfis import AnfisSection
from uavdamp.benchmark.loop import BenchmarkOptions
from uavdamp.benchmark.payload import PayloadBenchmark
from uavdamp.benchmark.scenarios import ScenarioOptions, Split
from uavdamp.camera.optics import CameraModel
from uavdamp.config.budget import Budget
from uavdamp.helicopter import HelicopterSection
from uavdamp.platform import PlatformSection
from uavdamp.reference_table import ReferenceTableSection
from uavdamp.settings import NAME, RENAMED, ConfigError, parse, require, setting, view
from uavdamp.signals.tracking import TrackerOptions
from uavdamp.sources.flight_log import FlightLogSource
from uavdamp.sources.levels_survey import LevelsSection
from uavdamp.sources.stated import StatedSource
from uavdamp.study.comparison import StudyOptions, StudySection
from uavdamp.study.payload import PayloadSection

__all__ = ["Config", "ConfigError", "benchmark_options", "load", "study_options", "view"]


@dataclass(frozen=True, kw_only=True)
class BenchmarkSection(BenchmarkOptions, ScenarioOptions):
    """The config section ``benchmark``: the scenarios (`ScenarioOptions`), the runs (`BenchmarkOptions`), the split,
    the benchmark on the payload (`PayloadBenchmark`)."""

    split: Split = setting()
    # K or the tracker band outside the reference table's ranges: refused unless true
    # (`uavdamp.config.checks.extrapolation`)
    allow_extrapolation: bool = setting(default=False)
    payload: PayloadBenchmark = setting(
        default=PayloadBenchmark()
    )  # the benchmark on the payload (`uavdamp.benchmark.payload`)

    def validate(self) -> None:
        BenchmarkOptions.validate(self)
        ScenarioOptions.validate(self)


@dataclass(frozen=True)
class Config:
    """The whole config, every section typed."""

    output_dir: str  # folder (relative, no ..) every output goes under
    plugins: tuple[str, ...]  # plug-in law files (.py, relative to the run directory): `uavdamp.plugins`
    helicopter: HelicopterSection
    platform: PlatformSection
    reference_table: ReferenceTableSection
    anfis: AnfisSection
    study: StudySection
    camera: CameraModel
    budget: Budget
    benchmark: BenchmarkSection
    flight_logs: dict[str, FlightLogSource]  # measured flights by name (the flight_log stage; cases name them)
    sources: dict[str, StatedSource]  # stated vibration sources by name (`uavdamp.sources.stated`; cases name them)
    levels: LevelsSection  # the levels stage: every input's levels at the mount (g, in/s, VIBE)
    payload: PayloadSection  # the payload stage: payloads x mounts x damping on the cases and stated sources

    def validate(self) -> None:
        parts = self.output_dir.split("/")
        require(
            all(NAME.fullmatch(p) and p != ".." for p in parts),
            "output_dir",
            f"must be a relative folder of names [A-Za-z0-9_.-] (no '..', not absolute), got {self.output_dir!r}",
        )


def load(mapping) -> Config:
    """The typed config of a merged config mapping; ConfigError names the first bad key."""
    return parse(Config, mapping, "")


def study_options(study: dict, camera: dict) -> StudyOptions:
    """The study runs' options from their views of ``study`` and ``camera`` (the camera attached)."""
    return replace(parse(StudyOptions, study, "study"), camera=parse(CameraModel, camera, "camera"))


def benchmark_options(runs: dict, tracking: dict, camera: dict) -> BenchmarkOptions:
    """The benchmark runs' options from their views of ``benchmark``, ``study.tracking`` and ``camera``."""
    options = parse(BenchmarkOptions, runs, "benchmark")
    tracker = parse(TrackerOptions, tracking, "study.tracking")
    return replace(options, tracking=tracker, camera=parse(CameraModel, camera, "camera"))


def _renames() -> dict[str, str]:
    """Old dotted key -> new key name: the keys renamed to carry their unit."""
    h = "helicopter."
    pairs = {
        h + "fuselage": {"mass": "mass_kg", "inertia": "inertia_kg_m2", "inertia_xz": "inertia_xz_kg_m2"},
        h + "main_rotor": {
            "blade_mass": "blade_mass_kg",
            "blade_length": "blade_length_m",
            "blade_inertia": "blade_inertia_kg_m2",
            "hub_height": "hub_height_m",
            "hinge_offset": "hinge_offset_m",
            "flap_stiffness": "flap_stiffness_n_m_rad",
            "flap_damping": "flap_damping_n_m_s_rad",
            "lag_stiffness": "lag_stiffness_n_m_rad",
            "lag_damping": "lag_damping_n_m_s_rad",
            "feather_stiffness": "feather_stiffness_n_m_rad",
            "feather_damping": "feather_damping_n_m_s_rad",
        },
        h + "tail_rotor": {
            "blade_mass": "blade_mass_kg",
            "blade_length": "blade_length_m",
            "blade_inertia": "blade_inertia_kg_m2",
            "position": "position_m",
        },
        h + "solver": {
            "duration": "duration_s",
            "step": "step_s",
            "output_step": "output_step_s",
            "newton_absolute_tolerance": "newton_absolute_tolerance_n",
        },
        h + "sensitivity": {"duration": "duration_s"},
        h + "sensitivity.parameters": {
            "lag_stiffness": "lag_stiffness_n_m_rad",
            "lag_damping": "lag_damping_n_m_s_rad",
            "hinge_offset": "hinge_offset_m",
            "feather_stiffness": "feather_stiffness_n_m_rad",
        },
        "helicopter": {"mount_point": "mount_points_m", "mount_point_m": "mount_points_m"},
        "reference_table": {
            "stiffness": "stiffness_n_m",
            "damping": "damping_n_s_m",
            "amplitude": "amplitude_m",
            "duration": "duration_s",
            "windows": "windows_s",
        },
        "study.cases.*": {"amplitude": "amplitude_m"},
    }
    return {f"{where}.{old}": new for where, keys in pairs.items() for old, new in keys.items()}


RENAMED.update(_renames())
