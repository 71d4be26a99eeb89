"""The Snakemake workflow: lint, formatting, config validation, an end-to-end quick run, CF compliance."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import compliance_checker.cf.util as cf_util
import numpy as np
import pytest
import yaml
from compliance_checker.cf import cf_base
from compliance_checker.runner import CheckSuite, ComplianceChecker
from conftest import QUICK_RUN_ARGS, ROOT, copy_workflow, snakemake_dry

from uavdamp import io


@pytest.mark.slow
def test_snakemake_lint_clean(tmp_path):
    result = snakemake_dry(copy_workflow(tmp_path), "--lint")
    assert result.returncode == 0, result.stdout + result.stderr
    assert "Lints for" not in result.stdout + result.stderr, result.stdout + result.stderr


def test_snakefmt_clean():
    snakefmt = shutil.which("snakefmt", path=str(Path(sys.executable).parent)) or shutil.which("snakefmt")
    assert snakefmt, "snakefmt is a test dependency"
    files = [ROOT / "workflow" / "Snakefile", *sorted((ROOT / "workflow" / "rules").glob("*.smk"))]
    result = subprocess.run([snakefmt, "--check", *map(str, files)], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr


def _bad(config: dict, path: list[str], value) -> dict:
    node = config
    for key in path[:-1]:
        node = node[key]
    if value is KeyError:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return config


@pytest.mark.parametrize(
    "path, value, named",
    [
        (["helicopter", "fuselage", "mass_kg"], -2200.0, "helicopter.fuselage.mass_kg: must be > 0"),
        (["helicopter", "main_rotor", "n_blades"], "four", "helicopter.main_rotor.n_blades: expected an integer"),
        (["helicopter", "main_rotor", "omega_rad_s"], KeyError, "helicopter.main_rotor.omega_rad_s: missing key"),
        (["helicopter", "solver", "step_s"], 0.0, "helicopter.solver.step_s: must be > 0"),
        (
            ["helicopter", "main_rotor", "blade_lenght_m"],
            4.91,
            "helicopter.main_rotor.blade_lenght_m: unknown key; did you mean helicopter.main_rotor.blade_length_m?",
        ),
        (
            ["helicopter", "fuselage", "mass"],
            2200.0,
            "helicopter.fuselage.mass: renamed to helicopter.fuselage.mass_kg",
        ),
    ],
    ids=["negative-mass", "wrong-type", "missing-key", "zero-step", "misspelt-key", "old-key-name"],
)
@pytest.mark.slow
def test_bad_config_refused_before_any_job(tmp_path, path, value, named):
    """A dry run in-process (`conftest.snakemake_dry`); tests/workflow/test_config_checks.py shows that a real run
    is refused in the same way, before any job."""
    workdir = copy_workflow(tmp_path)
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    (workdir / "config" / "config.yaml").write_text(yaml.safe_dump(_bad(config, path, value)))
    result = snakemake_dry(workdir, "-n", "-j1", "all")
    output = result.stdout + result.stderr
    assert result.returncode != 0
    assert named in output, output[-2000:]
    assert "Building DAG" not in output, output[-2000:]
    assert len(output.splitlines()) < 40, output  # a few lines naming the key, not a schema dump
    assert not (workdir / "reports").exists()


def test_quick_study_end_to_end(quick_run):
    vib = io.open_dataset(quick_run / "reports-quick/helicopter/vibration.nc")
    assert set(vib.rotor.values) == {"balanced", "imbalanced", "hover", "forward"}  # the vacuum and the flight runs
    assert list(vib.axis.values) == ["x", "y", "z"]
    assert vib.mount_displacement.dims == ("rotor", "mount", "axis", "time")
    assert vib.dominant_omega.attrs["units"] == "rad s-1"
    omega = yaml.safe_load((ROOT / "config/config.yaml").read_text())["helicopter"]["main_rotor"]["omega_rad_s"]
    # even the 4 s quick record puts the lateral vibration at the 1/rev imbalance frequency
    assert float(vib.dominant_omega.sel(rotor="imbalanced", mount="cg", axis="y")) == pytest.approx(omega, rel=0.02)
    imbalanced = np.abs(vib.mount_displacement.sel(rotor="imbalanced")).max()
    balanced = np.abs(vib.mount_displacement.sel(rotor="balanced")).max()
    assert float(balanced) < 1e-6 * float(imbalanced)
    config = io.read_config_attr(vib, "helicopter")
    assert config["solver"]["duration_s"] == 4.0  # the quick override reached the job
    assert (quick_run / "reports-quick/figures/fuselage_vibration.png").stat().st_size > 10_000
    assert (quick_run / "reports-quick/logs/helicopter_vibration.log").exists()
    assert (quick_run / "reports-quick/benchmarks/helicopter_run_imbalanced.tsv").exists()
    # the flight runs: trimmed (trim.nc, one row per flight condition), their lines at 1/rev too
    trim = io.open_dataset(quick_run / "reports-quick/helicopter/trim.nc")
    assert list(trim.flight.values) == ["hover", "forward"] and bool((trim.trim_converged == 1).all())
    assert trim.collective.attrs["units"] == "rad" and trim.main_power.attrs["units"] == "W"
    assert float(vib.dominant_omega.sel(rotor="hover", mount="cg", axis="y")) == pytest.approx(omega, rel=0.02)


def _cf_errors(path: Path, report: Path) -> tuple[int, list]:
    """(number of high-priority CF 1.11 checks, the failed ones) of one file, by compliance-checker's own runner."""
    ComplianceChecker.run_checker(
        str(path), ["cf:1.11"], 0, "normal", output_filename=str(report), output_format="json"
    )
    result = json.loads(report.read_text())["cf:1.11"]
    return len(result["high_priorities"]), [c for c in result["high_priorities"] if c["value"][0] < c["value"][1]]


