"""The summary rule's results page against the NetCDF values it is generated from (the quick run's outputs)."""

from __future__ import annotations

import numpy as np
import pytest

from uavdamp import io, summary


@pytest.fixture(scope="module")
def outputs(quick_run):
    base = quick_run / "reports-quick"
    paths = {
        "comparison": "study/comparison.nc",
        "table": "reference_table/table.nc",
        "stroke": "reference_table/stroke.nc",
        "training": "anfis/training.nc",
        "modes": "platform/modes.nc",
        "vibration": "helicopter/vibration.nc",
    }
    return base, {role: io.open_dataset(base / path) for role, path in paths.items()}


def _cells(markdown: str, section: str) -> dict[str, list[str]]:
    """The rows of the table under heading `section`: {row label: its cells}."""
    text = markdown.split(f"## {section}\n", 1)[1].split("\n## ", 1)[0]
    rows = [line.strip().strip("|").split("|") for line in text.splitlines() if line.startswith("|")][2:]
    return {cells[0].strip(): [c.strip() for c in cells[1:]] for cells in rows}


def test_the_study_table_is_the_comparison_values(outputs):
    base, ds = outputs
    page = (base / "summary.md").read_text()
    comparison = ds["comparison"]
    rows = _cells(page, "Closed-loop study")
    case, k = str(comparison.case.values[0]), float(comparison.stiffness.values[0])
    for strategy in ("passive", "anfis", "rigid"):
        cells = rows[f"('{case}', {k}, '{strategy}')"]
        std_y = 1e3 * float(comparison.std_total.sel(case=case, stiffness=k, strategy=strategy, axis="y"))
        assert float(cells[0]) == pytest.approx(std_y, rel=5e-4)  # 4 significant digits
        los = 1e3 * float(comparison.los_std.sel(case=case, stiffness=k, strategy=strategy))
        assert float(cells[2]) == pytest.approx(los, rel=5e-4)


def test_the_other_tables_and_the_headline_are_the_datasets_values(outputs):
    base, ds = outputs
    page = (base / "summary.md").read_text()
    modes = _cells(page, "Platform: the clamped modes")
    for n, f in enumerate(ds["modes"].natural_frequency.values, start=1):
        assert float(modes[str(n)][0]) == pytest.approx(f, rel=5e-4)
    table = _cells(page, "Reference table")
    for k, sag in zip(ds["stroke"].stiffness.values, ds["stroke"].static_sag.values, strict=True):
        assert float(table[f"{k:g}"][2]) == pytest.approx(1e3 * sag, rel=5e-4)
    numbers = summary.headline(ds["comparison"])
    c = ds["comparison"].sel(stiffness=numbers["stiffness_n_m"])
    case = str(c.case.values[0])
    expected = float(c.los_std.sel(case=case, strategy="anfis") / c.los_std.sel(case=case, strategy="passive")) - 1
    assert numbers[f"{case}_anfis_vs_passive_los"] == pytest.approx(expected, rel=1e-12)
    assert f'"{case}_anfis_vs_passive_los": {expected!r}'[:40] in page  # the JSON block holds it
    assert "commit:" in page and "config sha256" in page


def test_the_report_landing_item_is_the_same_tables(outputs):
    base, ds = outputs
    html = (base / "summary.html").read_text()
    assert html.count("<table") == len(summary.summary_tables(ds))
    assert np.isfinite(summary.study_table(ds["comparison"]).to_numpy(dtype=float, na_value=np.nan)).any()
