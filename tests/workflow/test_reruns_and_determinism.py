"""Rerun promises for an edit of every config section, and two quick runs compared file by file (the second killed
in the reference table and resumed; its helicopter stage is the first's, which repeats exactly on its own).

workflow/rules/common.smk promises that a rule's params hold only what the rule uses, with sorted keys, so an
edit reruns exactly the stages it affects (and those downstream of them) and reordering keys reruns nothing.
Each case edits the quick run's merged config (quick.yaml and its plug-in override) and asks Snakemake for a
dry run on the finished quick run, through Snakemake's command line inside the test process
(`conftest.snakemake_dry`: the same plan as a new `snakemake -n` process, without its start-up).
"""

from __future__ import annotations

import copy
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import (
    QUICK_RUN_ARGS,
    copy_workflow,
    quick_run_config,
    seed_helicopter,
    snakemake,
    snakemake_dry,
    with_plugin,
)
from conftest import planned_rules as dry_run_rules

from uavdamp import io

pytestmark = pytest.mark.slow  # every test here starts Snakemake (in-process or as a process)

# the payload stage reads the cases (excitation), the payload table, the camera and the platform
# the levels stage reads every helicopter run, the cases and the logs
FLIGHT = {"helicopter_flight", "helicopter_trim", "helicopter_vibration", "excitation", "study", "payload", "levels"}
HELICOPTER_ALL = {
    "helicopter_run",
    "helicopter_flight",
    "helicopter_trim",
    "helicopter_vibration",
    "helicopter_campbell",
    "helicopter_sensitivity_run",
    "helicopter_sensitivity",
    "excitation",
    "study",
    "payload",
    "levels",
}
GRID_DOWN = {"reference_table_chunk", "reference_table", "reference_table_stroke", "anfis", "study"}

# name: (path of the edited key, new value or a function of the old one, rules the dry run must plan besides "all")
EDITS = {
    "helicopter.fuselage.mass_kg": (("helicopter", "fuselage", "mass_kg"), lambda v: v * 1.01, HELICOPTER_ALL),
    "helicopter.campbell.n_speeds": (("helicopter", "campbell", "n_speeds"), lambda v: v + 2, {"helicopter_campbell"}),
    # the flight runs' own sections: the vacuum runs, the Campbell diagram and the vacuum sensitivity stay
    "helicopter.aerodynamics.main_blade.chord_m": (
        ("helicopter", "aerodynamics", "main_blade", "chord_m"),
        lambda v: v * 1.01,
        FLIGHT,
    ),
    "helicopter.flight.hold.bandwidth_hz": (
        ("helicopter", "flight", "hold", "bandwidth_hz"),
        lambda v: v * 0.9,
        FLIGHT,
    ),
    "helicopter.sensitivity.flight": (
        ("helicopter", "sensitivity", "flight"),
        lambda v: "hover",
        {"helicopter_sensitivity_run", "helicopter_sensitivity"},
    ),
    "helicopter.sensitivity.duration_s": (
        ("helicopter", "sensitivity", "duration_s"),
        lambda v: v + 0.5,
        {"helicopter_sensitivity_run", "helicopter_sensitivity"},
    ),
    "platform.structure.camera_mass_kg": (
        ("platform", "structure", "camera_mass_kg"),
        lambda v: v * 1.01,
        {"platform_modes", "payload_table", "payload_anfis", "payload"} | GRID_DOWN,
    ),
    # the head's own bodies: not the gimbal's table (it carries only the camera)
    "platform.structure.base_mass_kg": (
        ("platform", "structure", "base_mass_kg"),
        lambda v: v * 1.01,
        {"platform_modes", "payload"} | GRID_DOWN,
    ),
    "payload.table.translation_amplitude_m": (
        ("payload", "table", "translation_amplitude_m"),
        lambda v: v * 2,
        {"payload_table", "payload_anfis", "payload"},
    ),
    "payload.schedule.window_s": (("payload", "schedule", "window_s"), lambda v: v * 0.8, {"payload"}),
    # the payload ANFIS's inputs: its training and the payload stage that runs it, not the table
    "payload.anfis.dofs": (("payload", "anfis", "dofs"), lambda v: ["x", "rz"], {"payload_anfis", "payload"}),
    "platform.response.duration_s": (("platform", "response", "duration_s"), lambda v: v + 0.5, {"platform_modes"}),
    "platform.isolator.damping_max_n_s_m": (
        ("platform", "isolator", "damping_max_n_s_m"),
        lambda v: v * 1.1,
        {"platform_modes", "payload"} | GRID_DOWN,
    ),
    # the stroke budget: the table's budget and the study, not the grid, the ANFIS or the platform's modes
    "platform.stroke.max_stroke_m": (
        ("platform", "stroke", "max_stroke_m"),
        lambda v: v * 2,
        {"reference_table_stroke", "study"},
    ),
    "reference_table.damping_n_s_m": (("reference_table", "damping_n_s_m", "num"), lambda v: v + 1, GRID_DOWN),
    "reference_table.flat_tolerance": (
        ("reference_table", "flat_tolerance"),
        lambda v: v * 2,
        {"reference_table", "reference_table_stroke", "anfis", "study"},
    ),
    # the anfis section's options train the study's ANFIS and the payload's
    "anfis.ridge": (("anfis", "ridge"), lambda v: v + 1e-6, {"anfis", "study", "payload_anfis", "payload"}),
    "study.passive_damping_n_s_m": (("study", "passive_damping_n_s_m"), lambda v: v * 1.5, {"study"}),
    "study.tracking.window_s": (
        ("study", "tracking", "window_s"),
        lambda v: v * 0.8,
        {"excitation", "study", "payload", "levels"},
    ),
    "levels.settle_s": (("levels", "settle_s"), lambda v: v + 0.5, {"levels"}),
    "study.figures.case_1": (("study", "figures", "case_1"), lambda v: "case2", {"study"}),
    # the sharp-frame threshold is the study's image metric, not the grid's blur (it once reran the grid)
    "camera.sharp_threshold_px": (("camera", "sharp_threshold_px"), lambda v: v * 2, {"study", "payload"}),
    # the grid's blur criterion uses the camera: its chunks, the table, the ANFIS and the study rerun
    "camera.exposure_s": (
        ("camera", "exposure_s"),
        lambda v: v * 2,
        {"reference_table_chunk", "reference_table", "reference_table_stroke", "anfis", "study", "payload"},
    ),
}


