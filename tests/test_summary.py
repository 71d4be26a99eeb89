"""The results page: findings, descriptions, tables and figures from small constructed datasets (values known here),
the page as a real browser renders it, and the quick run's page against its NetCDF values."""

from __future__ import annotations

import io as bytes_io
import re
import shutil
import subprocess

import matplotlib
import numpy as np
import pytest
import xarray as xr
from conftest import apt_install

from uavdamp.results import page as page_blocks
from uavdamp.results import payload_page, summary
from uavdamp.results import render as summary_render
from uavdamp.study import comparison as study
from uavdamp.study.comparison import strategies

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CASES, KS, STRATEGIES = ["case1", "case2"], [10.0, 1000.0], ["rigid", "passive", "anfis"]
# blur p95 (px) and LOS std (rad) per (case, K, strategy): anfis beats passive by 0.5 px at (case1, 10)
BLUR = np.array([[[20.0, 10.5, 10.0], [20.0, 12.0, 12.5]], [[8.0, 5.0, 5.0], [8.0, 6.0, 6.3]]])
LOS = 1e-3 * np.array([[[40.0, 25.592, 25.590], [40.0, 28.0, 27.0]], [[15.0, 9.0, 9.5], [15.0, 11.0, 10.0]]])
STD = 1e-3 * np.array([[[0.7, 0.2, 0.22], [0.7, 0.5, 0.45]], [[0.3, 0.08, 0.09], [0.3, 0.2, 0.18]]])
STROKE = np.where(np.array(KS)[None, :, None] < 100, 1.7283, 0.0201) * np.ones(BLUR.shape)  # m
CASE_TEXT = {"case1": "imbalanced rotor, tail rotor stopped", "case2": "imbalanced rotor, tail rotor running"}
STRATEGY_TEXT = {"rigid": "no isolator", "passive": "constant C", "anfis": "the ANFIS schedule"}


def comparison(extra_dim: dict | None = None) -> xr.Dataset:
    """A comparison of the study's shape (case, stiffness, strategy, axis) with the values above."""
    dims = ("case", "stiffness", "strategy")
    stroke = np.stack([STROKE, 0.5 * STROKE], axis=-1)
    stroke[:, :, 0] = np.nan  # rigid: no isolator
    feasible = np.where(stroke.max(-1) <= 0.05, 1.0, 0.0)
    feasible[:, :, 0] = np.nan
    ds = xr.Dataset(
        {
            "blur_p95": (dims, BLUR, {"units": "1"}),
            "los_std": (dims, LOS, {"units": "rad"}),
            "std_total": ((*dims, "axis"), np.stack([STD, 2 * STD], axis=-1), {"units": "m"}),
            "stroke_needed": ((*dims, "axis"), stroke, {"units": "m"}),
            "stroke_feasible": (dims, feasible, {"units": "1"}),
        },
        coords={
            "case": CASES,
            "stiffness": ("stiffness", KS, {"units": "N m-1"}),
            "strategy": STRATEGIES,
            "axis": ["y", "z"],
            "case_description": ("case", [CASE_TEXT[c] for c in CASES]),
            "strategy_description": ("strategy", [STRATEGY_TEXT[s] for s in STRATEGIES]),
        },
        attrs={"git_commit": "abc123", "history": "2026-12-02T00:00:00Z snakemake rule study"},
    )
    if extra_dim:
        ds = ds.expand_dims(extra_dim, axis=0)
    return ds


def vibration() -> xr.Dataset:
    omega = np.array([[[0.0, 20.1, 20.1]], [[0.0, 44.43, 50.62]]])  # rotor x mount x axis (x, y, z)
    return xr.Dataset(
        {
            "dominant_omega": (("rotor", "mount", "axis"), omega, {"units": "rad s-1"}),
            "mass_imbalance_factor": ("rotor", [1.0, 0.5]),
            "flight": ("rotor", ["vacuum", "vacuum"]),
        },
        coords={"rotor": ["balanced", "imbalanced"], "mount": ["cg"], "axis": ["x", "y", "z"]},
    )


