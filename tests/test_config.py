"""The one config layer: every shipped config loads typed, every key is documented, and a bad config is refused
naming the key and the rule it breaks (`uavdamp.config.checks.validate`: typed load, schema ranges, cross-section
checks).

Each case edits config/quick.yaml's merged config; tests/workflow/test_config_checks.py runs the same refusals
through Snakemake and checks that no job starts.
"""

from __future__ import annotations

import dataclasses
import re
import types
import typing

import pytest
import yaml
from conftest import ROOT, deep_update, load_config

from uavdamp.config import checks
from uavdamp.config import docs as config_docs
from uavdamp.config.load import Config, load
from uavdamp.settings import RENAMED, ConfigError, key_of

STATED_CASE = {"motion": "full", "amplitude_scaling": "measured", "amplitude_reading": "dominant", "description": "x"}
# (override merged over quick.yaml, text the error must contain)
BAD = {
    # the payload stage reads the study's cases from their start; a multirotor source needs its VIBE's settling
    # a stated source as a case: its lines below the platform solver's limit and one of them in the tracker's band
    "source-lines-above-the-platform-limit": (
        {"study": {"cases": {"case4": {"source": "heli_sine_on_random", **STATED_CASE}}}},
        "study.cases.case4.source: the source 'heli_sine_on_random' puts its lines at 7.0665-84.798 Hz: each must "
        "stay below",
    ),
    "source-lines-outside-the-tracker-band": (
        {
            "sources": {"tones_30": {"kind": "tones", "freq_y_hz": [30.0], "freq_z_hz": [31.0], "amplitude_m": 1e-4}},
            "study": {"cases": {"case4": {"source": "tones_30", **STATED_CASE}}},
        },
        "study.cases.case4.source: the source 'tones_30' puts its lines at 30-31 Hz, none in the tracker's band "
        "study.tracking.min_freq_hz/max_freq_hz [3, 12] Hz",
    ),
    # the levels stage reads a helicopter run after levels.settle_s (the quick runs are 4 s)
    "levels-settle-leaves-too-little": (
        {"levels": {"settle_s": 3.0}},
        "levels.settle_s: (3.0 s) leaves 1 s of the helicopter runs (helicopter.solver.duration_s = 4.0 s)",
    ),
    "levels-orders-not-distinct": ({"levels": {"orders": [1, 1]}}, "levels.orders: must be distinct integers"),
    "payload-longer-than-the-study": (
        {"payload": {"duration_s": 3.0}},
        "payload.duration_s: (3.0 s) must be at most study.duration_s (2.0 s)",
    ),
    "payload-too-short-for-vibe": (
        {"payload": {"duration_s": 1.5}},
        "payload.duration_s: (1.5 s) must exceed 1.59 s for payload.sources[0] 'multirotor_30'",
    ),
    "payload-wire-rope-not-dissipative": (
        {"payload": {"wire_rope": {"beta_share": 0.4}}},
        "payload.wire_rope.beta_share: must lie in [0.5, 1] (gamma <= beta: dissipative), got 0.4",
    ),
    "payload-wire-rope-axis": (
        {"payload": {"wire_rope": {"axes": ["x", "x"]}}},
        "payload.wire_rope.axes: must be distinct names of ['x', 'y', 'z'], got ['x', 'x']",
    ),
    "payload-anfis-reference-beyond-the-table": (
        {"payload": {"anfis": {"freq_hz": {"start": 1.0, "stop": 120.0, "num": 9, "spacing": "log"}}}},
        "payload.anfis.freq_hz: must lie within payload.table.freq_hz's [2, 120] Hz, got 1-120 Hz",
    ),
    "payload-anfis-fewer-rows-than-folds": (
        {
            "payload": {
                "anfis": {"freq_hz": {"start": 7.0, "stop": 7.0, "num": 1}},
                "table": {"stiffness_n_m": {"values": [500.0]}},
            }
        },
        "payload.anfis.freq_hz: the payload ANFIS's 1 x 1 x 1 = 1 reference cells (payload.anfis.freq_hz per DOF, "
        "payload.table.stiffness_n_m) give 0 training rows, fewer than anfis.selection.folds (3)",
    ),
    "benchmark-payload-unknown-source": (
        {"benchmark": {"payload": {"sources": ["nowhere"]}}},
        "benchmark.payload.sources[0]: 'nowhere' is not a stated source",
    ),
    "benchmark-payload-scenarios-within-the-settling": (
        {"benchmark": {"duration_s": 0.5}},  # quick: payload.settle_s 0.5 s
        "benchmark.duration_s: (0.5 s) must exceed payload.settle_s (0.5 s) with benchmark.payload.enabled",
    ),
    "payload-unknown-source": (
        {"payload": {"sources": ["nowhere"]}},
        "payload.sources[0]: 'nowhere' is not a name of the sources section",
    ),
    "freq-above-nyquist": (
        {"reference_table": {"freq_y_hz": {"start": 4.0, "stop": 200.0}}},
        "reference_table.freq_y_hz: 200 Hz must stay below 0.25 x the Nyquist frequency",
    ),
    "response-above-nyquist": (
        {"platform": {"response": {"freq_z_hz": 40.0}}},
        "platform.response.freq_z_hz: 40 Hz must stay below",
    ),
    "tracking-band-reversed": (
        {"study": {"tracking": {"min_freq_hz": 12.0, "max_freq_hz": 3.0}}},
        "study.tracking.max_freq_hz: the band [12.0, 3.0] Hz is empty",
    ),
    "duplicated-study-stiffness": (
        {"study": {"stiffness_n_m": [10.0, 10.0]}},
        "study.stiffness_n_m: values must be unique",
    ),
    "damper-bounds-reversed": (
        {"platform": {"isolator": {"damping_min_n_s_m": 50.0, "damping_max_n_s_m": 5.0}}},
        "platform.isolator.damping_max_n_s_m: (5.0) must be >=",
    ),
    "grid-window-longer-than-run": (
        {"reference_table": {"windows_s": {"transient": [0.0, 19.0]}}},
        "reference_table.windows_s.transient: need [start, end] with 0 <= start < end <= duration_s (1.5 s)",
    ),
    "update-period-not-a-multiple": (
        {"platform": {"isolator": {"update_period_s": 0.5003}}},
        "platform.isolator.update_period_s: (0.5003 s) must be a whole multiple",
    ),
    "duplicated-grid-values": (
        {"reference_table": {"stiffness_n_m": {"values": [10.0, 10.0]}}},
        "reference_table.stiffness_n_m: values must be strictly increasing",
    ),
    "passive-outside-bounds": (
        {"study": {"passive_damping_n_s_m": 500.0}},
        "study.passive_damping_n_s_m: (500.0) must lie within the damper bounds",
    ),
    "early-window-after-run": ({"study": {"early_s": 3.0}}, "study.early_s: (3.0 s) must lie inside study.duration_s"),
    "unknown-strategy": ({"study": {"strategies": ["passive", "telepathy"]}}, "study.strategies: unknown strategy"),
    "unknown-controller": (
        {"benchmark": {"controllers": ["rigid", "telepathy"]}},
        "benchmark.controllers: unknown strategy ['telepathy']",
    ),
    "missing-plugin-file": ({"plugins": ["nowhere/laws.py"]}, "plugins: no file 'nowhere/laws.py'"),
    "plugin-not-python": ({"plugins": ["laws.txt"]}, "plugins.0: 'laws.txt' does not match"),
    "grid-over-budget": (
        {"reference_table": {"freq_y_hz": {"num": 1000}, "freq_z_hz": {"num": 1000}, "damping_n_s_m": {"num": 1000}}},
        "budget.max_cpu_hours: the run is estimated at 55.6 CPU hours (grid 2,000,000,000 points",
    ),
    "budget-not-positive": ({"budget": {"max_cpu_hours": 0.0}}, "budget.max_cpu_hours: must be > 0"),
    "figure-case-unknown": ({"study": {"figures": {"case_1": "case9"}}}, "study.figures.case_1: 'case9' is not a case"),
    "flight-case-in-vacuum": (
        {"helicopter": {"aerodynamics": {"inflow": "none"}}},
        "study.cases.case3.run: 'hover' is a flight run: it needs helicopter.aerodynamics.inflow uniform or",
    ),
    "flight-without-tail-rotor": (
        {"helicopter": {"tail_rotor": {"omega_running_rad_s": 0.0}}},
        "study.cases.case3.run: 'hover' is a flight run: it needs a turning tail rotor",
    ),
    "position-hold-faster-than-attitude": (
        {"helicopter": {"flight": {"hold": {"position_bandwidth_hz": 0.5}}}},
        "helicopter.flight.hold.position_bandwidth_hz: must be below bandwidth_hz",
    ),
    # a bad value in every section
    "helicopter.fuselage": (
        {"helicopter": {"fuselage": {"mass_kg": -1.0}}},
        "helicopter.fuselage.mass_kg: must be > 0",
    ),
    "helicopter.main_rotor": (
        {"helicopter": {"main_rotor": {"n_blades": 1}}},
        "helicopter.main_rotor.n_blades: must be >= 2, got 1",
    ),
    "helicopter.solver": ({"helicopter": {"solver": {"step_s": -0.001}}}, "helicopter.solver.step_s: must be > 0"),
    "helicopter.imbalance": (
        {"helicopter": {"imbalance": {"blade": 9}}},
        "helicopter.imbalance.blade: must lie in [0, 3] (helicopter.main_rotor.n_blades = 4), got 9",
    ),
    "platform.structure": (
        {"platform": {"structure": {"camera_mass_kg": 0.0}}},
        "platform.structure.camera_mass_kg: must be > 0",
    ),
    "platform.structure.modes": (
        {"platform": {"structure": {"natural_frequencies_hz": [6.7, 6.7, 4.5]}}},
        "platform.structure.natural_frequencies_hz: must be distinct",
    ),
    "platform.solver": ({"platform": {"solver": {"time_step_s": 0.0}}}, "platform.solver.time_step_s: must be > 0"),
    "platform.response": (
        {"platform": {"response": {"amplitude_m": -1.0}}},
        "platform.response.amplitude_m: must be > 0",
    ),
    "platform.backend": ({"platform": {"backend": "analog"}}, "platform.backend: must be one of ['exudyn', 'linear']"),
    "reference_table": (
        {"reference_table": {"flat_tolerance": -0.1}},
        "reference_table.flat_tolerance: must be >= 0, got -0.1",
    ),
    "reference_table.n_chunks": ({"reference_table": {"n_chunks": 0}}, "reference_table.n_chunks: must be >= 1, got 0"),
    "reference_table.n_chunks-float": (
        {"reference_table": {"n_chunks": 3.0}},
        "reference_table.n_chunks: expected an integer, got 3.0",
    ),
    "anfis": ({"anfis": {"train_fraction": 1.5}}, "anfis.train_fraction: must lie in (0, 1), got 1.5"),
    "anfis.epochs-float": ({"anfis": {"epochs": 50.0}}, "anfis.epochs: expected an integer, got 50.0"),
    "anfis.selection": ({"anfis": {"selection": {"folds": 1}}}, "anfis.selection.folds: must be >= 2, got 1"),
    "study": ({"study": {"duration_s": -2.0}}, "study.duration_s: must be > 0"),
    "study.tracking": ({"study": {"tracking": {"method": "music"}}}, "study.tracking.method: must be one of"),
    "study.cases": (
        {"study": {"cases": {"case1": {"amplitude_reading": "rms"}}}},
        "study.cases.case1.amplitude_reading: must be one of ['peak', 'dominant'], got 'rms'",
    ),
    "study.cases-two-sources": (
        {"study": {"cases": {"case1": {"flight_log": "quadrotor"}}}},
        "study.cases.case1: needs exactly one source: run (a helicopter run), flight_log or source",
    ),
    "study.cases-unknown-log": (
        {"study": {"cases": {"case1": {"run": None, "mount": None, "flight_log": "octocopter"}}}},
        "study.cases.case1.flight_log: 'octocopter' is not a name of flight_logs (['quadrotor', 'vtol'])",
    ),
    "study.cases-measured-with-amplitude": (
        {"study": {"cases": {"case1": {"amplitude_scaling": "measured"}}}},
        "study.cases.case1.amplitude_m: is not used with amplitude_scaling: measured (set it to null), got 0.0013",
    ),
    "study.cases-log-with-mount": (
        {"study": {"cases": {"case1": {"run": None, "flight_log": "quadrotor"}}}},
        "study.cases.case1.mount: a flight_log case is at its log's mount (flight_logs.NAME)",
    ),
    "flight_logs-band": (
        {"flight_logs": {"quadrotor": {"band_hz": [47.0, 20.0]}}},
        "flight_logs.quadrotor.band_hz: needs 0 < low < high, got [47.0, 20.0]",
    ),
    "benchmark.flight_logs-unknown": (
        {"benchmark": {"flight_logs": [{"name": "hop", "flight_log": "octo"}]}},
        "benchmark.flight_logs.hop.flight_log: 'octo' is not a name of flight_logs",
    ),
    "platform.stroke": (
        {"platform": {"stroke": {"weight_support": "magnets"}}},
        "platform.stroke.weight_support: must be one of ['spring', 'preloaded'], got 'magnets'",
    ),
    "camera": ({"camera": {"exposure_s": -1.0}}, "camera.exposure_s must be a finite number > 0"),
    "camera.image": ({"camera": {"image_width_px": 0}}, "camera.image_width_px must be a finite number > 0"),
    "benchmark": ({"benchmark": {"damper_lag_s": 0.0}}, "benchmark.damper_lag_s: must be > 0"),
    "benchmark.split": (
        {"benchmark": {"split": {"tuning_fraction": 1.0}}},
        "benchmark.split.tuning_fraction: must lie in (0, 1)",
    ),
    "budget": ({"budget": {"helicopter_cpu_per_simulated_s": -1.0}}, "budget.helicopter_cpu_per_simulated_s"),
    "helicopter.aerodynamics": (
        {"helicopter": {"aerodynamics": {"inflow": "vortex"}}},
        "helicopter.aerodynamics.inflow: must be one of ['none', 'uniform', 'pitt_peters']",
    ),
    "helicopter.aerodynamics.main_blade": (
        {"helicopter": {"aerodynamics": {"main_blade": {"chord_m": 0.0}}}},
        "helicopter.aerodynamics.main_blade.chord_m: must be > 0",
    ),
    "helicopter.flight": (
        {"helicopter": {"flight": {"forward_advance_ratio": 0.6}}},
        "helicopter.flight.forward_advance_ratio: must lie in (0, 0.25]",
    ),
    "helicopter.flight.trim": (
        {"helicopter": {"flight": {"trim": {"max_iterations": 0}}}},
        "helicopter.flight.trim.max_iterations: must be >= 1",
    ),
    "helicopter.sensitivity.flight": (
        {"helicopter": {"sensitivity": {"flight": "orbit"}}},
        "helicopter.sensitivity.flight: must be one of ['vacuum', 'hover', 'forward']",
    ),
    "benchmark.helicopter.flight": (
        {"benchmark": {"helicopter": {"flight": ["hover", "orbit"]}}},
        "benchmark.helicopter.flight[1]: must be one of ['vacuum', 'hover', 'forward']",
    ),
}