def _geophysical_vars(self, ds, refresh=False):
    """`CFBaseCheck._find_geophysical_vars` with its cache hit: compliance-checker 6.1 stores the list under
    str(ds) and looks it up under ds, so it recomputed it about nine times a file (the same reports on the quick run's
    47 files, 14.6 -> 9.5 s, measured)."""
    key = str(ds)
    if refresh or key not in self._geophysical_vars:
        self._geophysical_vars[key] = cf_util.get_geophysical_variables(ds)
    return self._geophysical_vars[key]


def test_every_netcdf_passes_cf_checker(quick_run, tmp_path, monkeypatch):
    """Every NetCDF the quick run writes passes compliance-checker's CF 1.11 high-priority checks (its runner in this
    process, the checkers loaded once: one `cchecker.py` process per file cost 1.5 s of start-up each)."""
    files = sorted((quick_run / "reports-quick").rglob("*.nc"))
    assert files
    monkeypatch.setattr(cf_base.CFBaseCheck, "_find_geophysical_vars", _geophysical_vars)
    CheckSuite().load_all_available_checkers()
    for k, path in enumerate(files):
        checks, errors = _cf_errors(path, tmp_path / f"{k}.json")
        assert checks and errors == [], f"{path.name}: {errors}"


def test_config_edit_reruns_only_affected_rules(quick_run, tmp_path):
    """Editing the spectrum options reruns the spectrum rule, not the 2 simulations."""
    config = {"helicopter": {"spectrum": {"min_omega_rad_s": 25.0}}}  # merged over the quick run's config files
    edited = quick_run / "config" / "edited.yaml"
    edited.write_text(yaml.safe_dump(config))
    result = snakemake_dry(quick_run, "-n", "-j1", "all", *QUICK_RUN_ARGS, "config/edited.yaml")
    assert result.returncode == 0, result.stderr
    plan = result.stdout + result.stderr
    assert "helicopter_vibration" in plan
    assert "helicopter_run" not in plan


def test_the_quick_config_writes_nothing_into_the_default_output_folder(quick_run):
    """config/quick.yaml's output_dir keeps a test run apart from the study's results (reports/)."""
    assert (quick_run / "reports-quick" / "study" / "comparison.nc").exists()
    assert not (quick_run / "reports").exists()
