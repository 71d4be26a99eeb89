"""Figures checked for content: the plotted data read back from the axes, not the PNG's size."""

from __future__ import annotations

import re

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr
from conftest import displacement_grid as synthetic_grid
from conftest import vibration_dataset
from matplotlib.colors import to_hex
from matplotlib.container import BarContainer

from uavdamp.plots.helicopter import fuselage_vibration_figure, sensitivity_figure
from uavdamp.plots.reference_table import GAIN_LABEL, SPREAD_LABEL, reference_table_figure
from uavdamp.plots.study import sharp_fraction_figure
from uavdamp.reference_table import criteria as criterion


def _seven_thirds_table():
    """The 7/3 fixture's reference table (displacement, transient): C grid 1, 2, 4, 8 N s/m, K = 10 and 20 N/m; the
    optimum at C = 4 for K = 10, at 1 (row f_y = 1) or 8 (other rows) for K = 20."""
    values = np.ones((3, 3, 2, 4))
    values[..., 0, 2] = 0.5
    values[0, :, 1, 0] = 0.2
    values[1:, :, 1, 3] = 0.2
    return criterion.select_table(criterion.reference_table(synthetic_grid(values)), "displacement", "transient")


def test_reference_table_figure_shows_the_table():
    """The 7/3 fixture (`_seven_thirds_table`): heatmaps hold damping_opt and the flat band per K; the
    right panel plots the spread (1, 8) and the scheduling gain (1, 7/3) against K."""
    table = _seven_thirds_table()
    fig = reference_table_figure(table)
    try:
        images = [ax.images[0] for ax in fig.axes if ax.images]
        assert len(images) == 4  # (optimal C, flat band) x 2 stiffnesses
        np.testing.assert_array_equal(images[0].get_array(), table.damping_opt.values[:, :, 0])
        np.testing.assert_array_equal(images[1].get_array(), table.damping_opt.values[:, :, 1])
        expected_c1 = np.where(np.arange(3)[:, None] == 0, 1.0, 8.0) * np.ones((3, 3))
        np.testing.assert_array_equal(images[1].get_array(), expected_c1)
        flat = (table.damping_flat_max / table.damping_flat_min).values
        np.testing.assert_array_equal(images[2].get_array(), flat[:, :, 0])
        gain_axes = next(ax for ax in fig.axes if GAIN_LABEL in [line.get_label() for line in ax.get_lines()])
        spread_axes = next(ax for ax in fig.axes if SPREAD_LABEL in [line.get_label() for line in ax.get_lines()])
        assert gain_axes is not spread_axes, "the gain (about 1) and the spread (up to 1e2) need their own axes"
        assert gain_axes.get_yscale() == "linear" and spread_axes.get_yscale() == "log"
        titles = [ax.get_title() for ax in fig.axes]
        assert "K = 10 N/m" in titles and "K = 20 N/m" in titles
        lines = {line.get_label(): line for ax in fig.axes for line in ax.get_lines()}
        gain = lines[GAIN_LABEL]
        np.testing.assert_array_equal(gain.get_xdata(), [10.0, 20.0])
        np.testing.assert_allclose(gain.get_ydata(), [1.0, 7 / 3], rtol=1e-14)
        np.testing.assert_array_equal(lines[SPREAD_LABEL].get_ydata(), [1.0, 8.0])
    finally:
        plt.close(fig)


