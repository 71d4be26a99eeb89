"""The README's quick start stays true: CI runs its test command verbatim."""

from conftest import ROOT


def _command_lines(text: str) -> list[str]:
    return [line.strip() for line in text.splitlines() if line.strip().startswith("python3 -m venv")]


def test_ci_runs_the_readme_test_command():
    readme = _command_lines((ROOT / "README.md").read_text())
    ci = _command_lines((ROOT / ".ci" / "run").read_text())
    assert len(readme) == 2, "quick start: one command for the study, one for the tests"
    assert len(ci) == 1 and ci[0] in readme
    assert "pytest" in ci[0] and "snakemake -j2 all" in [r for r in readme if r != ci[0]][0]
