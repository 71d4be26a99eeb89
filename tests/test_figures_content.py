"""Figures checked for content: the plotted data read back from the axes, not the PNG's size."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest
from conftest import displacement_grid as synthetic_grid
from conftest import vibration_dataset

from uavdamp.plots.helicopter import fuselage_vibration_figure
from uavdamp.plots.reference_table import GAIN_LABEL, SPREAD_LABEL, reference_table_figure
from uavdamp.reference_table import criteria as criterion


def test_reference_table_figure_shows_the_table():
    """The 7/3 fixture (tests/test_mutants_criterion.py): heatmaps hold damping_opt and the flat band per K; the
    right panel plots the spread (1, 8) and the scheduling gain (1, 7/3) against K."""
    values = np.ones((3, 3, 2, 4))
    values[..., 0, 2] = 0.5
    values[0, :, 1, 0] = 0.2
    values[1:, :, 1, 3] = 0.2
    table = criterion.select_table(criterion.reference_table(synthetic_grid(values)), "displacement", "transient")
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


def test_selection_figure_shows_rules_against_cv_error_and_the_one_se_line():
    """Candidates at (rules, mean CV RMSE) with SE bars, the line at best + 1 SE, the one-SE choice ringed."""
    from uavdamp.anfis import model_selection
    from uavdamp.plots.anfis import selection_figure

    candidates = [{"init": "fcm", "n_rules": 2}, {"init": "grid", "n_mfs": 2}, {"init": "subtractive", "radius": 0.4}]
    # fold RMSEs: means 0.3, 0.19, 0.18; the best's sample std 0.03, its SE 0.03 / sqrt(3) = 0.0173
    folds = {2: [0.3, 0.3, 0.3], 8: [0.19, 0.19, 0.19], 30: [0.15, 0.18, 0.21]}
    results = [(rmse, rules, 0.1) for rules, values in folds.items() for rmse in values]
    _, record, _ = model_selection.summarise(candidates, results, 3, "one_se")
    models = {"check_rmse_target": [0.1, 0.2], "check_regret_mean": [1.01, 1.02], "check_regret_max": [1.1, 1.2]}
    record = record.assign({k: ("model", v, {"units": "1"}) for k, v in models.items()})
    fig = selection_figure(record.assign_coords(model=["anfis", "hgb"]))
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
