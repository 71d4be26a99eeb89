"""Every figure readable at a glance: it fits a laptop screen, its legends are short and off the data, spectra are
clipped above numerical noise, and no peak is the input's offset at t = 0.

Limits (`uavdamp.plots.style`): MAX_WIDTH_PX x MAX_HEIGHT_PX at the saved dpi, MAX_LEGEND_ENTRIES per legend."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402
from conftest import vibration_dataset  # noqa: E402
from matplotlib.container import BarContainer  # noqa: E402
from PIL import Image  # noqa: E402

from uavdamp import io  # noqa: E402
from uavdamp.plots import benchmark, helicopter, platform, reference_table, study  # noqa: E402
from uavdamp.plots.style import (  # noqa: E402
    DPI,
    MAX_HEIGHT_PX,
    MAX_LEGEND_ENTRIES,
    MAX_WIDTH_PX,
    SPECTRUM_DYNAMIC_RANGE,
    number,
    spread_labels,
)
from uavdamp.reference_table import criteria  # noqa: E402

FIGURES = "reports-quick/figures"


def test_every_figure_the_quick_run_writes_fits_a_laptop_screen(quick_run):
    pngs = sorted((quick_run / FIGURES).rglob("*.png"))
    assert len(pngs) >= 15, f"expected the pipeline's figures under {FIGURES}, found {len(pngs)}"
    too_big = {}
    for path in pngs:
        with Image.open(path) as image:
            if image.width > MAX_WIDTH_PX or image.height > MAX_HEIGHT_PX:
                too_big[str(path.relative_to(quick_run / FIGURES))] = image.size
    assert not too_big, f"figures larger than {MAX_WIDTH_PX} x {MAX_HEIGHT_PX} px: {too_big}"


def plot_function_figures(run: Path):
    """(name, figure) for every plot function of uavdamp.plots but the ANFIS and flight-log ones, from a quick
    run's NetCDF files (`run` is the run directory) and a synthetic platform response."""
    reports = run / "reports-quick"
    ds = io.open_dataset(reports / "study/comparison.nc")
    k = float(ds.stiffness[0])
    case1, case2 = (str(c) for c in ds.case.values[:2])
    yield "study_fig10", study.rigid_mount_figure(ds, case1, "y")
    yield "study_fig11", study.passive_vs_anfis_figure(ds, case1, "y", k)
    yield "study_fig12", study.tracked_frequency_figure(ds, case2, "z")
    yield "study_fig13", study.passive_vs_anfis_figure(ds, case2, "z", k)
    yield "study_blur", study.blur_distribution_figure(ds)
    yield "study_sharp_frames", study.sharp_fraction_figure(ds)
    yield "study_strategies", study.strategies_figure(ds, case1)
    table = io.open_dataset(reports / "reference_table/table.nc")
    chosen = criteria.select_table(table, table.attrs["criterion"], table.attrs["window"])
    yield "reference_table", reference_table.reference_table_figure(chosen)
    yield "reference_table_criteria", reference_table.criteria_figure(table)
    yield (
        "fuselage_vibration",
        helicopter.fuselage_vibration_figure(io.open_dataset(reports / "helicopter/vibration.nc")),
    )
    yield "helicopter_campbell", helicopter.campbell_figure(io.open_dataset(reports / "helicopter/campbell.nc"))
    yield (
        "helicopter_sensitivity",
        helicopter.sensitivity_figure(io.open_dataset(reports / "helicopter/sensitivity.nc")),
    )
    bench = io.open_dataset(reports / "benchmark/criteria.nc")
    yield "benchmark_criteria", benchmark.criteria_figure(bench)
    yield "benchmark_boxplots", benchmark.boxplot_figure(bench)
    yield "platform_response", platform.response_figure(*platform_runs())


def platform_runs():
    """A rigid and an isolated run of the real plant (the platform stage's own inputs, 1 s), and the modes."""
    from conftest import platform_params

    from uavdamp.damping.laws import Constant
    from uavdamp.platform import ExudynPlant
    from uavdamp.sources.excitation import sine_input

    params = platform_params()
    time, motion = sine_input(7.0, 8.0, 1.3e-3, 1.0, params.time_step)
    rigid = ExudynPlant(params, mount="rigid").run(time, motion)
    isolated = ExudynPlant(params).run(time, motion, stiffness=10.0, law=Constant(2.0))
    return rigid, isolated