def benchmark_criteria() -> xr.Dataset:
    """The gather's shape: J_mean / J_worst over (controller, stiffness, criterion, damper); anfis not run on mr."""
    mean = np.array([[[[0.5, 0.6]]], [[[0.25, np.nan]]]])  # controller x stiffness x criterion x damper
    return xr.Dataset(
        {
            "J_mean": (("controller", "stiffness", "criterion", "damper"), mean),
            "J_worst": (("controller", "stiffness", "criterion", "damper"), 1.5 * mean),
        },
        coords={
            "controller": ["passive_tuned", "anfis"],
            "stiffness": ("stiffness", [10.0], {"units": "N m-1"}),
            "criterion": ["los_std"],
            "damper": ["ideal", "mr"],
            "scenario": ["s1", "s2", "s3"],
            "set": ("scenario", ["tuning", "evaluation", "evaluation"]),
        },
    )


def png(color: str) -> bytes:
    """A small PNG filled with one colour (a figure whose pixels the browser test can find)."""
    fig = plt.figure(figsize=(3, 2), dpi=50, facecolor=color)
    out = bytes_io.BytesIO()
    fig.savefig(out, format="png", facecolor=color)
    plt.close(fig)
    return out.getvalue()


@pytest.fixture(scope="module")
def page():
    outputs = {"comparison": comparison(), "vibration": vibration(), "benchmark": benchmark_criteria()}
    return summary.summary_page(outputs, {"blur": "figures/study_blur.png"})


def rows_of(markdown: str, title: str) -> list[list[str]]:
    """The cells of the table under heading `title`, header first."""
    text = markdown.split(f"## {title}\n", 1)[1].split("\n## ", 1)[0]
    lines = [line for line in text.splitlines() if line.startswith("|")]
    return [[c.strip() for c in line.strip().strip("|").split("|")] for line in lines[:1] + lines[2:]]


def test_numbers_have_their_digits_and_sign():
    assert page_blocks.fmt(1728.3446352924368) == "1728"
    assert page_blocks.fmt(0.0009024738307372715) == "0.0009025"
    assert page_blocks.fmt(10.0) == "10" and page_blocks.fmt(np.nan) == "-"
    assert page_blocks.signed(-0.0009024738307372715) == "-0.0009" and page_blocks.signed(0.0499) == "+0.05"


def test_the_findings_are_sentences_of_the_data(page):
    first = page.findings[0]  # case1, K = 10 N/m
    assert first.startswith("**case1, K = 10 N/m.**")
    # blur: anfis 10 px, passive 10.5 px: 0.5 px = 4.76 % of 10.5; rigid 20 px: 10 / 20 - 1 = -50 %
    assert "Blur p95: anfis lowest at 10 px, 0.5 px (4.8 %) below passive (10.5 px)" in first
    assert "rigid mount 20 px (best isolated -50 %)" in first
    # LOS 25.590 against 25.592 mrad: equal at four significant digits
    assert "Line-of-sight std: anfis and passive tie at 25.59 mrad" in first
    # ANFIS minus passive: blur 10 - 10.5 = -0.5 px (-4.8 %); camera std y 0.22 - 0.2 = +0.02 mm (+10 %)
    assert "blur p95 -0.5 px (-4.8 %)" in first and "camera std y +0.02 mm (+10 %)" in first
    assert "Stroke: no isolated strategy fits (1728 mm needed)." in first
    assert "Stroke: every isolated strategy fits (20.1 mm needed)." in page.findings[1]
    assert len(page.findings) == len(CASES) * len(KS)
    assert "{" not in summary_render.to_markdown(page)  # no JSON


def test_rows_are_labelled_by_their_dimensions_and_feasibility_is_words(page):
    rows = rows_of(summary_render.to_markdown(page), "Closed-loop study")
    assert rows[0][:3] == ["case", "K (N/m)", "strategy"]
    by_label = {tuple(r[:3]): r[3:] for r in rows[1:]}
    assert by_label[("case1", "10", "rigid")][-2:] == ["-", "-"]  # no isolator: no stroke, nothing to fit
    assert by_label[("case1", "10", "anfis")][-1] == "no" and by_label[("case1", "1000", "anfis")][-1] == "yes"
    assert float(by_label[("case2", "1000", "anfis")][2]) == pytest.approx(10.0)  # LOS std, mrad
    assert len(rows) - 1 == BLUR.size


