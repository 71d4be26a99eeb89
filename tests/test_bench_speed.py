"""benchmarks/bench_speed.py: with --vs, two commits timed in turn, each in a fresh clone at its commit."""

from __future__ import annotations

import subprocess
import sys

import pytest
from conftest import ROOT, load_module

bs = load_module(ROOT / "benchmarks/bench_speed.py", "uavdamp_bench_speed")


def test_the_two_commits_take_turns_going_first():
    """HEAD first in the first repeat, the other commit in the second, and so on: a machine that slows down through
    a pair does not always count against the same commit."""
    assert [bs.order(["HEAD", "abc"], k) for k in range(3)] == [["HEAD", "abc"], ["abc", "HEAD"], ["HEAD", "abc"]]
    assert bs.order(["HEAD"], 1) == ["HEAD"]


def _git(cwd, *args) -> str:
    return subprocess.run(["git", *args], cwd=cwd, capture_output=True, text=True, check=True).stdout.strip()


def test_a_clone_at_a_commit_holds_that_commit_and_a_bad_one_is_named(tmp_path, monkeypatch):
    """`clone` checks out the commit asked for (the first of a two-commit repository here: a clone left at HEAD would
    time the wrong code); a --vs that names no commit stops before any run, naming it."""
    repo = tmp_path / "repo"
    repo.mkdir()
    _git(repo, "init", "-q")
    for text in ("first", "second"):
        (repo / "f.txt").write_text(text)
        _git(repo, "add", "f.txt")
        _git(repo, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", text)
    monkeypatch.setattr(bs, "ROOT", repo)
    first = _git(repo, "rev-parse", "HEAD~1")
    work = bs.clone(tmp_path / "c", first)
    assert (work / "f.txt").read_text() == "first" and _git(work, "rev-parse", "HEAD") == first
    assert (bs.clone(tmp_path / "d") / "f.txt").read_text() == "second"
    assert bs.short("HEAD~1") == _git(repo, "rev-parse", "--short", "HEAD~1")
    with pytest.raises(SystemExit, match="--vs no-such-commit: not a commit of"):
        bs.short("no-such-commit")


def test_a_vs_that_names_heads_own_commit_is_refused_before_any_clone():
    """Comparing HEAD with itself would time one commit twice and call it a pair: refused, naming the commit."""
    done = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks/bench_speed.py"), "--only", "tests", "--vs", "HEAD"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode != 0 and "--vs HEAD: names HEAD's own commit" in done.stderr