def legends(fig):
    """Every legend of a figure: its axes' and its own (subfigures included)."""
    found = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    stack = [fig]
    while stack:
        f = stack.pop()
        found += list(f.legends)
        stack += list(getattr(f, "subfigs", []))
    return found


def data_points_under(legend, axes) -> int:
    """How many plotted line vertices and bars of `axes` lie inside the legend's box on the canvas."""
    box = legend.get_window_extent()
    count = 0
    for ax in axes:
        for line in ax.get_lines():
            if not line.get_visible() or not np.asarray(line.get_xydata()).size:
                continue
            xy = line.get_transform().transform(np.asarray(line.get_xydata(), dtype=float))
            inside = (xy[:, 0] > box.x0) & (xy[:, 0] < box.x1) & (xy[:, 1] > box.y0) & (xy[:, 1] < box.y1)
            count += int(np.count_nonzero(inside & np.isfinite(xy).all(axis=1)))
        for patch in ax.patches:
            if patch.get_visible() and patch.get_window_extent().overlaps(box):
                count += 1
    return count


@pytest.fixture(scope="module")
def plot_figures(quick_run):
    figures = dict(plot_function_figures(quick_run))
    for fig in figures.values():
        fig.draw_without_rendering()  # layout and tick labels as when saved (a bare Figure's canvas draws nothing)
    yield figures
    for fig in figures.values():
        plt.close(fig)


def test_plot_functions_make_figures_that_fit_a_laptop_screen(plot_figures):
    sizes = {name: tuple(np.round(fig.get_size_inches() * DPI)) for name, fig in plot_figures.items()}
    too_big = {n: s for n, s in sizes.items() if s[0] > MAX_WIDTH_PX or s[1] > MAX_HEIGHT_PX}
    assert not too_big, f"larger than {MAX_WIDTH_PX} x {MAX_HEIGHT_PX} px at {DPI} dpi: {too_big}"


def test_no_legend_has_more_than_the_limit_of_entries(plot_figures):
    long = {
        name: [len(legend.get_texts()) for legend in legends(fig)]
        for name, fig in plot_figures.items()
        if any(len(legend.get_texts()) > MAX_LEGEND_ENTRIES for legend in legends(fig))
    }
    assert not long, f"legends with more than {MAX_LEGEND_ENTRIES} entries (entries per legend): {long}"


def test_legends_sit_off_the_data(plot_figures):
    covered = {}
    for name, fig in plot_figures.items():
        for legend in legends(fig):
            hidden = data_points_under(legend, fig.axes)
            if hidden:
                covered[name] = covered.get(name, 0) + hidden
    assert not covered, f"legends drawn over plotted data (points and bars hidden): {covered}"


def texts_off_the_figure(fig) -> list[str]:
    """Titles, axis labels, legend texts, annotations and figure titles (subfigures included) that reach beyond
    the figure's edge, where the saved PNG cuts them; the figure must have been drawn."""
    found, stack = [], [fig]
    while stack:
        f = stack.pop()
        found += list(f.texts) + [t for legend in f.legends for t in (*legend.get_texts(), legend.get_title())]
        stack += list(getattr(f, "subfigs", []))
    for ax in fig.axes:
        found += [ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label, *ax.texts]
        if ax.get_legend() is not None:
            found += [*ax.get_legend().get_texts(), ax.get_legend().get_title()]
    edge = fig.bbox
    cut = []
    for text in (t for t in found if t.get_visible() and t.get_text()):
        box = text.get_window_extent()
        if box.x0 < edge.x0 - 1 or box.x1 > edge.x1 + 1 or box.y0 < edge.y0 - 1 or box.y1 > edge.y1 + 1:
            cut.append(text.get_text())
    return cut