def test_a_new_dimension_adds_a_column_and_rows():
    ds = comparison({"payload": ["light", "heavy"]})
    table = summary.study_table(ds)
    assert list(table.frame.columns[:4]) == ["payload", "case", "K (N/m)", "strategy"]
    assert len(table.frame) == 2 * BLUR.size and table.labels == 4
    assert summary.findings(ds)[0].startswith("**light, case1, K = 10 N/m.**")


def test_the_balanced_rotor_is_apart_from_the_paper_comparison(page):
    md = summary_render.to_markdown(page)
    compared = rows_of(md, "Helicopter: the imbalanced rotor's dominant lines against the paper's")
    assert [r[0] for r in compared[1:]] == ["imbalanced"]
    assert compared[1][compared[0].index("y minus paper (rad/s)")] == "+0.39"  # 44.43 - 44.04
    reference = rows_of(md, "Helicopter: the balanced rotor (reference)")
    assert reference[1][:2] == ["balanced", "cg"] and not any("paper" in c for c in reference[0])


def test_cases_and_strategies_are_described_from_the_dataset(page):
    described = dict(page.descriptions)
    assert described["Cases (the mount's input)"] == CASE_TEXT
    assert described["Damping strategies"] == STRATEGY_TEXT


def test_the_study_writes_the_descriptions_of_its_rows():
    @strategies.register("described_for_the_summary_test")
    def described(ctx):
        """A law a user wrote, in one sentence."""

    cases = xr.Dataset({"description": ("case", ["first input", "second input"])}, coords={"case": ["a", "b"]})
    coords = study.describe_rows(cases, ["described_for_the_summary_test"])
    assert list(coords["case_description"][1]) == ["first input", "second input"]
    assert coords["strategy_description"][1] == ["A law a user wrote, in one sentence."]


def test_the_benchmark_table_marks_runs_that_did_not_happen(page):
    rows = rows_of(summary_render.to_markdown(page), "Controller benchmark")
    by_label = {tuple(r[:3]): r[3] for r in rows[1:]}
    assert by_label[("anfis", "10", "ideal")] == "0.25 / 0.375"
    assert by_label[("anfis", "10", "mr")] == "-"
    assert "2 evaluation scenarios" in summary.benchmark_table(benchmark_criteria()).note


def test_figures_are_linked_in_markdown_and_embedded_in_html(page):
    md = summary_render.to_markdown(page)
    assert "![Image blur per strategy](figures/study_blur.png)" in md
    data = png("red")
    html = summary_render.to_html(page, {"figures/study_blur.png": data})
    src = re.search(r'<img src="data:image/png;base64,([^"]+)"', html).group(1)
    import base64

    assert base64.b64decode(src) == data


def test_the_html_is_a_standalone_styled_page(page):
    html = summary_render.to_html(page)
    assert html.startswith("<!doctype html>") and "</html>" in html and "<style>" in html
    assert "sans-serif" in html and "border=" not in html
    assert "<th></th>" not in html and html.count("<table>") == len(page.tables)


def chromium() -> str:
    """Debian's Chromium, installed with apt-get as the SLURM and fuzzylite tests install theirs."""
    binary = shutil.which("chromium")
    if binary is None:
        why = apt_install(["chromium"])
        if why == "not root":
            pytest.skip("Chromium is absent and cannot be installed without root")
        binary = shutil.which("chromium")
        assert binary is not None, f"apt-get install chromium: {why}"
    return binary


def headless(binary: str, tmp_path, *args: str) -> subprocess.CompletedProcess:
    flags = [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        f"--user-data-dir={tmp_path / 'profile'}",
    ]
    return subprocess.run([binary, *flags, *args], capture_output=True, text=True, timeout=180)