UNKNOWN = {
    "top": ({"camerra": {"x": 1}}, "camerra: unknown key; did you mean camera?"),
    "helicopter": ({"helicopter": {"rotor_count": 2}}, "helicopter.rotor_count: unknown key"),
    "platform": (
        {"platform": {"isolator": {"stiffnes_n_m": 5.0}}},
        "platform.isolator.stiffnes_n_m: unknown key; did you mean platform.isolator.stiffness_n_m?",
    ),
    "reference_table": (
        {"reference_table": {"window_s": [0.0, 1.0]}},
        "reference_table.window_s: unknown key; did you mean reference_table.windows_s?",
    ),
    "anfis": ({"anfis": {"epoch": 3}}, "anfis.epoch: unknown key; did you mean anfis.epochs?"),
    "study": ({"study": {"tracking": {"windw_s": 1.0}}}, "study.tracking.windw_s: unknown key; did you mean"),
    "camera": ({"camera": {"iso": 100}}, "camera.iso: unknown key"),
    "benchmark": ({"benchmark": {"tunning": {}}}, "benchmark.tunning: unknown key; did you mean benchmark.tuning?"),
}


def _merged(override: dict) -> dict:
    return deep_update(load_config("quick.yaml"), override)


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_bad_value_is_refused_naming_the_key_and_the_rule(case):
    override, message = BAD[case]
    with pytest.raises(ValueError) as error:
        checks.validate(_merged(override))
    assert message in str(error.value), str(error.value)
    assert len(str(error.value).splitlines()) <= 3, str(error.value)  # a few lines, not a schema dump


