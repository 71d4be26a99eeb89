"""The documentation's runnable Python: docs/getting-started.md's "Opening a result" block, run on the session's
quick run with its paths pointed at reports-quick/ (it once read a variable the file does not hold)."""

from __future__ import annotations

import re

import matplotlib

matplotlib.use("Agg")

from conftest import ROOT  # noqa: E402

BLOCK = re.compile(r"```python\n(.*?)```", re.S)


def test_the_getting_started_example_opens_a_result(quick_run):
    text = (ROOT / "docs" / "getting-started.md").read_text()
    section = text.split("## Opening a result", 1)[1]
    (code,) = BLOCK.findall(section.split("\n## ", 1)[0])
    assert "reports/" in code
    code = code.replace('"reports/', f'"{quick_run}/reports-quick/')
    namespace: dict = {}
    exec(compile(code, "docs/getting-started.md", "exec"), namespace)  # the page's own example
    assert namespace["ds"].time.attrs["units"].startswith("s since")