def test_a_browser_renders_the_page_with_its_tables_and_figure(page, tmp_path):
    """The page as headless Chromium shows it: every table in the DOM, and the embedded figure's colour (pure red,
    a colour nothing else on the page uses) in the screenshot, so the image decoded and was drawn."""
    binary = chromium()
    html = tmp_path / "summary.html"
    html.write_text(summary_render.to_html(page, {"figures/study_blur.png": png("#ff0000")}))
    shot = tmp_path / "summary.png"
    result = headless(binary, tmp_path, f"--screenshot={shot}", "--window-size=1200,2000", html.as_uri())
    assert shot.is_file(), result.stderr[-2000:]
    pixels = plt.imread(shot)[..., :3]
    assert pixels.std() > 0.05  # not blank
    red = (pixels[..., 0] > 0.95) & (pixels[..., 1] < 0.05) & (pixels[..., 2] < 0.05)
    assert red.sum() > 1000, "the embedded figure was not drawn"
    dom = headless(binary, tmp_path, "--dump-dom", html.as_uri()).stdout
    assert dom.count("<table>") == len(page.tables) and "Closed-loop study" in dom
    assert '<img src="data:image/png;base64,' in dom


def check_run_page(reports) -> None:
    """A run's summary.md against its comparison.nc: every study row's LOS std and blur to the shown digits."""
    from uavdamp import io

    ds = io.open_dataset(reports / "study" / "comparison.nc")
    rows = rows_of((reports / "summary.md").read_text(), "Closed-loop study")
    header = rows[0]
    los, blur = header.index("LOS std (mrad)"), header.index("blur p95 (px)")
    n = len(summary.study_rows(ds))
    assert header[:n] == [summary.dim_label(ds[d]) for d in summary.study_rows(ds)]
    assert len(rows) - 1 == ds.blur_p95.size
    for row in rows[1:]:
        where = {"case": row[0], "stiffness": float(row[1]), "strategy": row[2]}
        assert float(row[los]) == pytest.approx(1e3 * float(ds.los_std.sel(where)), rel=5e-4)  # 4 digits
        assert float(row[blur]) == pytest.approx(float(ds.blur_p95.sel(where)), rel=5e-4)
    payload = io.open_dataset(reports / "payload" / "comparison.nc")
    landing = (reports / "report_landing.rst").read_text()
    assert landing.count("- **") == ds.sizes["case"] * ds.sizes["stiffness"] + payload.sizes["input"]
    for i in payload.input.values:  # each input's least line of sight, as the page states it (3 digits)
        least = float(payload.los_std.sel(input=i).min()) * 1e6
        stated = re.search(rf"\*\*{i}\.\*\* Least line of sight at a constant C: .*?, ([0-9.]+) µrad rms", landing)
        assert stated and float(stated.group(1)) == pytest.approx(least, rel=5e-3, abs=0.5), (i, least)


def test_the_quick_runs_page_is_its_comparison(quick_run):
    check_run_page(quick_run / "reports-quick")


def test_the_payload_table_and_findings_are_its_numbers():
    """A payload dataset made here: the table shows each isolator at the C of least line of sight, in µrad, '-' where
    not modelled; the finding names the least cell and says whether it is within 175 µrad, and why a balanced
    camera sees nothing of an input without rotation."""
    los = np.full((2, 2, 3, 2), np.nan)  # input, payload, mount (rigid, yz, six_axis), damping (3, 30)
    los[:, 0, 0, :], los[:, 0, 1, :] = 0.04, [[0.03, 0.035], [0.03, 0.035]]  # head: six_axis not modelled
    los[:, 1, 0, :], los[:, 1, 1, :], los[:, 1, 2, :] = 3e-3, [[9e-4, 8e-4]] * 2, [[1e-4, 2e-3]] * 2
    los[1, 0] = 0.0  # the second input has no rotation: the head sees nothing
    best = np.array([[[np.nan, 3.0, np.nan], [np.nan, 30.0, 3.0]]] * 2)
    ds = xr.Dataset(
        {
            "los_std": (("input", "payload", "mount", "damping"), los, {"units": "rad"}),
            "best_damping": (("input", "payload", "mount"), best, {"units": "N s m-1"}),
            "input_rotation_rms": (("input",), [1e-3, 0.0], {"units": "rad"}),
        },
        coords={
            "input": ["heli", "quad"],
            "payload": ["paper_head", "gimbal"],
            "mount": ["rigid", "yz", "six_axis"],
            "damping": [3.0, 30.0],
        },
    )
    frame = payload_page.payload_table(ds).frame
    gimbal = frame[(frame.input == "heli") & (frame.payload == "gimbal")].iloc[0]
    assert gimbal["rigid (µrad)"] == "3000"
    assert gimbal["yz (µrad, at C N s/m)"] == "800 (30)" and gimbal["six_axis (µrad, at C N s/m)"] == "100 (3)"
    head = frame[(frame.input == "heli") & (frame.payload == "paper_head")].iloc[0]
    assert head["six_axis (µrad, at C N s/m)"] == "-"
    first, second = payload_page.payload_findings(ds)
    assert "gimbal on the six_axis mount at C = 3 N s/m, 100 µrad rms (within 175 µrad)" in first
    assert "paper_head on the rigid mount" in second and "does not rotate the mount" in second


