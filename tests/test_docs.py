"""The documentation site builds with `mkdocs build --strict` (broken links, missing pages and missing snippets
fail), offline: no plugin that fetches at build time, no web font or script from another site."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import time

import yaml
from conftest import ROOT

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


def test_the_configuration_page_includes_the_generated_key_reference():
    text = (ROOT / "docs" / "configuration.md").read_text()
    assert '--8<-- "config/README.md"' in text, "include config/README.md, do not copy it"
    assert "BEGIN GENERATED" not in text


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