@pytest.mark.parametrize("section", sorted(UNKNOWN))
def test_an_unknown_key_in_every_section_is_refused_with_the_nearest_valid_key(section):
    override, message = UNKNOWN[section]
    with pytest.raises(ConfigError) as error:
        checks.validate(_merged(override))
    assert message in str(error.value), str(error.value)


@pytest.mark.parametrize(
    "path, old, new",
    [
        (["helicopter", "fuselage"], "mass", "helicopter.fuselage.mass_kg"),
        (["helicopter", "solver"], "duration", "helicopter.solver.duration_s"),
        (
            ["helicopter", "sensitivity", "parameters"],
            "lag_damping",
            "helicopter.sensitivity.parameters.lag_damping_n_m_s_rad",
        ),
        (["reference_table"], "windows", "reference_table.windows_s"),
        (["study", "cases", "case1"], "amplitude", "study.cases.case1.amplitude_m"),
    ],
)
def test_an_old_key_name_is_refused_naming_its_new_name(path, old, new):
    config = load_config("quick.yaml")
    section = config
    for key in path:
        section = section[key]
    section[old] = section.pop(new.rsplit(".", 1)[1])
    with pytest.raises(ConfigError, match=re.escape(f"{'.'.join(path)}.{old}: renamed to {new}")):
        checks.validate(config)


