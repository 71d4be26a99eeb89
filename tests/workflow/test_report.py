"""The README's report command, run as written after the quick run: the report is made, its first page holds the
run's findings, its entries are titled, and it holds every figure of the run with its caption rendered from the
config."""

from __future__ import annotations

import re
import shlex

from conftest import QUICK_RUN_ARGS, ROOT, snakemake


def readme_report_commands() -> list[list[str]]:
    """The README's `snakemake --report ...` commands (its table of targets), as argument lists."""
    found = re.findall(r"`(snakemake --report [^`]+)`", (ROOT / "README.md").read_text())
    return [shlex.split(command) for command in found]


def test_the_readme_names_a_report_command_per_output_folder():
    commands = readme_report_commands()
    folders = {words[words.index("--report") + 1].split("/")[0] for words in commands}
    assert folders == {"reports", "reports-quick"}


def test_the_readme_report_command_works_after_the_quick_run(quick_run):
    (words,) = [w for w in readme_report_commands() if "config/quick.yaml" in w]
    extra = list(QUICK_RUN_ARGS[2:])  # the session's run also has the plug-in override after quick.yaml
    at = words.index("config/quick.yaml") + 1
    result = snakemake(quick_run, *words[1:at], *extra, *words[at:])
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    report = (quick_run / words[words.index("--report") + 1]).read_text()
    landing = (quick_run / "reports-quick" / "report_landing.rst").read_text()
    first = next(line for line in landing.splitlines() if line.startswith("- **"))
    assert "Findings" in report and first.split("** ", 1)[1][:40] in report  # the first page: the findings
    assert "Fig. 10: rigid mount, camera Y" in report  # entries titled, not file paths
    assert '"0 Summary"' not in report and "Summary" in report
    figures = sorted(p.name for p in (quick_run / "reports-quick/figures").rglob("*.png"))
    assert len(figures) >= 12, figures
    missing = [name for name in [*figures, "rules.md"] if name not in report]
    assert not missing, f"not in the report: {missing}"
    assert "passive damper (constant C = 2.0 N s/m)" in report  # captions rendered from the config (Jinja)
    assert "Stages:" in report  # the workflow description page
