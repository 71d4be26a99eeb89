"""The documentation site builds with `mkdocs build --strict` (broken links, missing pages and missing snippets
fail), offline: no plugin that fetches at build time, no web font or script from another site."""

from __future__ import annotations

import importlib
import os
import re
import subprocess
import sys
import time

import pytest
import yaml
from conftest import ROOT

from uavdamp.results import publish

OFFLINE_ONLY = {"social", "privacy", "optimize"}  # mkdocs-material plugins that download or need network tools


def _nav_pages(nav) -> list[str]:
    pages = []
    for item in nav:
        value = next(iter(item.values())) if isinstance(item, dict) else item
        pages += _nav_pages(value) if isinstance(value, list) else [value]
    return pages


def _config() -> dict:
    return yaml.safe_load((ROOT / "mkdocs.yml").read_text())


def _html(site, page: str):
    """Where mkdocs writes a page (directory URLs): docs/a/b.md -> site/a/b/index.html, a/index.md -> a/index.html."""
    stem = page.removesuffix(".md").removesuffix("index").rstrip("/")
    return site / stem / "index.html" if stem else site / "index.html"


def test_the_site_builds_strict_and_offline(tmp_path):
    config = _config()
    plugins = {next(iter(p)) if isinstance(p, dict) else p for p in config.get("plugins", [])}
    assert not plugins & OFFLINE_ONLY, f"plugins that fetch at build time: {sorted(plugins & OFFLINE_ONLY)}"
    assert config["theme"].get("font") is False, "theme.font: false (no Google Fonts request)"
    site = tmp_path / "site"
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    start = time.perf_counter()
    result = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    seconds = time.perf_counter() - start
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-6000:]
    assert seconds < 60, f"the docs build took {seconds:.0f} s (keep it under about 30 s)"
    for page in _nav_pages(config["nav"]):
        assert _html(site, page).exists(), f"{page} did not render ({_html(site, page).relative_to(site)})"
    external = set()
    for html in site.rglob("*.html"):
        text = html.read_text()
        external |= set(re.findall(r'<(?:script|img)[^>]*\bsrc="(https?://[^"]+)"', text))
        external |= set(re.findall(r'<link[^>]*\bhref="(https?://[^"]+)"', text))
    assert not external, f"the site loads assets from the network: {sorted(external)[:5]}"


def test_every_docs_page_is_in_the_navigation():
    pages = set(_nav_pages(_config()["nav"]))
    excluded = [line.strip() for line in _config().get("exclude_docs", "").splitlines() if line.strip()]
    files = {str(p.relative_to(ROOT / "docs")) for p in (ROOT / "docs").rglob("*.md")}
    files = {f for f in files if not any(f.startswith(e) for e in excluded)}  # snippets, not pages
    assert files == pages, (
        f"in docs/ but not in mkdocs.yml's nav: {sorted(files - pages)}; missing: {sorted(pages - files)}"
    )


def test_no_page_includes_a_file_the_code_host_would_show_as_a_literal_line():
    """A snippet include (`--8<--`) renders on the code host as the literal line (the results page once did):
    every page holds its copies as text (`uavdamp.results.publish`)."""
    pages = [ROOT / "README.md", *(ROOT / "docs").rglob("*.md")]
    literal = [str(p.relative_to(ROOT)) for p in pages if re.search(r"^\s*--8<--", p.read_text(), flags=re.M)]
    assert literal == []


@pytest.mark.parametrize("page", sorted(publish.COPIES))
def test_every_copy_in_the_docs_is_its_source_as_it_is_now(page):
    """docs/configuration.md holds config/README.md, docs/cluster.md the SLURM profile, each exactly (seen failing
    with a key added to config/README.md and the copy left as it was)."""
    source, _ = publish.COPIES[page]
    assert publish.copied((ROOT / page).read_text(), source) == (ROOT / source).read_text().rstrip()


def test_the_results_page_is_a_run_summary_whose_figures_are_in_the_docs():
    """docs/results.md holds a run's summary (its heading and provenance lines) and every figure it embeds lies in
    docs/results/figures/, so the page shows them on the code host and on the site."""
    text = (ROOT / "docs" / "results.md").read_text()
    run = publish.copied(text, "reports/summary.md")
    assert run.startswith("## Results of the run") and "- commit: `" in run
    images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", run)
    assert images and all(i.startswith(publish.FIGURES + "/") for i in images), images
    assert [i for i in images if not (ROOT / "docs" / i).is_file()] == []


