"""Bad configs are refused before any job: the schema per value, `uavdamp.checks` across sections.

Each case edits config/quick.yaml's merged config through one more --configfile; Snakemake must exit non-zero
naming the key, start no job and leave the previous outputs untouched.
"""

from __future__ import annotations

import pytest
import yaml
from conftest import ROOT, copy_workflow, load_config, snakemake
from snakemake.exceptions import WorkflowError

from uavdamp import checks

# (override merged over quick.yaml, text the error must contain)
BAD = {
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
        "[10.0, 10.0] has non-unique elements\n\nFailed validating 'uniqueItems' in "
        "schema['properties']['study']['properties']['stiffness_n_m']",
    ),
    "damper-bounds-reversed": (
        {"platform": {"isolator": {"damping_min_n_s_m": 50.0, "damping_max_n_s_m": 5.0}}},
        "platform.isolator.damping_max_n_s_m: (5.0) must be >=",
    ),
    "grid-window-longer-than-run": (
        {"reference_table": {"windows": {"transient": [0.0, 19.0]}}},
        "reference_table.windows.transient",
    ),
    "update-period-not-a-multiple": (
        {"platform": {"isolator": {"update_period_s": 0.5003}}},
        "platform.isolator.update_period_s: (0.5003 s) must be a whole multiple",
    ),
    "duplicated-grid-values": (
        {"reference_table": {"stiffness": {"values": [10.0, 10.0]}}},
        "reference_table.stiffness: values must be strictly increasing",
    ),
    "passive-outside-bounds": (
        {"study": {"passive_damping_n_s_m": 500.0}},
        "study.passive_damping_n_s_m: (500.0) must lie within the damper bounds",
    ),
    "early-window-after-run": ({"study": {"early_s": 3.0}}, "study.early_s: (3.0 s) must lie inside study.duration_s"),
    "unknown-strategy": (
        {"study": {"strategies": ["passive", "telepathy"]}},
        "'telepathy' is not one of ['rigid', 'passive', 'optimal_passive', 'anfis', 'skyhook']",
    ),
    "grid-over-budget": (
        {"reference_table": {"freq_y_hz": {"num": 1000}, "freq_z_hz": {"num": 1000}, "damping": {"num": 1000}}},
        "budget.max_cpu_hours: the run is estimated at 55.6 CPU hours (grid 2,000,000,000 points",
    ),
    "budget-not-positive": (
        {"budget": {"max_cpu_hours": 0.0}},
        "Failed validating 'exclusiveMinimum' in schema['properties']['budget']['properties']['max_cpu_hours']",
    ),
    "figure-case-unknown": ({"study": {"figures": {"case_1": "case9"}}}, "study.figures.case_1: 'case9' is not a case"),
}


def _merged(override: dict) -> dict:
    from conftest import deep_update

    return deep_update(load_config("quick.yaml"), override)


def _validate_and_check(config: dict) -> None:
    """What the Snakefile does before any job: the schema, then the checks across sections."""
    from snakemake.utils import validate

    validate(config, str(ROOT / "workflow" / "schemas" / "config.schema.yaml"))
    checks.check_config(config)


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_value_is_refused_naming_the_key(case):
    override, message = BAD[case]
    with pytest.raises((ValueError, WorkflowError)) as error:
        _validate_and_check(_merged(override))
    assert message in str(error.value), str(error.value)[-2000:]


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """A scratch workflow with a previous output in place, which no refused run may touch."""
    work = copy_workflow(tmp_path_factory.mktemp("refuse"))
    previous = work / "reports" / "study" / "comparison.nc"
    previous.parent.mkdir(parents=True)
    previous.write_text("previous good result")
    return work


@pytest.mark.parametrize("case", ["freq-above-nyquist", "duplicated-study-stiffness", "tracking-band-reversed"])
def test_snakemake_refuses_before_any_job(workdir, case):
    """Through Snakemake: non-zero exit naming the key, no job started, the previous output untouched."""
    override, message = BAD[case]
    (workdir / "config" / "bad.yaml").write_text(yaml.safe_dump(override))
    result = snakemake(workdir, "-j1", "all", "--configfile", "config/quick.yaml", "config/bad.yaml", timeout=300)
    output = result.stdout + result.stderr
    assert result.returncode != 0, output[-2000:]
    assert message in output, output[-3000:]
    assert "Building DAG" not in output and "localrule" not in output and "rule " not in output, output[-2000:]
    files = sorted(p.relative_to(workdir).as_posix() for p in (workdir / "reports").rglob("*") if p.is_file())
    assert files == ["reports/study/comparison.nc"], files
    assert (workdir / "reports/study/comparison.nc").read_text() == "previous good result"


@pytest.mark.parametrize("name", ["config.yaml", "quick.yaml"])
def test_shipped_configs_pass_the_checks(name):
    _validate_and_check(load_config(name))


def test_the_plan_and_its_cost_are_printed_before_any_job(tmp_path):
    """A dry run shows the counts and the CPU estimate: 3 x 3 x 2 x 4 grid points, 3 helicopter runs of 4 s and the
    sensitivity runs (8 of 2 s), 2 cases x 2 K x (5 strategies + 5 candidates + 20 refinements) study runs."""
    work = copy_workflow(tmp_path)
    result = snakemake(work, "-n", "-j1", "all", "--configfile", "config/quick.yaml", timeout=300)
    assert result.returncode == 0, result.stderr[-2000:]
    assert "uavdamp plan: 72 grid points, 28 simulated s of helicopter, 120 study runs: about" in result.stderr
