"""Figures checked for content: the plotted data read back from the axes, not the PNG's size."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr
from conftest import displacement_grid as synthetic_grid

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
    ds = xr.Dataset(
        {
            "mount_displacement": (("rotor", "mount", "axis", "time"), disp[:, None]),
            "amplitude_spectrum": (("rotor", "mount", "axis", "omega"), np.ones((2, 1, 3, omega.size)) * 1e-4),
            "dominant_omega": (("rotor", "mount", "axis"), np.array([[[0.0, 44.0, 50.3]], [[0.0, 44.0, 50.3]]])),
        },
        coords={
            "rotor": ["imbalanced", "balanced"],
            "mount": ["cg"],
            "axis": ["x", "y", "z"],
            "time": t,
            "omega": omega,
        },
    )
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
