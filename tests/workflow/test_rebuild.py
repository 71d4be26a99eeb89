"""Every output is requested by `rule all`: delete any one and the dry run plans the rule that rebuilds it.

The dry runs go through Snakemake's command line inside the test process (`conftest.snakemake_dry`), on a copy of
the quick run (the tests move its files aside: other workers read the quick run meanwhile)."""

from __future__ import annotations

import os

import pytest
from conftest import QUICK_RUN_ARGS, copy_run, planned_rules, snakemake_dry

pytestmark = pytest.mark.slow  # every test here starts Snakemake (in-process or as a process)

# one output of each kind per producing rule (rule name, path under the quick run's folder)
OUTPUTS = [
    ("helicopter_run", "reports-quick/helicopter/runs/imbalanced.nc"),
    ("helicopter_vibration", "reports-quick/figures/fuselage_vibration.png"),
    ("helicopter_campbell", "reports-quick/helicopter/campbell.nc"),
    ("helicopter_sensitivity_run", "reports-quick/helicopter/sensitivity/baseline.nc"),
    ("helicopter_sensitivity", "reports-quick/figures/helicopter_sensitivity.png"),
    ("platform_modes", "reports-quick/figures/platform_response.png"),
    ("reference_table_chunk", "reports-quick/reference_table/chunks/2-of-2.nc"),
    ("reference_table", "reports-quick/reference_table/grid.nc"),
    ("anfis", "reports-quick/anfis/rules.txt"),
    ("anfis", "reports-quick/anfis/rules.md"),
    ("anfis", "reports-quick/anfis/model.fis"),
    ("anfis", "reports-quick/anfis/training.nc"),
    ("anfis", "reports-quick/figures/anfis_selection.png"),
    ("excitation", "reports-quick/excitation/cases.nc"),
    ("study", "reports-quick/figures/study_fig12_tracked_frequency.png"),
    # one named figure per case (a directory() output was not rebuilt when one of its files was deleted)
    ("study", "reports-quick/figures/study_strategies/case1.png"),
]


@pytest.fixture(scope="module")
def run_copy(quick_run, tmp_path_factory):
    return copy_run(quick_run, tmp_path_factory.mktemp("rebuild") / "run")


@pytest.mark.parametrize(("rule", "path"), OUTPUTS, ids=[p.rsplit("/", 1)[-1] for _, p in OUTPUTS])
def test_deleted_output_is_planned_for_rebuild(run_copy, rule, path):
    target = run_copy / path
    assert target.is_file(), path
    aside = target.with_name(target.name + ".aside")
    os.replace(target, aside)  # keeps the mtime, so putting it back restores the finished run
    try:
        result = snakemake_dry(run_copy, "-n", "-j1", "all", *QUICK_RUN_ARGS)
    finally:
        os.replace(aside, target)
    assert result.returncode == 0, result.stderr[-3000:]
    assert rule in planned_rules(result), (rule, result.stdout[-3000:])


def test_nothing_planned_after_a_complete_run(run_copy):
    result = snakemake_dry(run_copy, "-n", "-j1", "all", *QUICK_RUN_ARGS)
    assert result.returncode == 0, result.stderr[-3000:]
    assert "Nothing to be done" in result.stdout + result.stderr, result.stdout[-3000:]