@pytest.mark.parametrize("names", [[], ["quick.yaml"], ["multirotor.yaml"], ["quick.yaml", "multirotor.yaml"]])
def test_every_shipped_config_loads_through_the_one_config_layer(names):
    mapping = load_config()
    for name in names:
        mapping = deep_update(mapping, yaml.safe_load((ROOT / "config" / name).read_text()))
    typed, estimate = checks.validate(mapping)
    assert isinstance(typed, Config) and estimate["cpu_s"] > 0


def _typed_keys(cls, prefix: str = "", mappings: set | None = None) -> set[str]:
    """Every dotted config key of section class `cls`: NAME for a name in a mapping of sections, [] for an entry of
    a list of sections; `mappings` collects the keys that are mappings of plain values (names the schema lists)."""
    out = set()
    hints = typing.get_type_hints(cls)
    for f in dataclasses.fields(cls):
        if not f.metadata.get("config", True):
            continue
        key = prefix + key_of(cls, f.name)
        out.add(key)
        kind = hints[f.name]
        if typing.get_origin(kind) in (typing.Union, types.UnionType):
            kind = next(a for a in typing.get_args(kind) if a is not type(None))
        args = typing.get_args(kind)
        if typing.get_origin(kind) is dict and dataclasses.is_dataclass(args[1]):
            out |= {key + ".NAME"} | _typed_keys(args[1], key + ".NAME.", mappings)
        elif typing.get_origin(kind) is dict and mappings is not None:
            mappings.add(key)
        elif typing.get_origin(kind) is tuple and dataclasses.is_dataclass(args[0]):
            out |= {key + "[]"} | _typed_keys(args[0], key + "[].", mappings)
        elif dataclasses.is_dataclass(kind):
            out |= _typed_keys(kind, key + ".", mappings)
    return out


