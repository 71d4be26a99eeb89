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


RECOVERY = 'pgrep -af "$(pwd -P)/.snakemake/scripts"'


def test_the_recovery_command_lists_this_checkouts_running_job_only(tmp_path):
    """The README's and the guide's command, run in one of two run directories each with a live Snakemake script
    job, lists that directory's job and not the other's (the unscoped `pgrep -af '.snakemake/scripts'` lists both)."""
    import os
    import signal
    import subprocess
    import sys
    import time

    for doc in (ROOT / "README.md", ROOT / "docs" / "getting-started.md"):
        text = doc.read_text()
        assert RECOVERY in text and "pgrep -af '.snakemake/scripts'" not in text, doc
    runs = {}
    for name in ("this", "other"):
        work = tmp_path / name
        work.mkdir()
        (work / "Snakefile").write_text('rule a:\n    output: "done"\n    script: "wait.py"\n')
        (work / "wait.py").write_text("import time\ntime.sleep(60)\n")
        runs[name] = subprocess.Popen(
            [sys.executable, "-m", "snakemake", "-j1"],
            cwd=work,
            start_new_session=True,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    try:
        found = ""
        for _ in range(120):
            listing = subprocess.run(["pgrep", "-af", ".snakemake/scripts"], capture_output=True, text=True).stdout
            if all(f"{tmp_path.resolve() / n}/.snakemake/scripts" in listing for n in runs):
                found = subprocess.run(
                    ["bash", "-c", RECOVERY], cwd=tmp_path / "this", capture_output=True, text=True
                ).stdout
                break
            time.sleep(0.5)
        assert "wait.py" in found and f"{tmp_path.resolve()}/this/.snakemake/scripts" in found, found
        assert f"{tmp_path.resolve()}/other/" not in found
    finally:
        for proc in runs.values():
            os.killpg(proc.pid, signal.SIGKILL)  # the groups this test started: Snakemake and its script job
            proc.wait(30)
