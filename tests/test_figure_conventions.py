"""The conventions the figures share: titles inside the figure, metrics as points on log axes (no bars, which have
no base there), and one time window across the time-series figures, said on their axes."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from conftest import vibration_dataset  # noqa: E402
from test_figures_readable import bars_on_log_axes, offset_study, texts_off_the_figure  # noqa: E402

from uavdamp.plots import anfis, helicopter, study, style  # noqa: E402


def test_the_training_figure_titles_fit_the_figure():
    """A record of 50 epochs and 20 samples with the quick run's scores: the right panel's title fits."""
    epoch, reference = np.arange(1, 51), np.geomspace(0.4, 200, 20)
    record = xr.Dataset(
        {
            "train_rmse": ("epoch", 0.1 / epoch, {"units": "1", "long_name": "training RMSE of log10_C"}),
            "validation_rmse": ("epoch", 0.4 + 0.1 / epoch),
            "is_training": ("sample", (np.arange(20) % 5 != 0).astype(int)),
            "damping_reference": ("sample", reference),
            "damping_predicted": ("sample", 1.3 * reference),
        },
        coords={"epoch": epoch},
        attrs={"epoch_selection": "validation", "best_epoch": 26, "check_median_relative_error": 0.38},
    )
    fig = anfis.training_figure(record.assign_attrs(check_regret_mean=1.354))
    try:
        fig.draw_without_rendering()
        assert not texts_off_the_figure(fig)
    finally:
        plt.close(fig)


def metrics_study() -> xr.Dataset:
    """`offset_study` with its whole-run std per axis (as the study writes it) for the metrics panel."""
    ds = offset_study()
    ds["std_total"] = ds.camera_displacement.std("time")
    return ds


def test_the_strategy_metrics_are_points_on_their_log_axis():
    """Per strategy: the std over the whole run (y and z combined) and the largest move from the start before
    0.5 s, both from the construction; drawn as points (a bar on a log axis has no base)."""
    ds = metrics_study()
    fig = study.strategies_figure(ds, "case2")
    try:
        assert not bars_on_log_axes(fig)
        ax = next(ax for ax in fig.axes if ax.get_title().endswith("metrics"))
        assert ax.get_yscale() == "log"
        drawn = np.concatenate([line.get_ydata() for line in ax.get_lines() if len(line.get_ydata())])
        t = ds.time.values
        for strategy in ("passive", "anfis"):
            camera = 1e3 * ds.camera_displacement.sel(case="case2", stiffness=10.0, strategy=strategy).values
            std = np.sqrt((camera.std(axis=-1) ** 2).sum())
            peak = np.abs(camera - camera[:, :1])[:, t <= 0.5].max()
            assert np.isclose(drawn, std, rtol=1e-9).any() and np.isclose(drawn, peak, rtol=1e-9).any()
    finally:
        plt.close(fig)


def window_study() -> xr.Dataset:
    """`metrics_study` (3 s) with a rigid mount and the input (mount_displacement) the rigid-mount figure draws."""
    ds = metrics_study()
    rigid = ds.isel(strategy=[0]).assign_coords(strategy=["rigid"])
    ds = xr.concat([rigid, ds], dim="strategy")
    mount = np.broadcast_to(ds.camera_displacement.values[0, 0, 0, 0], (1, 3, ds.sizes["time"]))
    return ds.assign(mount_displacement=(("case", "mount_axis", "time"), mount.copy())).assign_coords(
        mount_axis=["x", "y", "z"]
    )


def shown_window(fig) -> dict[str, float]:
    """{time axis label: the latest time drawn} over the panels whose x axis is time."""
    return {
        ax.get_xlabel(): max(float(np.max(line.get_xdata())) for line in ax.get_lines() if len(line.get_xdata()) > 2)
        for ax in fig.axes
        if ax.get_xlabel().startswith("time")
    }


def test_every_time_series_figure_shows_the_same_window_and_says_so():
    """The study's 3 s run and the fuselage's 8 s run, each longer than the window: every time-series figure, at
    its defaults, draws the same first seconds, and its time axis says how many of how long a run."""
    ds = window_study()
    t = np.arange(0, 8 + 1e-9, 0.01)
    omega = np.linspace(0, 200, 201)
    vibration = vibration_dataset(t, omega, np.ones((2, 3, t.size)), np.ones((2, 3, omega.size)), np.ones((2, 3)))
    figures = {
        "fig10": study.rigid_mount_figure(ds, "case2", "y"),
        "fig11": study.passive_vs_anfis_figure(ds, "case2", "y", 10.0),
        "strategies": study.strategies_figure(ds, "case2"),
        "fuselage": helicopter.fuselage_vibration_figure(vibration),
    }
    try:
        shown = {name: shown_window(fig) for name, fig in figures.items()}
        windows = {round(w, 6) for labels in shown.values() for w in labels.values()}
        assert len(windows) == 1, f"time windows differ between figures: {shown}"
        assert windows == {style.TIME_WINDOW_S}
        run = {"fig10": 3, "fig11": 3, "strategies": 3, "fuselage": 8}
        for name, labels in shown.items():
            for label in labels:
                assert f"first {style.TIME_WINDOW_S:g} s of the {run[name]} s run" in label, (name, label)
    finally:
        for fig in figures.values():
            plt.close(fig)