def _schema() -> dict:
    return yaml.safe_load((ROOT / "workflow" / "schemas" / "config.schema.yaml").read_text())


def test_the_config_reference_is_generated_from_the_schema_and_current():
    readme = (ROOT / "config" / "README.md").read_text()
    assert readme == config_docs.update_readme(readme, _schema()), "run: python -m uavdamp.config.docs"


def test_every_typed_key_is_in_the_schema_and_documented_and_no_other():
    """The typed sections and the schema name the same keys; the reference documents each one."""
    documented = set(re.findall(r"^\| `([^`]+)` \|", (ROOT / "config" / "README.md").read_text(), re.MULTILINE))
    mappings: set = set()
    typed = {k for k in _typed_keys(Config, "", mappings) if "." in k}  # the sections head their own tables
    assert sorted(typed - documented) == [], "typed keys missing from the schema (and so from config/README.md)"
    stale = sorted(k for k in documented - typed if k.rsplit(".", 1)[0] not in mappings)
    assert stale == [], "schema keys no section class reads"


def test_every_renamed_key_names_a_key_that_exists():
    documented = (ROOT / "config" / "README.md").read_text()
    keys = _typed_keys(Config)
    for old, new in RENAMED.items():
        key = f"{old.rsplit('.', 1)[0]}.{new}".replace("*", "NAME")
        assert key in keys or f"`{key}`" in documented, (old, new)


