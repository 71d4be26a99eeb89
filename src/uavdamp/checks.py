"""Checks that span config sections, run right after the schema and before any job (the Snakefile calls them).

The schema checks each value alone; these check values against each other, and the typed section loaders
check each section: every ValueError names the key and the rule it breaks.
"""

from __future__ import annotations

from uavdamp import budget
from uavdamp.config import require
from uavdamp.platform import PlatformParams
from uavdamp.platform.params import is_multiple


def check_config(config: dict) -> dict:
    """Raise ValueError naming the first key that breaks a rule across sections (see the module docstring) or a
    run estimated above the budget; return the estimate (`uavdamp.budget`)."""
    from uavdamp import grid, helicopter
    from uavdamp.study import StudyOptions

    heli = config["helicopter"]
    helicopter.Helicopter.from_config(heli)
    helicopter.SolverOptions.from_config(heli["solver"])
    platform = PlatformParams.from_config(config["platform"])
    spec = grid.GridSpec.from_config(config["reference_table"])
    spec.check_damper_bounds(platform)
    study = config["study"]
    options = StudyOptions.from_config(
        {k: v for k, v in study.items() if k not in ("cases", "duration_s", "highpass_hz", "figures")}
    )
    _check_frequencies(config, platform, spec)
    _check_study(study, options, platform)
    verify = config["reference_table"].get("verify", {}).get("n_points", 0)
    return budget.check(config, spec.size, verify)


def _check_frequencies(config: dict, platform: PlatformParams, spec) -> None:
    """Every input frequency below the configured fraction of the platform solver's Nyquist frequency."""
    h = platform.time_step
    limit = platform.solver.max_frequency_fraction * 0.5 / h
    rule = (
        f"must stay below {platform.solver.max_frequency_fraction} x the Nyquist frequency of "
        f"platform.solver.time_step_s = {h} s, i.e. {limit:g} Hz"
    )
    for key, values in (("reference_table.freq_y_hz", spec.freq_y), ("reference_table.freq_z_hz", spec.freq_z)):
        require(values.max() < limit, key, f"{values.max():g} Hz {rule}")
    if platform.response is not None:
        for key in ("freq_y_hz", "freq_z_hz"):
            value = getattr(platform.response, key)
            require(value < limit, f"platform.response.{key}", f"{value:g} Hz {rule}")
    track = config["study"]["tracking"]
    require(track["max_freq_hz"] < limit, "study.tracking.max_freq_hz", f"{track['max_freq_hz']:g} Hz {rule}")
    output_step = config["helicopter"]["solver"]["output_step"]
    require(
        track["max_freq_hz"] < 0.5 / output_step,
        "study.tracking.max_freq_hz",
        f"must stay below the Nyquist frequency of helicopter.solver.output_step ({0.5 / output_step:g} Hz)",
    )


def _check_study(study: dict, options, platform: PlatformParams) -> None:
    """Run lengths, windows, update periods and the passive damper against the platform and the helicopter."""
    duration = study["duration_s"]
    require(
        options.early_s < duration,
        "study.early_s",
        f"({options.early_s} s) must lie inside study.duration_s ({duration} s)",
    )
    require(
        options.settle_s < duration,
        "study.settle_s",
        f"({options.settle_s} s) must lie inside study.duration_s ({duration} s)",
    )
    require(
        is_multiple(platform.update_period, platform.time_step),
        "platform.isolator.update_period_s",
        f"({platform.update_period} s) must be a whole multiple of platform.solver.time_step_s "
        f"({platform.time_step} s)",
    )
    bounds = (platform.damping_min, platform.damping_max)
    require(
        bounds[0] <= options.passive_damping <= bounds[1],
        "study.passive_damping_n_s_m",
        f"({options.passive_damping}) must lie within the damper bounds {list(bounds)} N s m-1",
    )
    for key in ("case_1", "case_2"):
        name = study["figures"][key]
        require(
            name in study["cases"],
            f"study.figures.{key}",
            f"{name!r} is not a case of study.cases ({sorted(study['cases'])})",
        )
