"""The documentation's copies of generated files, written into the pages so that they read the same on the site
and on the code host (a snippet include shows there as a literal `--8<--` line).

Each copy sits between a BEGIN and an END marker naming its source: `docs/configuration.md` holds
`config/README.md`, `docs/cluster.md` the SLURM profile, `docs/results.md` a run's `summary.md` (its figures copied
into `docs/results/figures/`, the links rewritten). `python -m uavdamp.results.publish` refreshes the first two;
`python -m uavdamp.results.publish reports` also publishes the default run's summary. tests/test_docs.py checks
that the first two are current and that every link of the results page resolves.
"""

from __future__ import annotations

import re
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
# page -> (source, fenced as): the copies refreshed from tracked files
COPIES = {
    "docs/configuration.md": ("config/README.md", None),
    "docs/cluster.md": ("profiles/slurm/config.v9+.yaml", "yaml"),
}
RESULTS_PAGE, RUN_SOURCE = "docs/results.md", "summary.md"
FIGURES = "results/figures"  # relative to docs/: where the published run's figures go
_IMAGE = re.compile(r"(!\[[^\]]*\]\()figures/([^)\s]+)\)")


def markers(source: str) -> tuple[str, str]:
    """The BEGIN and END lines around the copy of `source` (a path relative to the repository)."""
    begin = f"<!-- BEGIN COPY of {source}: python -m uavdamp.results.publish writes it; edit the source -->"
    return begin, f"<!-- END COPY of {source} -->"


def with_copy(page: str, source: str, content: str, fence: str | None = None) -> str:
    """`page` with the text between the markers of `source` replaced by `content` (fenced as `fence` if set).
    ValueError naming the source when the page lacks its markers."""
    begin, end = markers(source)
    if begin not in page or end not in page:
        raise ValueError(f"the page has no markers for {source} ({begin!r} ... {end!r})")
    head, rest = page.split(begin, 1)
    tail = rest.split(end, 1)[1]
    body = f"```{fence}\n{content.rstrip()}\n```" if fence else content.rstrip()
    return f"{head}{begin}\n\n{body}\n\n{end}{tail}"


def copied(page: str, source: str) -> str:
    """The copy of `source` held in `page` (between its markers, unfenced), as written."""
    begin, end = markers(source)
    body = page.split(begin, 1)[1].split(end, 1)[0].strip("\n")
    fenced = re.fullmatch(r"```\w*\n(.*)\n```", body, re.S)
    return fenced.group(1) if fenced else body


def run_page(summary: str) -> tuple[str, list[str]]:
    """(the summary's text with its figure links pointing into docs/results/figures and its headings one level
    down, the figures it links, relative to the run's folder)."""
    figures = [f"figures/{m.group(2)}" for m in _IMAGE.finditer(summary)]
    text = _IMAGE.sub(lambda m: f"{m.group(1)}{FIGURES}/{m.group(2)})", summary)
    return re.sub(r"^#", "##", text, flags=re.M), figures  # its headings one level below the page's title


def refresh(root: Path = ROOT) -> list[Path]:
    """Rewrite every copy of COPIES from its source; return the pages written."""
    written = []
    for page, (source, fence) in COPIES.items():
        path = root / page
        path.write_text(with_copy(path.read_text(), source, (root / source).read_text(), fence))
        written.append(path)
    return written


def publish_run(run_dir: Path, root: Path = ROOT) -> Path:
    """Copy `run_dir`/summary.md into docs/results.md and the figures it links into docs/results/figures/
    (the folder emptied first, so that no figure of an earlier run stays). FileNotFoundError names a missing one."""
    run_dir = Path(run_dir)
    text, figures = run_page((run_dir / RUN_SOURCE).read_text())
    missing = [f for f in figures if not (run_dir / f).is_file()]
    if missing:
        raise FileNotFoundError(f"{run_dir / RUN_SOURCE} links figures the run has not written: {missing}")
    target = root / "docs" / FIGURES
    shutil.rmtree(target, ignore_errors=True)
    for figure in figures:
        (target / figure.removeprefix("figures/")).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(run_dir / figure, target / figure.removeprefix("figures/"))
    page = root / RESULTS_PAGE
    page.write_text(with_copy(page.read_text(), f"reports/{RUN_SOURCE}", text))
    return page


if __name__ == "__main__":  # python -m uavdamp.results.publish [RUN_DIR]
    for written in refresh():
        print(f"wrote {written.relative_to(ROOT)}")
    if len(sys.argv) > 1:
        print(f"wrote {publish_run(Path(sys.argv[1])).relative_to(ROOT)}")