def bars_on_log_axes(fig) -> list[str]:
    """Titles of the panels that draw bars on a log axis (a bar there has no base: its length means nothing)."""
    return [
        ax.get_title()
        for ax in fig.axes
        if "log" in (ax.get_xscale(), ax.get_yscale()) and any(isinstance(c, BarContainer) for c in ax.containers)
    ]


def test_no_title_or_label_runs_off_the_figure(plot_figures):
    cut = {name: texts_off_the_figure(fig) for name, fig in plot_figures.items()}
    assert not {name: texts for name, texts in cut.items() if texts}, "texts cut at the figure's edge"


def test_no_bars_on_a_log_axis(plot_figures):
    found = {name: bars_on_log_axes(fig) for name, fig in plot_figures.items()}
    assert not {name: panels for name, panels in found.items() if panels}, "bars on a log axis"


def test_every_axis_with_data_says_its_unit(plot_figures):
    """Every numeric axis label of a panel with data carries a unit in parentheses, as '(mm)', '(1)' or '(Hz)'."""
    missing = []
    for name, fig in plot_figures.items():
        for ax in fig.axes:
            if not ax.get_visible() or not (ax.get_lines() or ax.patches or ax.images):
                continue
            for which, label in (("x", ax.get_xlabel()), ("y", ax.get_ylabel())):
                ticks = ax.get_xticklabels() if which == "x" else ax.get_yticklabels()
                categorical = any(t.get_text() and not _numeric(t.get_text()) for t in ticks)
                if label and not categorical and "(" not in label:
                    missing.append(f"{name}: {which} label {label!r}")
    assert not missing, missing


def _numeric(text: str) -> bool:
    text = text.replace("\N{MINUS SIGN}", "-").replace("$", "").replace("\\mathdefault{", "").replace("}", "")
    try:
        float(text.replace("10^", "1e").replace("{", ""))
    except ValueError:
        return False
    return True


# ----------------------------------------------------------------------------------------------------
# Defects a reviewer found, checked on small synthetic data (no pipeline run).


def offset_study(offset=-0.06e-3, amplitude=0.02e-3):
    """A study dataset whose camera starts at the input's offset and then oscillates around zero."""
    t = np.round(np.arange(0, 3.0 + 1e-9, 2e-3), 9)
    wave = offset * np.exp(-t / 0.05) + amplitude * np.sin(2 * np.pi * 7 * t)
    camera = np.broadcast_to(wave, (1, 1, 2, 2, t.size)).copy()
    camera[0, 0, 1] *= 0.8  # anfis
    damping = np.broadcast_to(np.array([2.0, 1.4])[:, None], (1, 1, 2, t.size)).copy()
    return xr.Dataset(
        {
            "camera_displacement": (("case", "stiffness", "strategy", "axis", "time"), camera),
            "damping": (("case", "stiffness", "strategy", "time"), damping),
            "peak_early": (
                ("case", "stiffness", "strategy", "axis"),
                np.abs(camera[..., t <= 0.5]).max(-1),
            ),
        },
        coords={
            "case": ["case2"],
            "stiffness": [10.0],
            "strategy": ["passive", "anfis"],
            "axis": ["y", "z"],
            "time": t,
        },
    )


def test_fig13_peak_is_the_move_from_the_start_not_the_offset_at_t0():
    ds = offset_study()
    assert 1e3 * ds.peak_early.sel(strategy="passive", axis="z").item() == pytest.approx(0.06, rel=1e-9)  # t = 0
    fig = study.passive_vs_anfis_figure(ds, "case2", "z", 10.0)
    try:
        (legend,) = legends(fig)
        text = legend.get_texts()[0].get_text()
        t = ds.time.values
        camera = 1e3 * ds.camera_displacement.sel(strategy="passive", axis="z").values.ravel()
        move = np.abs(camera - camera[0])[t <= 0.5]
        assert text.startswith(f"passive: {move.max():.3f} mm"), text
        assert f"{1e3 * 0.06:.3f}" not in text
        first = fig.axes[0].get_lines()[0].get_ydata()
        assert first[0] == 0.0, "the camera is drawn from its start"
    finally:
        plt.close(fig)


