"""Bad configs are refused by Snakemake before any job (`uavdamp.config.checks.validate`, tests/test_config.py).

Each case edits config/quick.yaml's merged config through one more --configfile; Snakemake must exit non-zero
naming the key, start no job and leave the previous outputs untouched. The refusal happens while Snakemake reads
the Snakefile, before it builds a DAG, so every case runs as a dry run through Snakemake's own command line inside
the test process (`conftest.snakemake_dry`: the same output, no interpreter start-up each); a few cases, one per
layer of checks, also run as a real `snakemake` process that would start jobs if the refusal were missing.
"""

from __future__ import annotations

import re

import pytest
import yaml
from conftest import copy_workflow, snakemake, snakemake_dry

pytestmark = pytest.mark.slow  # every test here starts Snakemake (in-process or as a process)

# (override merged over quick.yaml, text the error must contain): the same refusals as tests/test_config.py


def _case_named(name: str) -> dict:
    """An override whose one study case, a valid helicopter case otherwise, is called `name`."""
    case = {
        "run": "imbalanced",
        "mount": "cg",
        "motion": "full",
        "amplitude_m": 1.0e-3,
        "amplitude_reading": "dominant",
        "amplitude_scaling": "per_axis",
    }
    return {"study": {"cases": {name: case}}}