def test_every_docs_page_named_in_the_config_code_and_rules_exists():
    """A `docs/....md` path in the README, a config comment, a module, a script, a rule or a report caption names a
    real page (mkdocs checks links inside docs/ only; config/config.yaml once pointed at a moved page)."""
    sources = [
        ROOT / "README.md",
        *(ROOT / "config").glob("*.yaml"),
        *(ROOT / "src").rglob("*.py"),
        *(ROOT / "workflow").rglob("*"),
    ]
    named = {
        (path.relative_to(ROOT), page)
        for path in sources
        if path.is_file() and path.suffix in {".md", ".yaml", ".py", ".smk", ".rst", ""}
        for page in re.findall(r"\bdocs/[\w/.-]+?\.md\b", path.read_text(errors="ignore"))
    }
    assert named, "no docs/ path found: the pattern is wrong"
    missing = sorted((str(path), page) for path, page in named if not (ROOT / page).is_file())
    assert not missing, f"pages named but absent (file, page): {missing}"


PROSE = (
    "README.md",
    "docs/**/*.md",
    "config/*.yaml",
    "workflow/**/*",
    "src/**/*.py",
    "pyproject.toml",
)
PATH = re.compile(r"(?<![\w/.-])((?:src|tests|workflow|docs|config|data|benchmarks|examples|profiles)/[\w/.+-]*\w)")


def _prose_files():
    for pattern in PROSE:
        yield from (
            p
            for p in ROOT.glob(pattern)
            if p.is_file() and p.suffix in {".md", ".yaml", ".py", ".smk", ".rst", ".toml", ""}
        )


def test_every_path_named_in_prose_exists():
    """A repository path (src/..., tests/..., workflow/..., docs/..., config/..., data/...) named in the README, the
    docs, a config comment, the schema, a rule or a docstring names a file or folder that exists: after
    the modules moved into packages, a path left behind points nowhere. Paths with a placeholder are skipped."""
    missing = set()
    for path in _prose_files():
        for named in PATH.findall(path.read_text(errors="ignore")):
            named = named.rstrip(".")
            if re.search(r"[A-Z]{3,}|\{|\*|<|NAME", named) or named.startswith("config/my"):
                continue
            if not (ROOT / named).exists():
                missing.add((str(path.relative_to(ROOT)), named))
    assert not sorted(missing), f"named but absent (file, path): {sorted(missing)}"


def _modules() -> list[str]:
    src = ROOT / "src"
    names = []
    for path in sorted((src / "uavdamp").rglob("*.py")):
        parts = path.relative_to(src).with_suffix("").parts
        names.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


def test_every_module_is_mapped_and_in_the_api_reference():
    """docs/architecture.md names every module of src/uavdamp (private ones too), and the API pages document every
    public one (`::: module`): a module added without its place on the map fails here."""
    architecture = (ROOT / "docs" / "architecture.md").read_text()
    api = "\n".join(p.read_text() for p in (ROOT / "docs" / "api").glob("*.md"))
    documented = set(re.findall(r"^::: (\S+)$", api, flags=re.M))
    unmapped = [m for m in _modules() if m != "uavdamp" and f"`{m}`" not in architecture]
    undocumented = [m for m in _modules() if m != "uavdamp" and "._" not in m and m not in documented]
    assert (unmapped, undocumented) == ([], [])


DOTTED = re.compile(r"(?<![\w/.])uavdamp(?:\.[A-Za-z_]\w*)+")


def _resolves(dotted: str) -> bool:
    """`uavdamp.a.b.c` names an importable module, or an attribute of its longest importable prefix (a class's
    method included)."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for name in parts[cut:]:
            if not hasattr(obj, name):
                return False
            obj = getattr(obj, name)
        return True
    return False


def test_every_module_named_in_prose_exists():
    """A dotted name `uavdamp.x.y` in the README, the docs, a config comment, the schema, a rule or a docstring is an
    importable module or one of its attributes: after the modules moved into packages, `uavdamp.summary` or
    `uavdamp.strategies.describe` left behind names nothing (seen failing on both before they were mended)."""
    missing = set()
    for path in _prose_files():
        for named in DOTTED.findall(path.read_text(errors="ignore")):
            named = named.rstrip(".")
            if named.endswith((".py", ".nc", ".md", ".fis", ".yaml", ".egg")) or "__mutmut_" in named:
                continue
            if not _resolves(named):
                missing.add((str(path.relative_to(ROOT)), named))
    assert not sorted(missing), f"named but absent (file, dotted name): {sorted(missing)}"
