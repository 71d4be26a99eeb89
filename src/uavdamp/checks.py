"""Checks that span config sections, run right after the typed load and before any job (the Snakefile calls them).

Each section class checks its own values (`uavdamp.config`); these check values against each other: every
ConfigError names the key and the rule it breaks.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from uavdamp import budget, plugins, strategies
from uavdamp.config import Config, load
from uavdamp.contract import is_multiple
from uavdamp.platform import PlatformParams, design_stiffness
from uavdamp.settings import ConfigError, require
from uavdamp.workflow import check_schema

SCHEMA = Path(__file__).resolve().parents[2] / "workflow" / "schemas" / "config.schema.yaml"


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
    benchmark.controllers must be registered (`uavdamp.strategies.REGISTRY`: the one list for both)."""
    try:
        plugins.load(config.plugins)
    except FileNotFoundError as error:
        raise ConfigError(str(error)) from None
    known = sorted(strategies.REGISTRY)
    for key, names in (
        ("study.strategies", config.study.strategies),
        ("benchmark.controllers", config.benchmark.controllers),
    ):
        unknown = sorted(set(names) - set(known))
        require(not unknown, key, f"unknown strategy {unknown} (known: {known}; a plug-in adds its own: plugins)")


def check_config(config: Config, benchmark: bool = False) -> dict:
    """Raise ConfigError naming the first key that breaks a rule across sections (see the module docstring) or a
    run estimated above the budget; return the estimate (`uavdamp.budget`)."""
    check_names(config)
    extrapolation(config)
    _check_platform(config.platform)
    _check_frequencies(config)
    _check_benchmark_frequencies(config)
    _check_run_length(config)
    _check_folds(config)
    _check_study(config)
    _check_mounts(config)
    _check_flights(config)
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
    h = platform.time_step
    limit = platform.solver.max_frequency_fraction * 0.5 / h
    rule = (
        f"must stay below {platform.solver.max_frequency_fraction} x the Nyquist frequency of "
        f"platform.solver.time_step_s = {h} s, i.e. {limit:g} Hz"
    )
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
    row, anfis.train_fraction of them for training: `uavdamp.anfis.training.split`; failed points only remove)."""
    from uavdamp.anfis.training import split

    grid, anfis = config.reference_table, config.anfis
    shape = [axis.array().size for axis in (grid.freq_y, grid.freq_z, grid.stiffness)]
    rows = int(np.prod(shape))
    train = int(split(rows, anfis.train_fraction, anfis.seed).sum()) if rows > 1 else 0
    require(
        anfis.selection.folds <= train,
        "anfis.selection.folds",
        f"{anfis.selection.folds} folds need as many training rows; the reference table gives at most "
        f"{' x '.join(map(str, shape))} = {rows} rows (reference_table.freq_y_hz, freq_z_hz, stiffness_n_m), "
        f"{train} of them training rows (anfis.train_fraction {anfis.train_fraction})",
    )


def _check_mounts(config: Config) -> None:
    """Every mount a case or a benchmark scenario names is a mount point of the helicopter, every flight log a
    case names is configured."""
    points, logs = list(config.helicopter.mount_points), sorted(config.flight_logs)
    used = {f"study.cases.{name}.flight_log": case.flight_log for name, case in config.study.cases.items()}
    used |= {f"benchmark.flight_logs.{s.name}.flight_log": s.flight_log for s in config.benchmark.flight_logs}
    for key, log in used.items():
        require(not log or log in config.flight_logs, key, f"{log!r} is not a name of flight_logs ({logs})")
    named = {f"study.cases.{name}.mount": case.mount for name, case in config.study.cases.items() if case.run}
    named |= {f"benchmark.helicopter.mount[{k}]": m for k, m in enumerate(config.benchmark.helicopter.mount)}
    for key, mount in named.items():
        require(mount in points, key, f"{mount!r} is not a mount point of helicopter.mount_points_m ({points})")


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


def _check_study(config: Config) -> None:
    """The passive damper within the damper bounds."""
    study, platform = config.study, config.platform
    bounds = (platform.damping_min, platform.damping_max)
    require(
        bounds[0] <= study.passive_damping <= bounds[1],
        "study.passive_damping_n_s_m",
        f"({study.passive_damping}) must lie within the damper bounds {list(bounds)} N s m-1",
    )


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