BAD = {
    "freq-above-nyquist": (
        {"reference_table": {"freq_y_hz": {"start": 4.0, "stop": 200.0}}},
        "reference_table.freq_y_hz: 200 Hz must stay below 0.25 x the Nyquist frequency",
    ),
    "duplicated-study-stiffness": (
        {"study": {"stiffness_n_m": [10.0, 10.0]}},
        "study.stiffness_n_m: values must be unique",
    ),
    # names that become paths: a case named with / or an absolute path writes outside the output folder
    "case-named-with-slash": (
        _case_named("a/b"),
        "study.cases: 'a/b' does not match '^[A-Za-z0-9_][A-Za-z0-9_.-]*$'",
    ),
    "case-named-absolute": (
        _case_named("/tmp/x"),
        "study.cases: '/tmp/x' does not match",
    ),
    # out of the ANFIS's training range: a K in kN m-1, the tracker band beyond the table's frequencies
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
    # checked only inside jobs before, after Snakemake had deleted their previous outputs
    "helicopter-run-shorter-than-the-study": (
        {"helicopter": {"solver": {"duration_s": 1.0}}},
        "study.duration_s: (2.0 s) is longer than the helicopter run 'imbalanced' of study.cases.case1 "
        "(helicopter.solver.duration_s = 1.0 s)",
    ),
    "anfis-folds-beyond-the-training-rows": (
        {"anfis": {"selection": {"folds": 100}}},
        "anfis.selection.folds: 100 folds need as many training rows; the reference table gives at most "
        "3 x 3 x 2 = 18 rows (reference_table.freq_y_hz, freq_z_hz, stiffness_n_m), 14 of them training rows",
    ),
    "benchmark-sweep-above-nyquist": (
        {"benchmark": {"synthetic": [{"name": "sweep", "kind": "sweep", "freq_hz": [4.0, 200.0]}]}},
        "benchmark.synthetic[0] (sweep).freq_hz: 200 Hz must stay below platform.solver.max_frequency_fraction "
        "0.25 x the Nyquist frequency 1/(2 x platform.solver.time_step_s) of 0.004 s, i.e. 31.25 Hz",
    ),
    "benchmark-random-band-above-nyquist": (
        {"benchmark": {"synthetic": [{"name": "noise", "kind": "random", "band_hz": [4.0, 300.0], "seed": 1}]}},
        "benchmark.synthetic[0] (noise).band_hz: 300 Hz must stay below",
    ),
    # already refused before any job on main before these checks were added: kept so that they stay so
    "rotor-speed-zero": (
        {"helicopter": {"main_rotor": {"omega_rad_s": 0.0}}},
        "helicopter.main_rotor.omega_rad_s: must be > 0",
    ),
    "rotor-speed-nan": (
        {"helicopter": {"main_rotor": {"omega_rad_s": float("nan")}}},
        "helicopter.main_rotor.omega_rad_s: expected a finite number, got nan",
    ),
    "study-duration-nan": ({"study": {"duration_s": float("nan")}}, "study.duration_s: expected a finite number"),
    "n-chunks-as-float": (
        {"reference_table": {"n_chunks": 3.0}},
        "reference_table.n_chunks: expected an integer, got 3.0",
    ),
    "epochs-as-float": ({"anfis": {"epochs": 50.0}}, "anfis.epochs: expected an integer, got 50.0"),
    "strategies-as-a-string": (
        {"study": {"strategies": "passive"}},
        "study.strategies: expected a list, got 'passive'",
    ),
    "imbalanced-blade-beyond-the-rotor": (
        {"helicopter": {"imbalance": {"blade": 4}}},
        "helicopter.imbalance.blade: must lie in [0, 3] (helicopter.main_rotor.n_blades = 4), got 4",
    ),
    "camera-exposure-beyond-the-frame": (
        {"camera": {"exposure_s": 0.1}},
        "camera.exposure_s (0.1 s) exceeds the frame period 0.0333333 s",
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


def _assert_refused_before_any_job(workdir, result, message):
    output = result.stdout + result.stderr
    assert result.returncode != 0, output[-2000:]
    assert message in output, output[-3000:]
    assert "Building DAG" not in output and "localrule" not in output and "rule " not in output, output[-2000:]
    files = sorted(p.relative_to(workdir).as_posix() for p in (workdir / "reports-quick").rglob("*") if p.is_file())
    assert files == ["reports-quick/study/comparison.nc"], files
    assert (workdir / "reports-quick/study/comparison.nc").read_text() == "previous good result"


@pytest.mark.parametrize("case", sorted(BAD))
def test_snakemake_refuses_before_any_job(workdir, case):
    """Through Snakemake (a dry run in-process): non-zero exit naming the key, no DAG built, no job, the previous
    output untouched."""
    override, message = BAD[case]
    (workdir / "config" / "bad.yaml").write_text(yaml.safe_dump(override))
    result = snakemake_dry(workdir, "-n", "-j1", "all", "--configfile", "config/quick.yaml", "config/bad.yaml")
    _assert_refused_before_any_job(workdir, result, BAD[case][1])


# one case per layer of checks: the typed load, the schema's ranges, the cross-section rules
REAL_RUN = ["n-chunks-as-float", "rotor-speed-zero", "helicopter-run-shorter-than-the-study"]


@pytest.mark.parametrize("case", REAL_RUN)
def test_a_real_run_is_refused_before_any_job(workdir, case):
    """A `snakemake` process without -n (it would start jobs): refused as the dry run is, nothing written."""
    override, message = BAD[case]
    (workdir / "config" / "bad.yaml").write_text(yaml.safe_dump(override))
    result = snakemake(workdir, "-j1", "all", "--configfile", "config/quick.yaml", "config/bad.yaml", timeout=300)
    _assert_refused_before_any_job(workdir, result, message)


def test_the_plan_and_its_cost_are_printed_before_any_job(tmp_path):
    """A dry run shows the counts and the CPU estimate: 3 x 3 x 2 x 4 grid points, 3 helicopter runs of 4 s, the
    sensitivity runs (8 of 2 s) and the 2 flight runs, each counted as 5 vacuum seconds (budget.FLIGHT_COST) per
    simulated second of trim (1 s + 12 phases of 0.3 s and two 0.1415 s revolutions), release (1.5 s) and record
    (4 s): 2 x 67.48 s; 3 cases x 2 K x (5 strategies + 5 candidates + 20 refinements) study runs."""
    work = copy_workflow(tmp_path)
    result = snakemake_dry(work, "-n", "-j1", "all", "--configfile", "config/quick.yaml")
    assert result.returncode == 0, result.stderr[-2000:]
    assert "uavdamp plan: 72 grid points, 162.963 simulated s of helicopter, 180 study runs: about" in result.stderr


def _refused(workdir, *args: str) -> str:
    """A dry run that must be refused before any job: its output."""
    result = snakemake_dry(workdir, "-n", "-j1", *args)
    output = result.stdout + result.stderr
    assert result.returncode != 0, output[-2000:]
    assert "Building DAG" not in output and "rule " not in output, output[-2000:]
    return output


def test_a_duplicated_yaml_key_is_refused_naming_the_file_and_the_lines(workdir):
    """Snakemake's YAML reader keeps the last of two equal keys without a word."""
    (workdir / "config" / "bad.yaml").write_text("study:\n  duration_s: 2.0\n  duration_s: 3.0\n")
    output = _refused(workdir, "all", "--configfile", "config/quick.yaml", "config/bad.yaml")
    assert "config/bad.yaml, line 3, column 3: duplicate key 'duration_s' (first given on line 2)" in output, output


def test_a_yaml_error_in_the_base_config_names_the_file_and_the_line(tmp_path):
    work = copy_workflow(tmp_path)
    path = work / "config" / "config.yaml"
    lines = path.read_text().splitlines()
    number = next(i for i, line in enumerate(lines) if line.startswith("  duration_s: 5.0"))
    lines[number] = lines[number].replace("duration_s: 5.0", "duration_s: [5.0", 1)
    path.write_text("\n".join(lines) + "\n")
    output = _refused(work, "all")
    # libyaml says "did not find expected ',' or ']'", PyYAML's own parser "expected ',' or ']', but got ..."
    assert re.search(rf"config/config.yaml, line {number + 2}, column 3: [^\n]*expected ',' or '\]'", output), output


def test_the_benchmark_counts_in_the_budget_when_it_is_requested(workdir):
    """1.2 CPU min: the quick study fits, the study and the benchmark do not (tests/test_budget.py counts them)."""
    (workdir / "config" / "bad.yaml").write_text(yaml.safe_dump({"budget": {"max_cpu_hours": 0.02}}))
    args = ("--configfile", "config/quick.yaml", "config/bad.yaml")
    study = snakemake_dry(workdir, "-n", "-j1", "all", *args)
    assert study.returncode == 0, study.stderr[-2000:]
    assert "benchmark runs" not in study.stderr
    output = _refused(workdir, "all", "benchmark", *args)
    assert "budget.max_cpu_hours: the run is estimated at" in output and "benchmark 181 runs" in output, output


def test_a_key_typo_is_refused_in_a_few_lines_with_the_nearest_key(workdir):
    """Not Snakemake's schema dump (~300 lines): the key, the nearest valid key and the rule."""
    (workdir / "config" / "bad.yaml").write_text(yaml.safe_dump({"study": {"duraton_s": 2.0}}))
    output = _refused(workdir, "all", "--configfile", "config/quick.yaml", "config/bad.yaml")
    message = (
        "study.duraton_s: unknown key; did you mean study.duration_s? study takes only its own keys "
        "(workflow/schemas/config.schema.yaml, config/README.md)"
    )
    assert message in output, output
    # 15 lines from a new process, which prints two lines of Exudyn's import first; in-process they are not there
    assert len(output.strip().splitlines()) <= 13, output


def test_a_config_error_prints_its_message_alone_and_its_traceback_on_request(workdir, monkeypatch):
    """The key and the rule it breaks, no frame of the checks; UAVDAMP_DEBUG=1 brings the frames back."""
    (workdir / "config" / "bad.yaml").write_text(yaml.safe_dump({"study": {"passive_damping_n_s_m": -3.0}}))
    args = ("all", "--configfile", "config/quick.yaml", "config/bad.yaml")
    output = _refused(workdir, *args)
    message = "config error: study.passive_damping_n_s_m: -3.0 is less than the minimum of 0"
    assert message in output and "(traceback: UAVDAMP_DEBUG=1)" in output, output
    assert 'File "' not in output and "Traceback" not in output, output
    monkeypatch.setenv("UAVDAMP_DEBUG", "1")
    output = _refused(workdir, *args)
    assert 'uavdamp/config/checks.py", line' in output, output
