"""Shared fixtures: configs, and a scratch copy of the workflow for Snakemake runs."""

from __future__ import annotations

import copy
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]


def deep_update(base: dict, override: dict) -> dict:
    """Snakemake's merge of --configfile over configfile: nested dicts merged, the rest replaced."""
    out = copy.deepcopy(base)
    for key, value in override.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = deep_update(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def load_config(name: str = "config.yaml") -> dict:
    """config/config.yaml, or it merged with an override file such as quick.yaml."""
    base = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    if name == "config.yaml":
        return base
    return deep_update(base, yaml.safe_load((ROOT / "config" / name).read_text()))


@pytest.fixture(scope="session")
def default_config() -> dict:
    return load_config()


@pytest.fixture(scope="session")
def quick_config() -> dict:
    return load_config("quick.yaml")


def copy_workflow(dest: Path) -> Path:
    """Copy what Snakemake needs (Snakefile, workflow/, config/) into `dest`; return it."""
    dest.mkdir(parents=True, exist_ok=True)
    shutil.copy(ROOT / "Snakefile", dest / "Snakefile")
    for folder in ("workflow", "config"):
        shutil.copytree(ROOT / folder, dest / folder, ignore=shutil.ignore_patterns("__pycache__"))
    return dest


def snakemake(workdir: Path, *args: str, timeout: float = 1800) -> subprocess.CompletedProcess:
    """Run Snakemake in `workdir` with this interpreter; output captured as text."""
    env = dict(os.environ)
    return subprocess.run(
        [sys.executable, "-m", "snakemake", *args],
        cwd=workdir,
        capture_output=True,
        text=True,
        timeout=timeout,
        env=env,
    )


def planned_rules(result: subprocess.CompletedProcess) -> set[str]:
    """The rules in a Snakemake dry run's job-count table (empty when there is nothing to be done)."""
    plan = result.stdout + result.stderr
    if "Nothing to be done" in plan:
        return set()
    table = plan[plan.index("job ") : plan.index("total")]
    return {line.split()[0] for line in table.splitlines()[2:] if line.strip()}


@pytest.fixture(scope="session")
def quick_run(tmp_path_factory) -> Path:
    """The quick config run from nothing through `all` and `benchmark` (the README's targets), once per session."""
    workdir = copy_workflow(tmp_path_factory.mktemp("quick"))
    result = snakemake(workdir, "-j2", "all", "benchmark", "--configfile", "config/quick.yaml")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-6000:]
    return workdir
