"""The benchmark's table and figures from a small gathered dataset of the shape the benchmark writes (values set
here): not-run cells, every damper drawn, ties, identical rows explained, points below five scenarios."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from uavdamp.benchmark import loop as benchmark
from uavdamp.plots import benchmark as plots

CONTROLLERS = ["rigid", "passive_tuned", "anfis", "table_lookup", "skyhook_on_off"]
CRITERIA, PHASED, DAMPERS = ["los_std", "blur_p95"], ["blur_p95"], ["ideal", "mr"]
# evaluation mean J of los_std on the ideal damper: passive_tuned 0.08351 and anfis 0.08349 show as 0.0835 both
IDEAL = {"rigid": 1.0, "passive_tuned": 0.08351, "anfis": 0.08349, "table_lookup": 0.09, "skyhook_on_off": 0.2}
BELOW = {"passive_tuned": 1.0, "anfis": 1.0, "table_lookup": 0.98}  # share of demands below the MR's c_off


def run(scenario: str, scale: float) -> xr.Dataset:
    """One scenario's criteria (`benchmark.run_scenario`'s variables and coordinates): on the MR damper the three
    table-like laws give one J (their demands below its range), the per-step law did not run (NaN)."""
    j = np.full((len(CONTROLLERS), 1, len(CRITERIA), len(DAMPERS)), np.nan)
    below = np.full((len(CONTROLLERS), 1, len(DAMPERS)), np.nan)
    for i, name in enumerate(CONTROLLERS):
        j[i, 0, :, 0] = IDEAL[name] * scale
        if name != "skyhook_on_off":
            j[i, 0, :, 1] = 1.0 if name == "rigid" else 0.5 * scale
        if name in BELOW:
            below[i, 0, :] = [0.0, BELOW[name]]
    phased = j[:, :, [CRITERIA.index(c) for c in PHASED], :]
    ds = xr.Dataset(
        {
            "J": (("controller", "stiffness", "criterion", "damper"), j),
            "J_low": (("controller", "stiffness", "phased", "damper"), 0.9 * phased),
            "J_high": (("controller", "stiffness", "phased", "damper"), 1.1 * phased),
            "step_difference": (("controller", "stiffness", "damper"), np.full(below.shape, np.nan)),
            "demand_below_range": (("controller", "stiffness", "damper"), below),
        },
        coords={
            "controller": CONTROLLERS,
            "stiffness": [10.0],
            "criterion": CRITERIA,
            "phased": PHASED,
            "damper": DAMPERS,
            "tuned_on": (("controller", "criterion"), [[""] * len(CRITERIA)] * len(CONTROLLERS)),
        },
    )
    return ds.expand_dims(scenario=[scenario])


def gathered(n_evaluation: int) -> xr.Dataset:
    names = ["tune0"] + [f"eval{i}" for i in range(n_evaluation)]
    split = {n: "tuning" if n.startswith("tune") else "evaluation" for n in names}
    return benchmark.gather([run(n, 1.0) for n in names], split, xr.Dataset())


def table_rows(text: str, header: str) -> dict[str, list[str]]:
    part = text.split(header, 1)[1].split("\n\n", 2)[1]
    rows = [line.strip("|").split("|") for line in part.splitlines()[2:]]
    return {r[0].strip(): [c.strip() for c in r[1:]] for r in rows}


def test_not_run_cells_show_a_dash():
    text = plots.markdown_table(gathered(2), damper="mr")
    rows = table_rows(text, "K = 10 N/m, mr damper")
    assert rows["skyhook_on_off"] == ["-", "-"]
    assert "nan" not in text
    assert rows["anfis"][0] == "0.5 / 0.5"


def test_equal_values_to_the_shown_digits_rank_as_a_tie():
    ds = gathered(2)
    assert plots.ranking(ds, 10.0, "los_std", "ideal") == "los_std: anfis 0.0835 = passive_tuned 0.0835"
    assert plots.ranking(ds, 10.0, "los_std", "mr").startswith("los_std: passive_tuned 0.5 = anfis 0.5")
    changed = ds.copy(deep=True)
    changed["J_mean"].loc[{"controller": "anfis", "damper": "ideal", "criterion": "los_std"}] = 0.08
    assert plots.ranking(changed, 10.0, "los_std", "ideal") == "los_std: anfis 0.08 < passive_tuned 0.0835"


def test_identical_rows_are_named_with_their_demands_below_the_dampers_range():
    ds = gathered(2)
    assert ds.demand_below_range_mean.sel(controller="table_lookup", damper="mr").item() == pytest.approx(0.98)
    text = plots.markdown_table(ds, damper="mr")
    remark = (
        "- identical rows: passive_tuned, anfis, table_lookup; share of their demands below the mr damper's range: "
        "passive_tuned 100 %, anfis 100 %, table_lookup 98 %"
    )
    assert remark in text
    assert "identical rows" not in plots.markdown_table(ds, damper="ideal")


def test_the_figures_show_every_damper_a_controller_ran_with():
    ds = gathered(2)
    fig = plots.criteria_figure(ds)
    titles = [ax.get_title() for ax in fig.axes if ax.get_title()]
    assert sorted(t.split(":")[0] for t in titles) == sorted(["ideal", "mr"] * 2)  # a row each: mean and worst
    mr = next(ax for ax in fig.axes if ax.get_title() == "mr: mean J, K = 10 N/m")
    texts = [t.get_text() for t in mr.texts]
    assert texts.count("-") == len(CRITERIA)  # skyhook_on_off's row: not run
    boxes = plots.boxplot_figure(ds, criteria=("los_std",))
    legend = boxes.axes[0].get_legend()
    assert [t.get_text() for t in legend.get_texts()] == ["ideal damper", "mr damper"]  # side by side in one panel


def test_fewer_than_five_scenarios_are_points_not_boxes():
    few = plots.boxplot_figure(gathered(2), criteria=("los_std",)).axes[0]
    points = [line for line in few.lines if line.get_marker() == "o"]  # per controller and damper it ran with
    assert len(points) == 2 * len(CONTROLLERS) - 1 and all(len(p.get_xdata()) == 2 for p in points)
    assert "(points)" in few.get_title() and not [line for line in few.lines if line.get_linestyle() == "-"]
    many = plots.boxplot_figure(gathered(5), criteria=("los_std",)).axes[0]
    drawn = [line for line in many.lines if line.get_linestyle() == "-"]  # boxes, whiskers, caps, medians
    assert len(drawn) >= 5 * len(CONTROLLERS) and "(boxes)" in many.get_title()


def test_demands_below_the_mr_dampers_off_state_are_counted():
    from types import SimpleNamespace

    options = SimpleNamespace(mr=SimpleNamespace(damping_range=(5.0, 50.0)))
    response = xr.Dataset({"damping": ("time", [0.0, 2.0, 5.0, 10.0])})  # two of four below c_off = 5 N s/m
    assert benchmark.below_range(response, "mr", options) == 0.5
    assert benchmark.below_range(response, "ideal", options) == 0.0
    rigid = xr.Dataset({"damping": ("time", [np.nan, np.nan])})
    assert np.isnan(benchmark.below_range(rigid, "mr", options))