def test_spectra_are_clipped_above_numerical_noise():
    t = np.arange(0, 8, 0.01)
    omega = np.linspace(0, 200, 201)
    spectrum = np.full((2, 3, omega.size), 1e-18)
    spectrum[:, :, 44] = 1e-3
    ds = vibration_dataset(t, omega, np.zeros((2, 3, t.size)), spectrum, np.full((2, 3), 44.0))
    fig = helicopter.fuselage_vibration_figure(ds)
    try:
        for ax in (fig.axes[1], fig.axes[3]):
            low, high = ax.get_ylim()
            assert low == pytest.approx(1.0 * SPECTRUM_DYNAMIC_RANGE) and high >= 1.0  # peak 1 mm
    finally:
        plt.close(fig)


def test_switching_damping_does_not_hide_the_other_laws():
    """The on-off skyhook (0 / 200 every step) is drawn as its running mean; the constant laws stay visible."""
    ds = offset_study()
    t = ds.time.values
    skyhook = np.where(np.sin(2 * np.pi * 100 * t) > 0, 200.0, 0.0)
    extra = ds.isel(strategy=[0]).assign_coords(strategy=["skyhook"])
    extra["damping"] = extra.damping.copy(data=np.broadcast_to(skyhook, extra.damping.shape).copy())
    ds = xr.concat([ds, extra], dim="strategy")
    ds["std_total"] = ds.camera_displacement.std("time")
    fig = study.strategies_figure(ds, "case2")
    try:
        damping_ax = next(ax for ax in fig.axes if ax.get_title().endswith("damping"))
        lines = damping_ax.get_lines()
        assert len(lines) == 3
        switching = max(lines, key=lambda line: np.nanmax(line.get_ydata()))
        assert np.nanmax(switching.get_ydata()) < 150 and np.nanmin(switching.get_ydata()) > 50
        (legend,) = [leg for leg in legends(fig) if "skyhook" in " ".join(t.get_text() for t in leg.get_texts())]
        assert any("mean over" in t.get_text() for t in legend.get_texts())
        styles = {(line.get_color(), str(line.get_linestyle())) for line in fig.axes[0].get_lines()}
        assert len(styles) == 3, "each strategy has its own colour and line style"
    finally:
        plt.close(fig)


def test_stiffness_labels_and_label_spreading():
    assert [number(k) for k in (10.0, 1000.0, 2000.0, 0.25)] == ["10", "1000", "2000", "0.25"]
    placed = spread_labels([166.0, 166.2, 112.0, 112.5, 28.0, 27.5, 8.0], 6.0, lower=0.0, upper=230.0)
    gaps = np.diff(np.sort(placed))
    assert gaps.min() >= 6.0 - 1e-9
    assert (
        np.argsort(placed).tolist() == np.argsort([166.0, 166.2, 112.0, 112.5, 28.0, 27.5, 8.0], kind="stable").tolist()
    )
    assert np.abs(placed - [166.0, 166.2, 112.0, 112.5, 28.0, 27.5, 8.0]).max() <= 6.0


def test_reference_table_figures_of_the_default_grid_fit_a_laptop_screen():
    """The default grid has 9 stiffnesses, 3 criteria and 2 windows (the quick run only 2 stiffnesses)."""
    from conftest import synthetic_grid

    rng = np.random.default_rng(0)
    table = criteria.reference_table(synthetic_grid(rng.uniform(1, 2, (3, 2, 4, 4, 9, 5)), ("transient", "steady")))
    table.attrs.update(criterion="displacement", window="transient")
    chosen = criteria.select_table(table, "displacement", "transient")
    for fig in (reference_table.reference_table_figure(chosen), reference_table.criteria_figure(table)):
        try:
            width, height = fig.get_size_inches() * DPI
            assert width <= MAX_WIDTH_PX and height <= MAX_HEIGHT_PX, (width, height)
            titles = [ax.get_title() for ax in fig.axes]
            assert not any("e+0" in t for t in titles), titles  # "K = 1000 N/m", not "K = 1e+03 N/m"
        finally:
            plt.close(fig)