# the summary rule reads these stages' outputs: an edit that reruns one of them reruns it
SUMMARY_INPUTS = {
    "helicopter_vibration",
    "platform_modes",
    "reference_table",
    "reference_table_stroke",
    "anfis",
    "study",
    "payload",
}


def planned_rules(workdir, config: dict) -> set[str]:
    """The rules a dry run of `all` would run with `config` as the one config file (the job-count table); the
    quick run's merged config (`quick_run_config`) plans nothing."""
    edited = workdir / "config" / "edited.yaml"
    edited.write_text(yaml.safe_dump(config, sort_keys=False))
    result = snakemake_dry(workdir, "-n", "-j1", "all", "--configfile", str(edited.relative_to(workdir)))
    assert result.returncode == 0, result.stderr[-3000:]
    return dry_run_rules(result)


@pytest.mark.parametrize("name", sorted(EDITS))
def test_an_edit_of_every_section_reruns_exactly_its_stages(quick_run, name):
    path, change, expected = EDITS[name]
    config = quick_run_config()
    node = config
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = change(node[path[-1]])
    expected = expected | ({"summary"} if expected & SUMMARY_INPUTS else set())
    assert planned_rules(quick_run, config) == expected | {"all"}


def _reversed(value):
    if isinstance(value, dict):
        return {key: _reversed(value[key]) for key in reversed(list(value))}
    return copy.deepcopy(value)


def test_reordered_keys_rerun_nothing(quick_run):
    assert planned_rules(quick_run, _reversed(quick_run_config())) == set()


def test_the_same_config_reruns_nothing(quick_run):
    assert planned_rules(quick_run, quick_run_config()) == set()


@pytest.mark.parametrize("section", ["anfis", "payload"])
def test_the_threads_rerun_nothing(quick_run, section):
    """anfis.threads and payload.threads are the jobs' threads, not options: the results do not depend on them
    (tests/test_payload.py checks the payload's numbers on 1 and 2 workers)."""
    config = quick_run_config()
    config[section]["threads"] = 1 if config[section]["threads"] != 1 else 2
    assert planned_rules(quick_run, config) == set()


# attrs that record when and how fast a file was made, not what it holds
PROVENANCE = {"history", "build_time_s", "solver_time_s", "worker_time_s", "wall_time_s", "run_started"}


def _attrs(attrs: dict, workdir) -> dict:
    """Attributes less PROVENANCE, with the run's folder (in config_files) written as <workdir>, and the core count,
    the resume's flag and the targets left out of the command line (files written before the kill carry -j1, after
    it -j2 and --rerun-incomplete; the second run asks for `SECOND_RUN`)."""
    out = {k: v.replace(str(workdir), "<workdir>") if isinstance(v, str) else v for k, v in attrs.items()}
    if "command_line" in out:  # the targets too: the second run asks for fewer
        out["command_line"] = re.sub(r" -j\d+| --rerun-incomplete", "", out["command_line"])
        out["command_line"] = re.sub(r"(__main__\.py) .*? (--configfile)", r"\1 <targets> \2", out["command_line"])
    return {k: v for k, v in out.items() if k not in PROVENANCE}


