"""Checks that span config sections, run right after the typed load and before any job (the Snakefile calls them).

Each section class checks its own values (`uavdamp.config.load`); these check values against each other: every
ConfigError names the key and the rule it breaks.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from uavdamp import plugins
from uavdamp.anfis.params import split
from uavdamp.benchmark.scenarios import scenario_specs
from uavdamp.config import budget, flight_logs
from uavdamp.config.load import Config, load
from uavdamp.contract import is_multiple
from uavdamp.helicopter import params as P
from uavdamp.platform import PlatformParams, design_stiffness
from uavdamp.settings import ConfigError, require
from uavdamp.sources.levels import vibe_settle_s
from uavdamp.study import strategies
from uavdamp.workflow import check_schema

SCHEMA = Path(__file__).resolve().parents[3] / "workflow" / "schemas" / "config.schema.yaml"


def validate(mapping: dict, schema_path=SCHEMA, benchmark: bool = False) -> tuple[Config, dict]:
    """What the Snakefile does before any job: every key typed (`uavdamp.config.load`), every value against the
    schema's ranges (`uavdamp.workflow.check_schema`), values against each other and the budget (`check_config`).
    Returns the typed config and the cost estimate (with `benchmark`, the benchmark target's runs counted);
    ConfigError names the first bad key."""
    typed = load(mapping)
    check_schema(mapping, schema_path)
    return typed, check_config(typed, benchmark)


def check_names(config: Config) -> None:
    """Load the plug-ins (``plugins``, `uavdamp.plugins`), then every name of study.strategies and
    benchmark.controllers must be registered (`uavdamp.study.strategies.REGISTRY`: the one list for both)."""
    try:
        plugins.load(config.plugins)
    except (FileNotFoundError, plugins.PluginError) as error:
        raise ConfigError(str(error)) from error.__cause__
    known = sorted(strategies.REGISTRY)
    for key, names in (
        ("study.strategies", config.study.strategies),
        ("benchmark.controllers", config.benchmark.controllers),
    ):
        unknown = sorted(set(names) - set(known))
        require(not unknown, key, f"unknown strategy {unknown} (known: {known}; a plug-in adds its own: plugins)")


def check_config(config: Config, benchmark: bool = False) -> dict:
    """Raise ConfigError naming the first key that breaks a rule across sections (see the module docstring) or a
    run estimated above the budget; return the estimate (`uavdamp.config.budget`)."""
    check_names(config)
    extrapolation(config)
    _check_platform(config.platform)
    _check_frequencies(config)
    _check_benchmark_frequencies(config)
    _check_run_length(config)
    _check_folds(config)
    _check_study(config)
    _check_payload(config)
    _check_benchmark_payload(config)
    _check_levels(config)
    _check_source_bands(config)
    _check_mounts(config)
    _check_scaling(config)
    flight_logs.check(config, benchmark)
    _check_flights(config)
    _check_rotor_physics(config)
    grid = config.reference_table
    damping, bounds = grid.damping.array(), (config.platform.damping_min, config.platform.damping_max)
    require(
        bounds[0] <= damping.min() and damping.max() <= bounds[1],
        "reference_table.damping_n_s_m",
        f"[{damping.min()}, {damping.max()}] N s m-1 lies outside the damper bounds platform.isolator."
        f"damping_min_n_s_m/damping_max_n_s_m {list(bounds)}",
    )
    return budget.check(config, benchmark)


def _check_platform(platform: PlatformParams) -> None:
    """The designed stiffnesses exist (the targets can be met with these inertias) and the update period fits."""
    try:
        design_stiffness(platform.structure)
    except ValueError as error:
        raise type(error)(f"platform.structure.natural_frequencies_hz: {error}") from None
    require(
        is_multiple(platform.update_period, platform.time_step),
        "platform.isolator.update_period_s",
        f"({platform.update_period} s) must be a whole multiple of platform.solver.time_step_s "
        f"({platform.time_step} s)",
    )


def _check_frequencies(config: Config) -> None:
    """Every input frequency below the configured fraction of the platform solver's Nyquist frequency."""
    platform = config.platform
    limit, rule = _platform_rule(config)
    grid = config.reference_table
    for key, axis in (("reference_table.freq_y_hz", grid.freq_y), ("reference_table.freq_z_hz", grid.freq_z)):
        top = axis.array().max()
        require(top < limit, key, f"{top:g} Hz {rule}")
    for key in ("freq_y_hz", "freq_z_hz"):
        value = getattr(platform.response, key)
        require(value < limit, f"platform.response.{key}", f"{value:g} Hz {rule}")
    track = config.study.tracking
    require(track.max_freq_hz < limit, "study.tracking.max_freq_hz", f"{track.max_freq_hz:g} Hz {rule}")
    output_step = config.helicopter.solver.output_step
    require(
        track.max_freq_hz < 0.5 / output_step,
        "study.tracking.max_freq_hz",
        f"must stay below the Nyquist frequency of helicopter.solver.output_step_s ({0.5 / output_step:g} Hz)",
    )


def _frequency_rule(config: Config) -> tuple[float, str]:
    """(Hz, text): the limit every benchmark input frequency stays below, a fraction of the Nyquist of the coarser
    of the platform solver's step (the inputs' sampling) and benchmark.time_step_s (the benchmark plants' step)."""
    platform = config.platform
    h, fraction, key = platform.time_step, platform.solver.max_frequency_fraction, "platform.solver.time_step_s"
    if config.benchmark.time_step is not None and config.benchmark.time_step > h:
        h, key = config.benchmark.time_step, "benchmark.time_step_s"
    limit = fraction * 0.5 / h
    return limit, (
        f"must stay below platform.solver.max_frequency_fraction {fraction} x the Nyquist frequency 1/(2 x "
        f"{key}) of {h} s, i.e. {limit:g} Hz"
    )


def _check_benchmark_frequencies(config: Config) -> None:
    """The benchmark's input frequencies (synthetic sweeps, tones, random bands, the helicopter band and high-pass)
    below the platform solver's limit (`_frequency_rule`), named by key before scipy sees them."""
    limit, rule = _frequency_rule(config)
    bench = config.benchmark
    named = {"benchmark.band_hz": bench.band_hz, "benchmark.highpass_hz": (bench.highpass_hz,)}
    for k, synthetic in enumerate(bench.synthetic):
        for key in ("freq_hz", "freq_y_hz", "freq_z_hz", "band_hz"):
            named[f"benchmark.synthetic[{k}] ({synthetic.name}).{key}"] = getattr(synthetic, key) or ()
    for key, values in named.items():
        top = max(values, default=0.0)
        require(top < limit, key, f"{top:g} Hz {rule}")


def _check_run_length(config: Config) -> None:
    """A case taking a helicopter run's motion needs study.duration_s of it (helicopter.solver.duration_s)."""
    recorded = config.helicopter.solver.duration
    for name, case in config.study.cases.items():
        require(
            not case.run or config.study.duration_s <= recorded + 1e-9,
            "study.duration_s",
            f"({config.study.duration_s} s) is longer than the helicopter run {case.run!r} of study.cases.{name} "
            f"(helicopter.solver.duration_s = {recorded} s)",
        )


def _check_folds(config: Config) -> None:
    """anfis.selection.folds at most the training rows the reference table can give (every (f_y, f_z, K) point a
    row, anfis.train_fraction of them for training: `uavdamp.anfis.params.split`; failed points only remove), and
    the payload ANFIS's reference likewise (every (f_a, f_b, K) cell a row: `uavdamp.study.payload_anfis`)."""

    grid, anfis = config.reference_table, config.anfis
    shape = [axis.array().size for axis in (grid.freq_y, grid.freq_z, grid.stiffness)]
    rows, train = _training_rows(shape, anfis)
    require(
        anfis.selection.folds <= train,
        "anfis.selection.folds",
        f"{anfis.selection.folds} folds need as many training rows; the reference table gives at most "
        f"{' x '.join(map(str, shape))} = {rows} rows (reference_table.freq_y_hz, freq_z_hz, stiffness_n_m), "
        f"{train} of them training rows (anfis.train_fraction {anfis.train_fraction})",
    )
    payload = config.payload
    shape = [payload.anfis.freq.array().size] * 2 + [payload.table.stiffness.array().size]
    rows, train = _training_rows(shape, anfis)
    require(
        anfis.selection.folds <= train,
        "payload.anfis.freq_hz",
        f"the payload ANFIS's {' x '.join(map(str, shape))} = {rows} reference cells (payload.anfis.freq_hz per DOF, "
        f"payload.table.stiffness_n_m) give {train} training rows, fewer than anfis.selection.folds "
        f"({anfis.selection.folds})",
    )


def _training_rows(shape: list[int], anfis) -> tuple[int, int]:
    """(rows, training rows) of a reference of `shape` cells under the anfis section's split."""
    rows = int(np.prod(shape))
    return rows, int(split(rows, anfis.train_fraction, anfis.seed).sum()) if rows > 1 else 0


def _check_mounts(config: Config) -> None:
    """Every mount a case or a benchmark scenario names is a mount point of the helicopter, every flight log a
    case names is configured."""
    points, logs = list(config.helicopter.mount_points), sorted(config.flight_logs)
    used = {f"study.cases.{name}.flight_log": case.flight_log for name, case in config.study.cases.items()}
    used |= {f"benchmark.flight_logs.{s.name}.flight_log": s.flight_log for s in config.benchmark.flight_logs}
    for key, log in used.items():
        require(not log or log in config.flight_logs, key, f"{log!r} is not a name of flight_logs ({logs})")
    known = sorted(config.sources)
    stated = {f"study.cases.{name}.source": case.stated for name, case in config.study.cases.items() if case.stated}
    stated |= {f"benchmark.sources[{k}]": name for k, name in enumerate(config.benchmark.sources)}
    stated |= {f"payload.sources[{k}]": name for k, name in enumerate(config.payload.sources)}
    for key, name in stated.items():
        require(name in config.sources, key, f"{name!r} is not a name of the sources section ({known})")
    named = {f"study.cases.{name}.mount": case.mount for name, case in config.study.cases.items() if case.run}
    named |= {f"benchmark.helicopter.mount[{k}]": m for k, m in enumerate(config.benchmark.helicopter.mount)}
    for key, mount in named.items():
        require(mount in points, key, f"{mount!r} is not a mount point of helicopter.mount_points_m ({points})")


PAPER_RUNS = ("balanced", "imbalanced", "both_rotors")  # the paper's vacuum runs: its per-axis scaled cases


def _check_scaling(config: Config) -> None:
    """A case keeps the ratios between the axes of its source: per_axis scaling (each axis to the amplitude) is the
    paper's construct and stays with the paper's vacuum runs; on a flight run it would invent motion (the trimmed
    hover's vertical line is 46 times below its fore-aft one; per_axis multiplies it by about 4)."""
    for name, case in config.study.cases.items():
        if case.amplitude_scaling != "per_axis" or case.run in PAPER_RUNS:
            continue
        require(
            False,
            f"study.cases.{name}.amplitude_scaling",
            f"per_axis would change the ratios between the axes of the {case.source} (it is the paper's construct, "
            f"kept for its vacuum runs {list(PAPER_RUNS)}): use common (one factor, the ratios kept) or measured",
        )


def _check_flights(config: Config) -> None:
    """Flight runs (hover, forward) named anywhere need aerodynamics (inflow other than none) and a tail rotor."""
    heli = config.helicopter
    named = {f"study.cases.{name}.run": case.run for name, case in config.study.cases.items()}
    named |= {f"benchmark.helicopter.flight[{k}]": f for k, f in enumerate(config.benchmark.helicopter.flight)}
    named["helicopter.sensitivity.flight"] = heli.sensitivity.flight
    for key, run in named.items():
        if run not in ("hover", "forward"):
            continue
        require(
            heli.aerodynamics.enabled,
            key,
            f"{run!r} is a flight run: it needs helicopter.aerodynamics.inflow uniform or pitt_peters, not none",
        )
        require(
            heli.tail_rotor.omega_running_rad_s > 0,
            key,
            f"{run!r} is a flight run: it needs a turning tail rotor (helicopter.tail_rotor.omega_running_rad_s > 0)",
        )


def _check_rotor_physics(config: Config) -> None:
    """With aerodynamics on (inflow other than none), the bounds of the rotor's physics: the advancing-tip Mach
    number of both rotors at the fastest rotor speed any run uses (the benchmark's rotor_speed_ratio included) and
    the forward run's advance ratio below MAX_TIP_MACH; the weight below the most thrust the main blades' elements
    can make in hover (disc loading W / A below rho (Omega R)^2 sigma a alpha_stall / 6)."""
    heli = config.helicopter
    if not heli.aerodynamics.enabled:
        return
    main, tail, aero = heli.main_rotor, heli.tail_rotor, heli.aerodynamics
    bench = config.benchmark.helicopter
    flies = any(f in ("hover", "forward") for f in bench.flight)
    ratio = max((1.0, *bench.rotor_speed_ratio)) if flies else 1.0
    scaled = f" x benchmark.helicopter.rotor_speed_ratio {ratio:g}" if ratio > 1.0 else ""
    mu = heli.flight.forward_advance_ratio
    radius = main.hinge_offset + main.blade_length
    for key, omega, tip, advance in (
        ("main_rotor.omega_rad_s", main.omega_rad_s, radius, mu),
        ("tail_rotor.omega_running_rad_s", tail.omega_running_rad_s, tail.blade_length, 0.0),
    ):
        mach = P.tip_mach(omega * ratio, tip, advance)
        require(
            mach <= P.MAX_TIP_MACH,
            f"helicopter.{key}",
            f"{omega:g} rad s-1{scaled} gives an advancing-tip Mach number Omega R (1 + mu) / a = {omega * ratio:g} x "
            f"{tip:g} m x {1 + advance:g} / {P.SPEED_OF_SOUND:g} m s-1 = {mach:.3g}, above {P.MAX_TIP_MACH}: the "
            "blade sections are quasi-steady and incompressible (no Mach correction, no shock), so the loads and the "
            "solver's step are not meant for it",
        )
    weight = heli.total_mass() * heli.flight.gravity
    root = main.hinge_offset + aero.main_blade.root_cutout
    thrust = P.max_hover_thrust(aero.main_blade, main.n_blades, root, radius, main.omega_rad_s, aero.air_density)
    area = np.pi * radius**2
    require(
        weight < thrust,
        "helicopter.fuselage.mass_kg",
        f"{heli.fuselage.mass:g} kg makes a weight W = {weight:.4g} N (disc loading W / A = {weight / area:.4g} N m-2) "
        f"above the most the main rotor's blade elements can lift in hover, every section at its stall lift "
        f"coefficient a alpha_stall = {aero.main_blade.lift_slope * aero.main_blade.stall_angle:.3g}: "
        f"N rho c Omega^2 a alpha_stall (R^3 - r_0^3) / 6 = {thrust:.4g} N (disc loading {thrust / area:.4g} N m-2; "
        "helicopter.main_rotor.omega_rad_s, blade_length_m, aerodynamics.main_blade chord_m, lift_slope_per_rad, "
        "stall_angle_rad, air_density_kg_m3): no trim exists",
    )


def _check_source_bands(config: Config) -> None:
    """A stated source a study case or a benchmark scenario uses has its lines (`StatedSource.lines_hz`) below the
    platform solver's limit (the rule every input frequency keeps) and at least one inside the tracker's band: else
    the tracker would sit at its band's edge on every update, and the damping law would schedule on no line."""
    track = config.study.tracking
    band = f"study.tracking.min_freq_hz/max_freq_hz [{track.min_freq_hz:g}, {track.max_freq_hz:g}] Hz"
    users = {f"study.cases.{n}.source": c.stated for n, c in config.study.cases.items() if c.stated}
    users |= {f"benchmark.sources[{k}]": name for k, name in enumerate(config.benchmark.sources)}
    for key, name in users.items():
        if name not in config.sources:
            continue  # refused by check_names, naming the key
        lines = config.sources[name].lines_hz()
        span = f"the source {name!r} puts its lines at {lines.min():g}-{lines.max():g} Hz"
        limit, rule = _frequency_rule(config) if key.startswith("benchmark") else _platform_rule(config)
        require(lines.max() < limit, key, f"{span}: each {rule}")
        inside = (lines >= track.min_freq_hz) & (lines <= track.max_freq_hz)
        require(
            bool(np.any(inside)),
            key,
            f"{span}, none in the tracker's band {band}: the tracker would find none of them. Either set the "
            "tracker's band (and the reference table's) across them, or name a source whose lines lie in it",
        )


def _platform_rule(config: Config) -> tuple[float, str]:
    """(Hz, text): the limit every study input frequency stays below (`_check_frequencies`' rule)."""
    h, fraction = config.platform.time_step, config.platform.solver.max_frequency_fraction
    limit = fraction * 0.5 / h
    return limit, (
        f"must stay below {fraction} x the Nyquist frequency of platform.solver.time_step_s = {h} s, i.e. {limit:g} Hz"
    )


def _check_levels(config: Config) -> None:
    """The levels stage reads a helicopter run after levels.settle_s: what is left must hold VIBE's settling twice
    (`uavdamp.sources.levels.vibe_settle_s`)."""
    left = config.helicopter.solver.duration - config.levels.settle_s
    need = 2 * vibe_settle_s()
    require(
        left > need,
        "levels.settle_s",
        f"({config.levels.settle_s} s) leaves {left:g} s of the helicopter runs (helicopter.solver.duration_s = "
        f"{config.helicopter.solver.duration} s); their levels need more than {need:.2f} s (VIBE's settling twice)",
    )


def _check_payload(config: Config) -> None:
    """The payload stage reads the study's cases from their start: its runs are no longer than the study's."""
    require(
        config.payload.duration_s <= config.study.duration_s,
        "payload.duration_s",
        f"({config.payload.duration_s} s) must be at most study.duration_s ({config.study.duration_s} s): the "
        "study's cases are that long",
    )
    need = 2 * vibe_settle_s()  # a multirotor source is scaled to its VIBE, measured after the filter settles
    for k, name in enumerate(config.payload.sources):
        source = config.sources.get(name)
        require(
            source is None or source.kind != "multirotor" or config.payload.duration_s > need,
            "payload.duration_s",
            f"({config.payload.duration_s} s) must exceed {need:.2f} s for payload.sources[{k}] {name!r}: a "
            "multirotor source is scaled to its VIBE level, measured after the level's 2 Hz filter settles",
        )


def _check_benchmark_payload(config: Config) -> None:
    """The benchmark on the payload scores its runs after payload.settle_s, within each scenario's duration."""
    bench = config.benchmark
    require(
        not bench.payload.enabled or config.payload.settle_s < bench.duration_s,
        "benchmark.duration_s",
        f"({bench.duration_s} s) must exceed payload.settle_s ({config.payload.settle_s} s) with "
        "benchmark.payload.enabled: the payload runs are scored after it",
    )
    taken = set(scenario_specs(bench))
    need = 2 * vibe_settle_s()  # a multirotor source is scaled to its VIBE, measured after the filter settles
    for k, name in enumerate(bench.payload.sources):
        key = f"benchmark.payload.sources[{k}]"
        require(name in config.sources, key, f"{name!r} is not a stated source ({sorted(config.sources)})")
        require(name not in taken, key, f"{name!r} is the name of a benchmark scenario: a source needs its own")
        require(
            not bench.payload.enabled or config.sources[name].kind != "multirotor" or bench.duration_s > need,
            "benchmark.duration_s",
            f"({bench.duration_s} s) must exceed {need:.2f} s for {key} {name!r}: a multirotor source is scaled to "
            "its VIBE level, measured after the level's 2 Hz filter settles",
        )


def _check_study(config: Config) -> None:
    """The passive damper within the damper bounds."""
    study, platform = config.study, config.platform
    bounds = (platform.damping_min, platform.damping_max)
    require(
        bounds[0] <= study.passive_damping <= bounds[1],
        "study.passive_damping_n_s_m",
        f"({study.passive_damping}) must lie within the damper bounds {list(bounds)} N s m-1",
    )


def stiffness_warnings(config: Config) -> list[str]:
    """The unit hint for the N m-1 stiffness keys the ANFIS range check does not cover (platform.isolator.
    stiffness_n_m, the platform stage's K): a value outside reference_table.stiffness_n_m's range is reported,
    with "a value in kN m-1?" when a thousand times it lies inside. Warnings (the Snakefile prints them), not
    refusals: the platform stage runs any K > 0."""
    k = config.reference_table.stiffness.array()
    low, high = float(k.min()), float(k.max())
    warnings = []
    for key, value in (("platform.isolator.stiffness_n_m", config.platform.isolator.stiffness),):
        if low <= value <= high:
            continue
        kilo = value * 1000.0
        hint = f"; a value in kN m-1? {value:g} kN m-1 = {kilo:g} N m-1" if low <= kilo <= high else ""
        warnings.append(
            f"{key}: {value:g} N m-1 lies outside [{low:g}, {high:g}] N m-1, the stiffnesses of the reference table "
            f"(reference_table.stiffness_n_m){hint}"
        )
    return warnings


def extrapolation(config: Config) -> dict[str, list[str]]:
    """What lies outside the reference table the ANFIS is trained on, per section ("study", "benchmark"): a K of
    ``SECTION.stiffness_n_m`` outside reference_table.stiffness_n_m's range, the tracker band study.tracking
    [min_freq_hz, max_freq_hz] outside the range both reference_table.freq_y_hz and .freq_z_hz cover (the ANFIS
    clamps its inputs to its training range without a word). ConfigError naming the first unless
    ``SECTION.allow_extrapolation`` is true; returns the warnings the run records (empty lists when inside)."""
    grid = config.reference_table
    k = grid.stiffness.array()
    fy, fz = grid.freq_y.array(), grid.freq_z.array()
    low, high = max(fy.min(), fz.min()), min(fy.max(), fz.max())
    track = config.study.tracking
    band = []
    if not (low <= track.min_freq_hz and track.max_freq_hz <= high):
        band.append(
            f"study.tracking.min_freq_hz/max_freq_hz: the tracker band [{track.min_freq_hz:g}, {track.max_freq_hz:g}] "
            f"Hz lies outside [{low:g}, {high:g}] Hz, the frequencies the ANFIS is trained on "
            "(reference_table.freq_y_hz and freq_z_hz)"
        )
    found = {}
    for section in ("study", "benchmark"):
        part = getattr(config, section)
        outside = [s for s in part.stiffness if not k.min() <= s <= k.max()]
        found[section] = [
            f"{section}.stiffness_n_m: {outside} N m-1 lies outside [{k.min():g}, {k.max():g}] N m-1, the stiffnesses "
            "the ANFIS is trained on (reference_table.stiffness_n_m; a value in kN m-1?)"
        ] * bool(outside) + band
        if found[section] and not part.allow_extrapolation:
            raise ConfigError(
                f"{found[section][0]}; set {section}.allow_extrapolation: true to run it anyway (the run records a "
                "warning)"
            )
    return found
