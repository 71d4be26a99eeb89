"""docs/stages/flight-logs.md, "A log beside the helicopter cases", followed word for word on the quick config.

The page's override (its YAML block, read from the page) is added to the session's quick run, as a user adds it to
theirs: the run reuses every upstream stage the override does not touch and brings the log's 0.501 ms samples and
the helicopter's 5 ms ones onto one grid.
"""

from __future__ import annotations

import re
import shutil

import numpy as np
import pytest
import yaml
from conftest import QUICK_RUN_ARGS, ROOT, planned_rules, snakemake, snakemake_dry

from uavdamp import io

pytestmark = pytest.mark.slow  # starts Snakemake on a copy of the quick run

PAGE = ROOT / "docs" / "stages" / "flight-logs.md"
SECTION = "## A log beside the helicopter cases"


def _page_override() -> tuple[str, str]:
    """(the YAML block, the command) of the page's section."""
    text = PAGE.read_text()
    section = text[text.index(SECTION) : text.index("\n## ", text.index(SECTION) + 1)]
    block = re.search(r"```yaml\n(.*?)```", section, re.S).group(1)
    command = re.search(r"`(snakemake [^`]*my-log\.yaml)`", section).group(1)
    return block, command


@pytest.fixture(scope="module")
def log_case_run(quick_run, tmp_path_factory):
    """The quick run copied (outputs, metadata and times), the page's override added, the page's command run."""
    workdir = tmp_path_factory.mktemp("log_case") / "run"
    shutil.copytree(quick_run, workdir, symlinks=True)
    block, command = _page_override()
    (workdir / "my-log.yaml").write_text(block)
    # the page's command on the quick config: config/config.yaml is always read first, quick.yaml over it
    args = command.split()[1:]
    args = args[: args.index("--configfile")] + [*QUICK_RUN_ARGS, "my-log.yaml"]
    plan = planned_rules(snakemake_dry(workdir, "-n", *args))
    result = snakemake(workdir, *args)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-6000:]
    return workdir / "reports-quick", plan, yaml.safe_load(block)


def test_the_page_override_reruns_only_the_stages_a_new_case_reaches(log_case_run):
    _, plan, _ = log_case_run
    assert {"flight_log", "excitation", "study", "payload", "summary"} <= plan
    assert not {"helicopter_run", "helicopter_flight", "reference_table", "reference_table_chunk", "anfis"} & plan


def test_the_log_case_is_its_window_as_measured_beside_the_helicopter_cases(log_case_run):
    out, _, block = log_case_run
    ((name, case),) = block["study"]["cases"].items()
    cases = io.open_dataset(out / "excitation" / "cases.nc")
    assert list(cases.case.values) == ["case1", "case2", "case3", name]
    log = io.open_dataset(out / "flight_logs" / f"{case['flight_log']}.nc")
    step = float(log.attrs["time_step_s"])
    assert float(cases.time[1] - cases.time[0]) == pytest.approx(step, rel=1e-12)  # the finest case's grid
    start = case["window_s"][0] - float(log.attrs["log_window_s"][0])
    expected = log.mount_displacement.sel(axis="y", time=slice(start - 1e-9, None)).values[: cases.time.size]
    np.testing.assert_array_equal(cases.mount_displacement.sel(case=name, mount_axis="y").values, expected)
    rates = cases.sample_rate_hz.values
    assert list(rates) == pytest.approx([200.0, 200.0, 200.0, 1 / step], rel=1e-9)  # the log's, upsampled
    assert np.all(cases.grid_timing_error_s.values <= 1e-4 * 2 / rates)  # below 1e-4 of each Nyquist period


def test_the_helicopter_cases_keep_their_line_on_the_log_grid(quick_run, log_case_run):
    """Case 1 on the log's 0.501 ms grid against the same case on its own 5 ms grid (the quick run): the
    amplitude of its 7.07 Hz line fitted over 0.5-1.5 s agrees within 0.2 % (the resampler's passband ripple)."""
    out, _, _ = log_case_run
    fits = []
    for folder in (quick_run / "reports-quick", out):
        y = io.open_dataset(folder / "excitation" / "cases.nc").mount_displacement.sel(case="case1", mount_axis="y")
        y = y.where((y.time > 0.5) & (y.time < 1.5), drop=True)
        w, t = 2 * np.pi * 7.07, y.time.values
        coef = np.linalg.lstsq(np.stack([np.sin(w * t), np.cos(w * t)], 1), y.values, rcond=None)[0]
        fits.append(coef)
    np.testing.assert_allclose(fits[1], fits[0], rtol=0, atol=2e-3 * np.hypot(*fits[0]))


def test_the_study_and_the_summary_carry_the_log_case(log_case_run):
    out, _, block = log_case_run
    ((name, case),) = block["study"]["cases"].items()
    study = io.open_dataset(out / "study" / "comparison.nc")
    assert name in study.case.values
    assert np.all(np.isfinite(study.los_std.sel(case=name).values))
    summary = (out / "summary.md").read_text()
    assert f"**{name}**: {case['description']}" in summary