def test_extrapolation_allowed_is_returned_as_the_runs_warning_and_refused_otherwise():
    """A K or a tracker band beyond the reference table: refused unless SECTION.allow_extrapolation,
    then the warning the run records; the shipped config lies inside, so nothing to record."""
    assert checks.extrapolation(load(load_config())) == {"study": [], "benchmark": []}
    quick = load_config("quick.yaml")
    band = (
        "study.tracking.min_freq_hz/max_freq_hz: the tracker band [3, 12] Hz lies outside [4, 10] Hz, the "
        "frequencies the ANFIS is trained on (reference_table.freq_y_hz and freq_z_hz)"
    )
    assert checks.extrapolation(load(quick)) == {"study": [band], "benchmark": [band]}
    inside = deep_update(quick, {"study": {"tracking": {"min_freq_hz": 4.0, "max_freq_hz": 10.0}}})
    kilo = deep_update(inside, {"benchmark": {"stiffness_n_m": [10.0, 2000.0]}})
    found = checks.extrapolation(load(kilo))
    assert found["study"] == [] and len(found["benchmark"]) == 1
    assert found["benchmark"][0].startswith("benchmark.stiffness_n_m: [2000.0] N m-1 lies outside [10, 1000] N m-1")
    refused = deep_update(kilo, {"benchmark": {"allow_extrapolation": False}})
    with pytest.raises(ConfigError, match=r"^benchmark.stiffness_n_m: \[2000.0\] .* benchmark.allow_extrapolation"):
        checks.extrapolation(load(refused))