def test_reference_table_figure_hatches_the_optima_on_a_grid_edge():
    """The 7/3 fixture without damper bounds: at K = 20 N/m the optimum is the grid's lowest C (1) in the f_y = 1
    row (flag 1) and its highest (8) in the other rows (flag 2); at K = 10 N/m it is inside (C = 4). Each flagged
    cell of the optimal-C heatmap is hatched, one hatch per flag, and a legend names the flags found."""
    table = _seven_thirds_table()
    fig = reference_table_figure(table)
    try:
        fig.draw_without_rendering()
        k10, k20 = [ax for ax in fig.axes if ax.images][:2]  # the optimal-C heatmaps come first
        assert (k10.get_title(), k20.get_title()) == ("K = 10 N/m", "K = 20 N/m")
        hatched = [p for p in k20.patches if p.get_hatch()]
        assert not [p for p in k10.patches if p.get_hatch()]
        by_hatch = {}
        x0, x1, y0, y1 = k20.images[0].get_extent()
        for patch in hatched:
            box = patch.get_bbox()
            row = int((0.5 * (box.y0 + box.y1) - y0) // ((y1 - y0) / 3))
            by_hatch.setdefault(patch.get_hatch(), []).append(row)
        assert sorted(sorted(rows) for rows in by_hatch.values()) == [[0, 0, 0], [1, 1, 1, 2, 2, 2]]
        (legend,) = [leg for f in fig.subfigs for sub in f.subfigs for leg in sub.legends]
        assert {h.get_hatch() for h in legend.legend_handles} == set(by_hatch)
    finally:
        plt.close(fig)


def test_fuselage_vibration_figure_shows_the_runs_in_mm():
    t = np.arange(0, 8, 0.01)
    disp = np.stack(
        [np.stack([a * np.sin(2 * np.pi * f * t) for a, f in ((0, 1), (1e-3, 7), (2e-3, 8))]) for _ in range(2)]
    )
    disp[1] *= 0.1  # the balanced rotor
    omega = np.linspace(0, 200, 201)
    ds = vibration_dataset(t, omega, disp, np.ones((2, 3, omega.size)) * 1e-4, [[0.0, 44.0, 50.3], [0.0, 44.0, 50.3]])
    fig = fuselage_vibration_figure(ds, window_s=5.0)
    try:
        z_ax, y_ax = fig.axes[0], fig.axes[2]
        imbalanced, balanced = z_ax.get_lines()[:2]
        early = t <= 5.0
        np.testing.assert_allclose(imbalanced.get_xdata(), t[early])
        np.testing.assert_allclose(imbalanced.get_ydata(), 1e3 * disp[0, 2, early], rtol=1e-12)
        np.testing.assert_allclose(balanced.get_ydata(), 1e3 * disp[1, 2, early], rtol=1e-12)
        np.testing.assert_allclose(y_ax.get_lines()[0].get_ydata(), 1e3 * disp[0, 1, early], rtol=1e-12)
        spectrum_ax = fig.axes[1]
        marks = [line for line in spectrum_ax.get_lines() if "dominant" in line.get_label()]
        assert marks and marks[0].get_xdata()[0] == pytest.approx(50.3)
    finally:
        plt.close(fig)


def test_the_sharp_frame_axis_is_scaled_to_the_fractions():
    """Fractions of sharp frames up to 0.1: the axis runs from 0 to little above 0.1 (not to 1), and its label
    says the fraction is of the run's frames that are sharp, with the threshold."""
    fractions = np.array([[[0.02, 0.1]], [[0.0, 0.05]]])  # (case, stiffness, strategy)
    ds = xr.Dataset(
        {"sharp_fraction": (("case", "stiffness", "strategy"), fractions)},
        coords={"case": ["case1", "case2"], "stiffness": [10.0], "strategy": ["passive", "anfis"]},
        attrs={"camera_sharp_threshold_px": 1.0},
    )
    fig = sharp_fraction_figure(ds)
    try:
        ax = fig.axes[0]
        low, high = ax.get_ylim()
        assert low == 0 and 0.1 < high <= 0.2
        label = ax.get_ylabel()
        assert "sharp frames" in label and "<= 1 px" in label and "frames of the run" in label
    finally:
        plt.close(fig)


def _three_runs() -> xr.Dataset:
    """The vibration layout with a third run, hover flight, and what the stage says of each run: the flight
    condition and the imbalanced blade's mass scale (0.5, 1 for the balanced rotor, 0.5)."""
    t = np.arange(0, 8, 0.01)
    disp = np.stack([np.stack([np.zeros_like(t), a * np.sin(44 * t), a * np.sin(50 * t)]) for a in (1e-3, 0.0)])
    omega = np.linspace(0, 200, 201)
    spectrum = np.full((2, 3, omega.size), 1e-6)
    spectrum[:, :, 44] = 1e-3
    ds = vibration_dataset(t, omega, disp, spectrum, [[0.0, 44.0, 50.0], [0.0, 44.0, 50.0]])
    hover = ds.isel(rotor=[0]).assign_coords(rotor=["hover"])
    hover["amplitude_spectrum"] = 2 * hover.amplitude_spectrum
    ds = xr.concat([ds, hover], dim="rotor")
    ds["flight"] = ("rotor", ["vacuum", "vacuum", "hover"])
    ds["mass_imbalance_factor"] = ("rotor", [0.5, 1.0, 0.5])
    return ds


def test_fuselage_vibration_figure_names_every_line_it_draws():
    """Every line drawn has its legend entry (same colour and style); the legend describes each run from the
    dataset (its name and blade mass scale); each panel's title names the runs it draws, no other."""
    ds = _three_runs()
    fig = fuselage_vibration_figure(ds)
    try:
        (legend,) = fig.legends
        keys = {(to_hex(h.get_color()), h.get_linestyle()) for h in legend.legend_handles}
        for ax in fig.axes:
            for line in ax.get_lines():
                assert (to_hex(line.get_color()), line.get_linestyle()) in keys, (ax.get_title(), line.get_color())
        texts = [t.get_text() for t in legend.get_texts()]
        hover = next(t for t in texts if t.startswith("hover"))
        assert "0.5" in hover and "hover" in hover
        assert any(t.startswith("balanced") for t in texts)
        z_time, z_spectrum = fig.axes[0], fig.axes[1]
        assert "imbalanced" in z_time.get_title() and "balanced" in z_time.get_title()
        assert "hover" not in z_time.get_title()
        spectra = [line for line in z_spectrum.get_lines() if len(line.get_xdata()) > 2]
        assert len(spectra) == 2  # the runs with an imbalanced blade: imbalanced and hover
        named = set(re.findall(r"[a-z]+", z_spectrum.get_title()))
        assert {"imbalanced", "hover"} <= named and not {"balanced", "rotor"} & named
    finally:
        plt.close(fig)


def _sensitivity() -> xr.Dataset:
    """A baseline, three hinge offsets and one parameter without a readable name. Z's dominant line in hinge-offset
    order (0.15, 0.3, 0.687 the config's, 1 m): another line at 47, the 1/rev line (its amplitude that of the 1/rev
    line) at 44.4, other lines at 50.6 and 52.4 rad/s; Y's is the 1/rev line in every run."""
    runs = ["baseline", "hinge_offset_m=0.15", "hinge_offset_m=0.3", "hinge_offset_m=1", "rotor.mystery=2"]
    z_omega, z_amp = [50.6, 47.0, 44.4, 52.4, 50.6], [1.1e-3, 2e-3, 1e-3, 1.8e-3, 1.1e-3]
    z_rotor = [1.0e-3, 0.5e-3, 1e-3, 1.1e-3, 1e-3]
    y_amp = [1e-2, 6e-3, 9e-3, 1.5e-2, 1e-2]
    omega = np.array([[44.4] * 5, z_omega]).T
    return xr.Dataset(
        {
            "dominant_omega": (("run", "axis"), omega),
            "dominant_amplitude": (("run", "axis"), np.array([y_amp, z_amp]).T),
            "rotor_line_amplitude": (("run", "axis"), np.array([y_amp, z_rotor]).T),
        },
        coords={
            "run": runs,
            "axis": ["y", "z"],
            "parameter": ("run", ["baseline", *["hinge_offset_m"] * 3, "rotor.mystery"]),
            "hinge_offset_m": ("run", [0.687, 0.15, 0.3, 1.0, 0.687], {"units": "m"}),
            "rotor.mystery": ("run", [1.0, 1.0, 1.0, 1.0, 2.0], {"units": "1"}),
        },
    )


def test_sensitivity_figure_joins_only_points_of_the_same_line():
    """Every run's dominant frequency is a point; a line joins two points only where both are the 1/rev line (never
    across a change of the dominant line). Panel titles: a readable name with its unit, else the key."""
    fig = sensitivity_figure(_sensitivity())
    try:
        top = fig.axes[0]  # the first parameter's frequencies: the hinge offset
        rotor_line = {(0.15, 44.4), (0.3, 44.4), (0.687, 44.4), (1.0, 44.4)}  # Y everywhere, Z at 0.3 m
        z_points = {(0.15, 47.0), (0.3, 44.4), (0.687, 50.6), (1.0, 52.4)}
        drawn = set()
        for line in top.get_lines():
            xy = {(round(float(x), 3), round(float(y), 3)) for x, y in line.get_xydata()}
            if line.get_linestyle() in ("None", "", " ") or len({x for x, _ in xy}) < 2:
                drawn |= xy if line.get_marker() not in ("None", "", None) else set()
                continue
            assert xy <= rotor_line, f"a line joins points of different lines: {sorted(xy)}"
            drawn |= xy if line.get_marker() not in ("None", "", None) else set()
        assert z_points <= drawn
        assert "hinge offset" in top.get_title() and "_" not in top.get_title() and "(m)" in top.get_title()
        assert any(ax.get_title() == "rotor.mystery" for ax in fig.axes)
    finally:
        plt.close(fig)


def _anfis(n_rules: int):
    """A DampingModel on log10 K and C with n_rules fuzzy c-means rules (2 or 65: one MF per rule and input)."""
    from conftest import anfis_options

    from uavdamp.anfis import DampingModel

    rng = np.random.default_rng(5)
    X = np.column_stack([rng.uniform(3, 12, 400), rng.uniform(3, 12, 400), 10 ** rng.uniform(1, 3.5, 400)])
    model = DampingModel.unfitted(anfis_options(epochs=3, log_stiffness=True, log_damping=True))
    model.estimator.set_params(init="fcm", n_rules=n_rules)
    return model.fit(X, 1 + 0.1 * X[:, 0] + np.sqrt(X[:, 2]))


@pytest.mark.parametrize("n_rules", [2, 65])
def test_membership_figure_is_readable_at_any_rule_count(n_rules):
    """Per input: every trained MF drawn (no per-MF legend), K on a log axis in N/m, each MF's centre in the
    ordered panel in the input's units."""
    from uavdamp.plots.anfis import membership_figure

    model = _anfis(n_rules)
    est = model.anfis
    fig = membership_figure(model)
    try:
        assert len(fig.axes) == 6
        top, bottom = fig.axes[:3], fig.axes[3:]
        for ax in fig.axes:
            legend = ax.get_legend()
            assert legend is None or len(legend.get_texts()) <= 2
        for i, (ax, low) in enumerate(zip(top, bottom, strict=True)):
            trained = [line for line in ax.get_lines() if line.get_linestyle() == "-" and len(line.get_xdata()) > 2]
            assert len(trained) == n_rules
            centres = est.centres_[est.mf_input_ == i]
            lo, hi = est.input_range_[i]
            shown = (lambda v: 10**v) if i == 2 else (lambda v: v)
            np.testing.assert_allclose(
                [trained[0].get_xdata()[0], trained[0].get_xdata()[-1]], shown(np.array([lo, hi]))
            )
            marks = next(line for line in low.get_lines() if line.get_label().startswith("trained"))
            np.testing.assert_allclose(marks.get_xdata(), shown(np.sort(centres)))
            assert (ax.get_xscale(), low.get_xscale()) == (("log", "log") if i == 2 else ("linear", "linear"))
        assert top[2].get_xlabel() == "K (N/m)" and top[0].get_xlabel() == "f_y (Hz)"
    finally:
        plt.close(fig)


def _selection_record():
    """A training record of three candidates (fold RMSEs below) and two models, anfis and hgb, checked: regret
    mean 1.01 and 1.02, max 1.1 and 1.2."""
    from uavdamp.anfis import model_selection

    candidates = [{"init": "fcm", "n_rules": 2}, {"init": "grid", "n_mfs": 2}, {"init": "subtractive", "radius": 0.4}]
    # fold RMSEs: means 0.3, 0.19, 0.18; the best's sample std 0.03, its SE 0.03 / sqrt(3) = 0.0173
    folds = {2: [0.3, 0.3, 0.3], 8: [0.19, 0.19, 0.19], 30: [0.15, 0.18, 0.21]}
    results = [(rmse, rules, 0.1) for rules, values in folds.items() for rmse in values]
    _, record, _ = model_selection.summarise(candidates, results, 3, "one_se")
    models = {"check_rmse_target": [0.1, 0.2], "check_regret_mean": [1.01, 1.02], "check_regret_max": [1.1, 1.2]}
    record = record.assign({k: ("model", v, {"units": "1"}) for k, v in models.items()})
    return record.assign_coords(model=["anfis", "hgb"])


def test_selection_figure_shows_rules_against_cv_error_and_the_one_se_line():
    """Candidates at (rules, mean CV RMSE) with SE bars, the line at best + 1 SE, the one-SE choice ringed."""
    from uavdamp.plots.anfis import selection_figure

    record = _selection_record()
    fig = selection_figure(record)
    try:
        ax = fig.axes[0]
        lines = {line.get_label(): line for line in ax.get_lines()}
        bars = {c.get_label(): c for c in ax.containers}  # one errorbar per init: (data, caps, bars)
        assert set(bars) == {"fcm", "grid", "subtractive"}
        points = sorted(np.c_[c.lines[0].get_xdata(), c.lines[0].get_ydata()][0].tolist() for c in bars.values())
        np.testing.assert_allclose(points, [(2, 0.3), (8, 0.19), (30, 0.18)], rtol=1e-12)
        assert lines["best + 1 SE"].get_ydata()[0] == pytest.approx(0.18 + 0.03 / np.sqrt(3), rel=1e-12)
        assert record.attrs["selected_candidate"] == "grid n_mfs=2"
        np.testing.assert_allclose([lines["selected"].get_xdata()[0], lines["selected"].get_ydata()[0]], [8, 0.19])
        segment = bars["subtractive"].lines[2][0].get_segments()[0]  # its SE bar
        np.testing.assert_allclose(segment[:, 1], [0.18 - 0.03 / np.sqrt(3), 0.18 + 0.03 / np.sqrt(3)], rtol=1e-12)
        assert ax.get_xlabel().startswith("rules")
    finally:
        plt.close(fig)


def test_selection_figure_draws_the_checking_regret_as_points_not_bars():
    """Regret - 1 of the models (mean 0.01, 0.02; max 0.1, 0.2: two decades, a log axis) as points at the models'
    positions 0 and 1: a bar on a log axis has no base."""
    from uavdamp.plots.anfis import selection_figure

    fig = selection_figure(_selection_record())
    try:
        ax = next(ax for ax in fig.axes if ax.get_title() == "checking rows: regret")
        assert ax.get_yscale() == "log"
        assert not [c for c in ax.containers if isinstance(c, BarContainer)]
        points = {(round(float(x), 9), round(float(y), 9)) for line in ax.get_lines() for x, y in line.get_xydata()}
        assert {(0, 0.01), (1, 0.02), (0, 0.1), (1, 0.2)} <= points
    finally:
        plt.close(fig)


def test_membership_figure_tells_crowded_functions_apart_by_the_order_of_their_centres():
    """65 MFs per input: each trained curve thin and in its own colour, the colours following the order of the
    curves' centres along one colour map (so neighbours in the ordered panel share a shade)."""
    from uavdamp.plots.anfis import membership_figure

    model = _anfis(65)
    fig = membership_figure(model)
    try:
        for ax in fig.axes[:3]:
            trained = [line for line in ax.get_lines() if line.get_linestyle() == "-" and len(line.get_xdata()) > 2]
            assert len(trained) == 65
            assert max(line.get_linewidth() for line in trained) <= 1.0
            centres = [line.get_xdata()[np.argmax(line.get_ydata())] for line in trained]
            colours = [to_hex(trained[k].get_color()) for k in np.argsort(centres, kind="stable")]
            assert len(set(colours)) == 65, "one colour per MF"
            greens = [int(c[3:5], 16) for c in colours]  # viridis-like maps brighten along the order
            assert greens[0] < greens[32] < greens[-1]
    finally:
        plt.close(fig)
