"""Checks of the measured flights the config names, before any job (`uavdamp.config.checks` calls `check`).

Every configured log's file exists; every study case and benchmark scenario that takes a log has a window inside
what its log can trust (the log's span less `edge_s` at either end, read from the file's timestamps without
integrating anything) and as long as the run it feeds; a study case's log is integrated in a band that meets
the study's tracker band, else the tracker would only see the band's edge. Each ConfigError names the key, the
rule and the fix. Cases sampled at other rates need no check: `uavdamp.sources.excitation.on_common_grid` brings
them onto one grid. With the benchmark target, a measured scenario's grid must be one the benchmark on the payload
can resample onto payload.time_step_s.
"""

from __future__ import annotations

import math
from pathlib import Path

from uavdamp.settings import ConfigError, require
from uavdamp.signals import inertial
from uavdamp.sources.flight_log import FlightLogError, log_span
from uavdamp.study.payload_runs import resample_ratio


def check(config, benchmark: bool = False) -> None:
    """ConfigError naming the first flight-log key that breaks a rule of the module docstring (with `benchmark`,
    the benchmark target's too)."""
    _check_files(config)
    spans: dict[str, tuple[float, float, float]] = {}
    for where, name, window, duration, duration_key in _uses(config):
        if name not in spans:
            spans[name] = _span(config.flight_logs[name], f"flight_logs.{name}")
        _check_window(where, config.flight_logs[name].band_hz, spans[name], window, duration, duration_key)
    if benchmark and config.benchmark.payload.enabled:
        for scenario in config.benchmark.flight_logs:
            _check_payload_grid(scenario, spans[scenario.flight_log][2], config)
    track = config.study.tracking
    for case_name, case in config.study.cases.items():
        if case.flight_log:
            low, high = config.flight_logs[case.flight_log].band_hz
            require(
                low < track.max_freq_hz and high > track.min_freq_hz,
                f"study.cases.{case_name}.flight_log",
                f"the log {case.flight_log!r} is integrated in flight_logs.{case.flight_log}.band_hz [{low:g}, "
                f"{high:g}] Hz, which does not meet the tracker's band study.tracking.min_freq_hz/max_freq_hz "
                f"[{track.min_freq_hz:g}, {track.max_freq_hz:g}] Hz: the tracker would find no line of it. Either "
                "set the log's band_hz across the tracker's band, or run the log in a study of its own band "
                "(config/multirotor.yaml sets the tracker, the reference table and the solver for 20-47 Hz)",
            )


def _check_payload_grid(scenario, step: float, config) -> None:
    """The benchmark on the payload resamples a measured scenario from its log's grid (`step` s: 1 / (its rate x
    its upsample)) onto payload.time_step_s by a polyphase filter, which needs a ratio of integers up to 1000."""
    h, log = config.payload.time_step_s, scenario.flight_log
    require(
        resample_ratio(step, h) is not None,
        f"benchmark.flight_logs.{scenario.name}",
        f"the log {log!r} is on a {step * 1e3:.6g} ms grid (1 / (its rate x flight_logs.{log}.upsample)), whose "
        f"ratio to payload.time_step_s ({h * 1e3:g} ms) is no ratio of integers up to 1000: the benchmark on the "
        "payload cannot resample it (`uavdamp.study.payload_runs.resampled`). Set payload.time_step_s to a step "
        "whose ratio is (config.yaml's 0.5 ms, for the shipped logs), or benchmark.payload.enabled: false",
    )


def _check_files(config) -> None:
    """Every configured flight log's file exists (paths relative to the run directory): an existing output must
    not hide a mistyped path."""
    for name, source in config.flight_logs.items():
        require(
            Path(source.path).is_file(),
            f"flight_logs.{name}.path",
            f"no file {source.path!r} (relative to the run "
            f"directory {Path.cwd()}; the flight_log rule reads it and reruns when its content changes)",
        )


def _uses(config):
    """(key of the window, log name, window_s or None, run length s, key of that length) per case or scenario."""
    for name, case in config.study.cases.items():
        if case.flight_log:
            yield f"study.cases.{name}", case.flight_log, case.window_s, config.study.duration_s, "study.duration_s"
    for scenario in config.benchmark.flight_logs:
        yield (
            f"benchmark.flight_logs.{scenario.name}",
            scenario.flight_log,
            scenario.window_s,
            config.benchmark.duration_s,
            "benchmark.duration_s",
        )


def _span(source, key: str) -> tuple[float, float, float]:
    """(first, last, step) s of the log's grid (`uavdamp.sources.flight_log.log_span`); a FlightLogError (a
    window outside the log, too low a rate, a gap) becomes a ConfigError naming the entry."""
    try:
        first, last, step = log_span(
            source.path, band_hz=source.band_hz, window_s=source.window_s, upsample=source.upsample
        )
    except FlightLogError as error:
        raise ConfigError(f"{key}: {error}") from None
    return first, last, step


def _check_window(where, band_hz, span, window, duration: float, duration_key: str) -> None:
    """The window within the span less edge_s at either end, holding `duration` s of the log's samples."""
    first, last, step = span
    edge = inertial.edge_s(band_hz)
    low, high = first + edge, last - edge
    start, end = window if window is not None else (low, high)
    require(
        start >= low - 1e-9 and end <= high + 1e-9,
        f"{where}.window_s",
        f"[{start:g}, {end:g}] s must lie within [{low:.3f}, {high:.3f}] s: the log's span [{first:.3f}, "
        f"{last:.3f}] s (of its clock) less edge_s = {edge:.3f} s at either end, where the band-limited "
        "integration is not to be trusted (`python -m uavdamp.sources.flight_log PATH` prints the span)",
    )
    k0 = math.ceil((start - first) / step - 1e-6)  # the first and last grid samples inside the window
    k1 = math.floor((end - first) / step + 1e-6)
    held = (k1 - k0) * step
    require(
        held >= duration - 1e-9,
        f"{where}.window_s",
        f"[{start:g}, {end:g}] s holds {held:.3f} s of the log's samples, shorter than {duration_key} = "
        f"{duration:g} s: widen the window or shorten {duration_key}",
    )