def test_rotor_physics_bounds_are_refused_naming_key_value_quantity_and_bound():
    """Schema-valid values beyond the rotor's physics, refused before any job. Expected numbers from closed forms
    computed here: tip Mach Omega R (1 + mu) / 340.3 m s-1, the hover thrust of blades stalled everywhere
    N rho c Omega^2 a alpha_s (R^3 - r_0^3) / 6.

    seen failing on the previous main: all three passed the checks (omega 500 rad/s then ended in an Exudyn
    SolverError traceback at the flight job; mass 1e5 kg and mu 0.4 in an unconverged trim flown as if trimmed)."""
    quick = load_config("quick.yaml")
    main, aero = quick["helicopter"]["main_rotor"], quick["helicopter"]["aerodynamics"]
    radius = main["hinge_offset_m"] + main["blade_length_m"]
    mu = quick["helicopter"]["flight"]["forward_advance_ratio"]
    mach = 500.0 * radius * (1 + mu) / 340.3
    with pytest.raises(ConfigError) as error:
        checks.validate(_merged({"helicopter": {"main_rotor": {"omega_rad_s": 500.0}}}))
    text = str(error.value)
    assert text.startswith("helicopter.main_rotor.omega_rad_s: 500 rad s-1") and "Mach" in text and "0.95" in text
    assert f"= {mach:.3g}," in text

    blade = aero["main_blade"]
    omega = main["omega_rad_s"]
    lift = blade["lift_slope_per_rad"] * blade["stall_angle_rad"]
    r_0 = main["hinge_offset_m"] + blade["root_cutout_m"]
    most = main["n_blades"] * aero["air_density_kg_m3"] * blade["chord_m"] * omega**2 * lift * (radius**3 - r_0**3) / 6
    with pytest.raises(ConfigError) as error:
        checks.validate(_merged({"helicopter": {"fuselage": {"mass_kg": 1.0e5}}}))
    text = str(error.value)
    assert text.startswith("helicopter.fuselage.mass_kg: 100000 kg") and "disc loading" in text
    assert f"= {most:.4g} N" in text

    with pytest.raises(ConfigError, match=r"^helicopter.flight.forward_advance_ratio: .* got 0.4"):
        checks.validate(_merged({"helicopter": {"flight": {"forward_advance_ratio": 0.4}}}))


def test_a_yaml_11_string_number_is_refused_saying_why_and_how_to_write_it():
    """PyYAML (YAML 1.1, Snakemake's loader) reads 1.0e9 as a string; the refusal says so and gives the spelling it
    reads as a float (checked here by loading that spelling with PyYAML).

    seen failing on the previous main: "expected a finite number, got '1.0e9'" without the reason."""
    text = "platform:\n  isolator:\n    stiffness_n_m: 1.0e9\n"
    loaded = yaml.safe_load(text)
    assert loaded["platform"]["isolator"]["stiffness_n_m"] == "1.0e9"  # the premise: YAML 1.1 gives a string
    with pytest.raises(ConfigError) as error:
        checks.validate(_merged(loaded))
    message = str(error.value)
    assert "YAML 1.1 reads 1.0e9 as a string" in message and "write 1.0e+9 or 1000000000.0" in message
    assert yaml.safe_load("x: 1.0e+9")["x"] == 1.0e9 == float("1000000000.0")


def test_the_platform_stiffness_outside_the_tables_range_gets_the_unit_hint():
    """platform.isolator.stiffness_n_m 0.01 (10 N/m written in kN/m) is reported with the table's range and the kN
    hint, as study.stiffness_n_m is; a value inside the range gets nothing.

    seen failing on the previous main: 0.01 passed every check without a word (no stiffness_warnings)."""
    quick = load_config("quick.yaml")
    low, high = (
        min(quick["reference_table"]["stiffness_n_m"]["values"]),
        max(quick["reference_table"]["stiffness_n_m"]["values"]),
    )
    assert not checks.stiffness_warnings(load(quick))
    (warning,) = checks.stiffness_warnings(load(_merged({"platform": {"isolator": {"stiffness_n_m": 0.01}}})))
    assert warning.startswith(f"platform.isolator.stiffness_n_m: 0.01 N m-1 lies outside [{low:g}, {high:g}] N m-1")
    assert warning.endswith("a value in kN m-1? 0.01 kN m-1 = 10 N m-1")