def assert_same_netcdf_files(first, second, skip: str) -> int:
    """Every NetCDF under second/reports-quick but those under its folder `skip` (seeded: copies) holds the same
    values and attributes as first's of the same name; the count compared."""
    second_files = sorted(p.relative_to(second) for p in (second / "reports-quick").rglob("*.nc"))
    compared = [rel for rel in second_files if rel.parts[1] != skip]
    for rel in compared:
        a, b = io.open_dataset(first / rel), io.open_dataset(second / rel)
        assert set(a.variables) == set(b.variables), rel
        for name in a.variables:
            np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=f"{rel}: {name}")
            assert a[name].attrs.keys() == b[name].attrs.keys(), f"{rel}: {name}"
            for key, value in a[name].attrs.items():
                np.testing.assert_array_equal(value, b[name].attrs[key], err_msg=f"{rel}: {name}.{key}")
        attrs_a, attrs_b = _attrs(a.attrs, first), _attrs(b.attrs, second)
        assert attrs_a.keys() == attrs_b.keys(), rel
        for key in attrs_a:
            np.testing.assert_array_equal(attrs_a[key], attrs_b[key], err_msg=f"{rel}: attribute {key}")
    return len(compared)


# the second run's targets: `all` and, of the benchmark, its tuning and the run of the synthetic scenario that draws
# random numbers (the other scenarios' runs and the gather repeat the same code on inputs already compared)
SECOND_RUN = ("all", "reports-quick/benchmark/tuned/K10.nc", "reports-quick/benchmark/runs/random_1.nc")


def _kill_after_two_chunks_started(workdir) -> list[str]:
    """`snakemake -j1 SECOND_RUN` on the quick run's config in `workdir`, killed (SIGKILL, the whole process group)
    once a second reference-table chunk has started; the chunks in the order they started (-j1: one job at a time,
    so a chunk starts only after the one before has finished)."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "snakemake", "-j1", *SECOND_RUN, *QUICK_RUN_ARGS],
        cwd=workdir,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    logs = workdir / "reports-quick/logs/reference_table"
    started: list[str] = []  # one chunk job at a time, each writes its log first
    deadline = time.monotonic() + 600
    try:
        while time.monotonic() < deadline and proc.poll() is None and len(started) < 2:
            for log in sorted(logs.glob("*-of-*.log")) if logs.exists() else []:
                if log.stem not in started:
                    started.append(log.stem)
            time.sleep(0.05)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=60)
    return started


@pytest.mark.slow
def test_a_killed_and_resumed_run_gives_the_quick_runs_netcdf_files(quick_run, tmp_path):
    """A second quick run in another folder, killed in the reference table and resumed: the finished chunks are
    kept, and every NetCDF the second run wrote (`SECOND_RUN`) holds the first's values and attributes (the run is
    reproducible, and a resume changes nothing). The helicopter stage, which draws no random number, is the quick
    run's, seeded (its runs repeat exactly: tests/test_helicopter.py and tests/test_helicopter_flight.py); every
    other stage runs again."""
    # the chunks record their worker count (n_jobs): at -j1 it is the quick config's only if that is one
    assert quick_run_config()["reference_table"]["threads"] == 1
    second = with_plugin(copy_workflow(tmp_path / "second"))
    seed_helicopter(quick_run, second, "reports-quick")
    started = _kill_after_two_chunks_started(second)
    assert len(started) >= 2, "the run ended or timed out before a second chunk started"
    chunks = second / "reports-quick/reference_table/chunks"
    kept = {name: (chunks / f"{name}.nc").stat().st_mtime_ns for name in started[:-1]}  # finished and recorded
    assert not (second / "reports-quick/reference_table/table.nc").exists()
    assert snakemake(second, "--unlock", *QUICK_RUN_ARGS).returncode == 0  # the kill left a lock
    result = snakemake(second, "-j2", *SECOND_RUN, *QUICK_RUN_ARGS, "--rerun-incomplete")
    assert result.returncode == 0, result.stderr[-3000:]
    for name, mtime in kept.items():
        assert (chunks / f"{name}.nc").stat().st_mtime_ns == mtime, f"{name} was recomputed"
    assert not list((second / "reports-quick/logs").glob("helicopter*")), "a seeded helicopter job ran again"
    first_files = {p.relative_to(quick_run / "reports-quick") for p in (quick_run / "reports-quick").rglob("*.nc")}
    second_files = {p.relative_to(second / "reports-quick") for p in (second / "reports-quick").rglob("*.nc")}
    asked = {Path(target).relative_to("reports-quick") for target in SECOND_RUN[1:]}
    assert {p for p in first_files if p.parts[0] != "benchmark"} | asked <= second_files <= first_files
    assert assert_same_netcdf_files(quick_run, second, skip="helicopter") > 10
