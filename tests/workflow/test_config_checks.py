"""Bad configs are refused by Snakemake before any job (`uavdamp.checks.validate`, tests/test_config.py).

Each case edits config/quick.yaml's merged config through one more --configfile; Snakemake must exit non-zero
naming the key, start no job and leave the previous outputs untouched.
"""

from __future__ import annotations

import pytest
import yaml
from conftest import copy_workflow, snakemake

# (override merged over quick.yaml, text the error must contain): the same refusals as tests/test_config.py
BAD = {
    "freq-above-nyquist": (
        {"reference_table": {"freq_y_hz": {"start": 4.0, "stop": 200.0}}},
        "reference_table.freq_y_hz: 200 Hz must stay below 0.25 x the Nyquist frequency",
    ),
    "duplicated-study-stiffness": (
        {"study": {"stiffness_n_m": [10.0, 10.0]}},
        "study.stiffness_n_m: values must be unique",
    ),
    # names that become paths (issue 24): a case named with / or an absolute path writes outside the output folder
    "case-named-with-slash": (
        {
            "study": {
                "cases": {
                    "a/b": {
                        "run": "imbalanced",
                        "mount": "cg",
                        "motion": "full",
                        "amplitude_m": 1.0e-3,
                        "amplitude_reading": "dominant",
                        "amplitude_scaling": "per_axis",
                    }
                }
            }
        },
        "study.cases: 'a/b' does not match '^[A-Za-z0-9_][A-Za-z0-9_.-]*$'",
    ),
    "case-named-absolute": (
        {
            "study": {
                "cases": {
                    "/tmp/x": {
                        "run": "imbalanced",
                        "mount": "cg",
                        "motion": "full",
                        "amplitude_m": 1.0e-3,
                        "amplitude_reading": "dominant",
                        "amplitude_scaling": "per_axis",
                    }
                }
            }
        },
        "study.cases: '/tmp/x' does not match",
    ),
    # out of the ANFIS's training range (issue 24): a K in kN m-1, the tracker band beyond the table's frequencies
    "study-stiffness-in-kn-per-m": (
        {"study": {"stiffness_n_m": [0.01], "allow_extrapolation": False}},
        "study.stiffness_n_m: [0.01] N m-1 lies outside [10, 1000] N m-1, the stiffnesses the ANFIS is trained on "
        "(reference_table.stiffness_n_m; a value in kN m-1?); set study.allow_extrapolation: true",
    ),
    "benchmark-stiffness-in-kn-per-m": (
        {"benchmark": {"stiffness_n_m": [0.01], "allow_extrapolation": False}},
        "benchmark.stiffness_n_m: [0.01] N m-1 lies outside [10, 1000] N m-1",
    ),
    "tracker-band-beyond-the-table": (
        {"study": {"allow_extrapolation": False}},
        "study.tracking.min_freq_hz/max_freq_hz: the tracker band [3, 12] Hz lies outside [4, 10] Hz, the "
        "frequencies the ANFIS is trained on (reference_table.freq_y_hz and freq_z_hz); set study.allow_extrapolation",
    ),
    "tracking-band-reversed": (
        {"study": {"tracking": {"min_freq_hz": 12.0, "max_freq_hz": 3.0}}},
        "study.tracking.max_freq_hz: the band [12.0, 3.0] Hz is empty",
    ),
}


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """A scratch workflow with a previous output in place, which no refused run may touch."""
    work = copy_workflow(tmp_path_factory.mktemp("refuse"))
    previous = work / "reports-quick" / "study" / "comparison.nc"
    previous.parent.mkdir(parents=True)
    previous.write_text("previous good result")
    return work


@pytest.mark.parametrize("case", sorted(BAD))
def test_snakemake_refuses_before_any_job(workdir, case):
    """Through Snakemake: non-zero exit naming the key, no job started, the previous output untouched."""
    override, message = BAD[case]
    (workdir / "config" / "bad.yaml").write_text(yaml.safe_dump(override))
    result = snakemake(workdir, "-j1", "all", "--configfile", "config/quick.yaml", "config/bad.yaml", timeout=300)
    output = result.stdout + result.stderr
    assert result.returncode != 0, output[-2000:]
    assert message in output, output[-3000:]
    assert "Building DAG" not in output and "localrule" not in output and "rule " not in output, output[-2000:]
    files = sorted(p.relative_to(workdir).as_posix() for p in (workdir / "reports-quick").rglob("*") if p.is_file())
    assert files == ["reports-quick/study/comparison.nc"], files
    assert (workdir / "reports-quick/study/comparison.nc").read_text() == "previous good result"


def test_the_plan_and_its_cost_are_printed_before_any_job(tmp_path):
    """A dry run shows the counts and the CPU estimate: 3 x 3 x 2 x 4 grid points, 3 helicopter runs of 4 s, the
    sensitivity runs (8 of 2 s) and the 2 flight runs, each counted as 5 vacuum seconds (budget.FLIGHT_COST) per
    simulated second of trim (1 s + 12 phases of 0.3 s and two 0.1415 s revolutions), release (1.5 s) and record
    (4 s): 2 x 67.48 s; 3 cases x 2 K x (5 strategies + 5 candidates + 20 refinements) study runs."""
    work = copy_workflow(tmp_path)
    result = snakemake(work, "-n", "-j1", "all", "--configfile", "config/quick.yaml", timeout=300)
    assert result.returncode == 0, result.stderr[-2000:]
    assert "uavdamp plan: 72 grid points, 162.963 simulated s of helicopter, 180 study runs: about" in result.stderr