def test_the_payload_findings_state_the_best_skyhook_run_against_the_best_constant_c_on_each_mount():
    """Skyhook runs at c_on 30 and 100 N s/m (75 and 90 µrad) against the gimbal's best constant C on the six-axis
    isolator (100 µrad at C = 3): the finding names the 75 µrad run, c_on 30 and -25 %; on the wire rope (best
    constant 80 µrad at C = 3) the 100 N s/m run (60 µrad), -25 % against 80; the rigid mount (no law: NaN) is not
    named; a worse six-axis run (120 µrad) is +20 %."""
    los = np.full((1, 1, 3, 2), np.nan)
    los[0, 0, 0] = [1e-3, 1e-3]
    los[0, 0, 1] = [1e-4, 2e-3]
    los[0, 0, 2] = [8e-5, 2e-3]
    laws = [[[np.nan, np.nan], [75e-6, 90e-6], [70e-6, 60e-6]]]
    ds = xr.Dataset(
        {
            "los_std": (("input", "payload", "mount", "damping"), los, {"units": "rad"}),
            "law_los_std": (("input", "mount", "law"), laws, {"units": "rad"}),
            "law_c_on": (("input", "law"), [[30.0, 100.0]], {"units": "N s m-1"}),
        },
        coords={
            "input": ["heli"],
            "payload": ["gimbal"],
            "mount": ["rigid", "six_axis", "wire_rope"],
            "damping": [3.0, 30.0],
            "law": ["skyhook_30", "skyhook_100"],
        },
    )
    (finding,) = payload_page.payload_findings(ds)
    assert (
        "Skyhook on the six-axis isolator (gimbal): 75 µrad at c_on = 30 N s/m, -25 % against its best constant C"
        " (100 µrad)." in finding
    )
    assert (
        "Skyhook on the wire-rope isolator (gimbal): 60 µrad at c_on = 100 N s/m, -25 % against its best constant C"
        " (80 µrad)." in finding
    )
    assert finding.count("Skyhook on") == 2
    laws[0][1] = [120e-6, 130e-6]
    worse = ds.assign(law_los_std=(("input", "mount", "law"), laws))
    assert "120 µrad at c_on = 30 N s/m, +20 % against" in payload_page.payload_findings(worse)[0]


def test_the_payload_findings_state_the_scheduled_law_apart_from_the_skyhook_runs():
    """A scheduled law (60 µrad, mean C 5.5 N s/m) beside a skyhook run (75 µrad at c_on 30): the skyhook finding
    names the skyhook run, not the scheduled law's lower value, and the scheduled law is stated with its mean C and
    -40 % against the best constant C (100 µrad); its detrended value (30 µrad) beside the skyhook's (35). The
    payload ANFIS (110 µrad, mean C 12 N s/m) with its mean C and +10 %."""
    los = np.full((1, 1, 1, 2), np.nan)
    los[0, 0, 0] = [1e-4, 2e-3]
    per_law, per_mount = ("input", "law"), ("input", "mount", "law")
    ds = xr.Dataset(
        {
            "los_std": (("input", "payload", "mount", "damping"), los, {"units": "rad"}),
            "los_detrended_std": (("input", "payload", "mount", "damping"), [[[[40e-6, 60e-6]]]], {"units": "rad"}),
            "law_los_std": (per_mount, [[[75e-6, 60e-6, 110e-6]]], {"units": "rad"}),
            "law_los_detrended_std": (per_mount, [[[35e-6, 30e-6, 50e-6]]], {"units": "rad"}),
            "law_c_on": (per_law, [[30.0, np.nan, np.nan]], {"units": "N s m-1"}),
            "law_damping_mean": (per_law, [[np.nan, 5.5, 12.0]], {"units": "N s m-1"}),
        },
        coords={
            "input": ["heli"],
            "payload": ["gimbal"],
            "mount": ["six_axis"],
            "damping": [3.0, 30.0],
            "law": ["skyhook_30", "scheduled", "anfis"],
        },
    )
    (finding,) = payload_page.payload_findings(ds)
    assert "Skyhook on the six-axis isolator (gimbal): 75 µrad at c_on = 30 N s/m, -25 %" in finding
    assert (
        "The scheduled law there (C from the tracked lines through the payload table; mean 5.5 N s/m): 60 µrad, -40 %"
        in finding
    )
    assert "35 µrad under skyhook, 30 µrad under the scheduled law." in finding
    assert "The payload ANFIS there (C from two DOFs' tracked frequencies; mean 12 N s/m): 110 µrad, +10 %." in finding


def test_the_payload_findings_state_the_gimbals_line_of_sight_without_the_slow_drift():
    """los_detrended_std of the gimbal on the six-axis isolator 40 and 60 µrad at C = 3 and 30: the finding names
    40 µrad at C = 3, and the skyhook runs' least (35 µrad)."""
    los = np.full((1, 1, 1, 2), 1e-4)
    ds = xr.Dataset(
        {
            "los_std": (("input", "payload", "mount", "damping"), los, {"units": "rad"}),
            "los_detrended_std": (("input", "payload", "mount", "damping"), [[[[40e-6, 60e-6]]]], {"units": "rad"}),
            "law_los_std": (("input", "mount", "law"), [[[75e-6, 90e-6]]], {"units": "rad"}),
            "law_los_detrended_std": (("input", "mount", "law"), [[[35e-6, 50e-6]]], {"units": "rad"}),
            "law_c_on": (("input", "law"), [[30.0, 100.0]], {"units": "N s m-1"}),
        },
        coords={
            "input": ["heli"],
            "payload": ["gimbal"],
            "mount": ["six_axis"],
            "damping": [3.0, 30.0],
            "law": ["skyhook_30", "skyhook_100"],
        },
    )
    (finding,) = payload_page.payload_findings(ds)
    assert "gimbal on the six-axis isolator gives 40 µrad at C = 3 N s/m, 35 µrad under skyhook." in finding


def test_the_payload_findings_state_the_mr_dampers_runs_against_the_best_constant_c():
    """MR runs on the six-axis isolator (held 0 V: 150 µrad, 2.25 V: 50, skyhook 80, scheduled 90; c_eq 1 and 6
    N s/m) against the best constant C there (100 µrad): each with its per cent; a skyhook_3 run beside them is not
    taken for one of them."""
    names = ["skyhook_3", "mr_off", "mr_on", "mr_skyhook", "mr_scheduled"]
    ds = xr.Dataset(
        {
            "los_std": (("input", "payload", "mount", "damping"), [[[[1e-4, 2e-4]]]], {"units": "rad"}),
            "law_los_std": (("input", "mount", "law"), [[[70e-6, 150e-6, 50e-6, 80e-6, 90e-6]]], {"units": "rad"}),
            "law_c_on": (("input", "law"), [[3.0, np.nan, np.nan, 6.0, np.nan]], {"units": "N s m-1"}),
            "law_damping_mean": (("input", "law"), [[np.nan, 1.0, 6.0, np.nan, 4.2]], {"units": "N s m-1"}),
        },
        coords={"input": ["heli"], "payload": ["gimbal"], "mount": ["six_axis"], "damping": [3.0, 30.0], "law": names},
    )
    (finding,) = payload_page.payload_findings(ds)
    assert (
        "An MR damper on each element (c_eq 1-6 N s/m at the reference stroke): held at 0 V 150 µrad (+50 %), at "
        "2.25 V 50 µrad (-50 %), under skyhook 80 µrad (-20 %), scheduled 90 µrad (-10 %), against the best "
        "constant C." in finding
    )
    assert "Skyhook on the six-axis isolator (gimbal): 70 µrad at c_on = 3 N s/m" in finding
