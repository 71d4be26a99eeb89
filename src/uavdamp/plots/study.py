"""Study figures: analogues of the paper's Figs. 10-13 and every strategy side by side."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

COLOURS = {
    "rigid": "tab:gray",
    "passive": "tab:red",
    "optimal_passive": "tab:orange",
    "anfis": "tab:blue",
    "skyhook": "tab:green",
}
_OTHERS = ("tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan", "black")


def colour(strategy: str, names=()) -> str:
    """The colour of a strategy: fixed for the paper's ones, else by its position among the others in `names`."""
    if strategy in COLOURS:
        return COLOURS[strategy]
    others = [str(n) for n in names if str(n) not in COLOURS] or [strategy]
    return _OTHERS[others.index(strategy) % len(_OTHERS)] if strategy in others else _OTHERS[0]


def _mm(da: xr.DataArray) -> np.ndarray:
    return 1e3 * da.values


def _damping_axis(ax, values) -> None:
    """C axis: logarithmic only where C spans more than a decade; plain numbers, not 2 x 10^0, otherwise."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v) & (v > 0)]
    if v.size and v.max() / v.min() > 10:
        ax.set_yscale("log")
    else:
        ax.ticklabel_format(axis="y", style="plain", useOffset=False)


def rigid_mount_figure(ds: xr.Dataset, case: str, axis: str = "y", window_s: float = 2.0):
    """Fig. 10 analogue: the camera without isolation, with the input and the paper's 1.5 mm mark."""
    part = ds.sel(case=case, time=slice(0, window_s))
    fig, ax = plt.subplots(figsize=(8, 3.6), constrained_layout=True)
    ax.plot(part.time, _mm(part.mount_displacement.sel(mount_axis=axis)), color="0.6", lw=0.8, label="input (fuselage)")
    ax.plot(
        part.time,
        _mm(part.camera_displacement.sel(stiffness=ds.stiffness[0], strategy="rigid", axis=axis)),
        color="k",
        lw=1.2,
        label="camera, rigid mount",
    )
    for sign in (1, -1):
        ax.axhline(sign * 1.5, color="tab:red", ls=":", lw=0.8)
    ax.axvline(0.5, color="0.3", ls="--", lw=0.6)
    peak = 1e3 * float(ds.peak_early.sel(case=case, stiffness=ds.stiffness[0], strategy="rigid", axis=axis))
    ax.set(
        xlabel="time (s)",
        ylabel=f"{axis.upper()} displacement (mm)",
        title=f"{case}: camera {axis.upper()} without isolation (peak before 0.5 s: {peak:.2f} mm; paper: > 1.5 mm)",
    )
    ax.legend(fontsize=8)
    return fig


def passive_vs_anfis_figure(ds: xr.Dataset, case: str, axis: str, stiffness: float, window_s: float = 3.0):
    """Figs. 11 and 13 analogue: the camera with passive and with ANFIS semi-active damping, and C(t)."""
    part = ds.sel(case=case, stiffness=stiffness, time=slice(0, window_s))
    fig, (ax, axc) = plt.subplots(2, 1, figsize=(8, 5), sharex=True, height_ratios=[3, 1.3], constrained_layout=True)
    for strategy in ("passive", "anfis"):
        peak = 1e3 * float(ds.peak_early.sel(case=case, stiffness=stiffness, strategy=strategy, axis=axis))
        ax.plot(
            part.time,
            _mm(part.camera_displacement.sel(strategy=strategy, axis=axis)),
            color=colour(strategy),
            lw=1.1,
            label=f"{strategy} (peak before 0.5 s: {peak:.3f} mm)",
        )
        axc.step(part.time, part.damping.sel(strategy=strategy), where="post", color=colour(strategy))
    ax.axvline(0.5, color="0.3", ls="--", lw=0.6)
    ax.set(ylabel=f"camera {axis.upper()} (mm)", title=f"{case}, K = {stiffness:g} N/m: passive vs ANFIS semi-active")
    ax.legend(fontsize=8)
    axc.set(xlabel="time (s)", ylabel="C (N s/m)")
    _damping_axis(axc, part.damping.sel(strategy=["passive", "anfis"]).values)
    return fig


def tracked_frequency_figure(ds: xr.Dataset, case: str, axis: str = "z"):
    """Fig. 12 analogue: the dominant frequency of the input chosen at every update."""
    fig, ax = plt.subplots(figsize=(8, 3.4), constrained_layout=True)
    freq = ds.tracked_freq.sel(case=case, axis=axis)
    ax.plot(ds.update_time, freq, "o-", color="tab:blue", label=f"{axis.upper()}, tracked every update")
    ax.set(
        xlabel="time (s)",
        ylabel="dominant frequency (Hz)",
        title=f"{case}: dominant {axis.upper()} frequency seen by the controller (NaN before enough signal)",
    )
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def strategies_figure(ds: xr.Dataset, case: str, window_s: float = 3.0):
    """Every strategy side by side for one case: camera y and z and C(t) per stiffness, and the metrics."""
    n_k = ds.sizes["stiffness"]
    fig, axes = plt.subplots(n_k, 4, figsize=(18, 3.4 * n_k), constrained_layout=True, squeeze=False)
    part = ds.sel(case=case, time=slice(0, window_s))
    for row, k in enumerate(ds.stiffness.values):
        for col, axis in enumerate(("y", "z")):
            ax = axes[row, col]
            for strategy in ds.strategy.values:
                ax.plot(
                    part.time,
                    _mm(part.camera_displacement.sel(stiffness=k, strategy=strategy, axis=axis)),
                    color=colour(str(strategy), ds.strategy.values),
                    lw=0.9,
                    label=str(strategy),
                )
            ax.set(xlabel="time (s)", ylabel=f"camera {axis.upper()} (mm)", title=f"K = {k:g} N/m, {axis.upper()}")
            if row == 0 and col == 0:
                ax.legend(fontsize=7)
        ax = axes[row, 2]
        for strategy in ds.strategy.values:
            if strategy != "rigid":
                ax.step(
                    part.time,
                    part.damping.sel(stiffness=k, strategy=strategy),
                    where="post",
                    color=colour(str(strategy), ds.strategy.values),
                    lw=0.9,
                    label=str(strategy),
                )
        ax.set(xlabel="time (s)", ylabel="C (N s/m)", title=f"K = {k:g} N/m: damping")
        _damping_axis(ax, part.damping.sel(stiffness=k).values)
        ax = axes[row, 3]
        names = [str(s) for s in ds.strategy.values]
        x = np.arange(len(names))
        std = 1e3 * np.sqrt((ds.std_total.sel(case=case, stiffness=k) ** 2).sum("axis")).values
        peak = 1e3 * ds.peak_early.sel(case=case, stiffness=k).max("axis").values
        ax.bar(x - 0.2, std, 0.4, label="std, whole run (y, z combined)")
        ax.bar(x + 0.2, peak, 0.4, label="peak before 0.5 s (max over y, z)")
        ax.set_xticks(x, names, rotation=30, fontsize=8)
        ax.set(ylabel="mm", yscale="log", title=f"K = {k:g} N/m: metrics")
        ax.legend(fontsize=7)
    fig.suptitle(f"{case}: all strategies", fontsize=12)
    return fig


def blur_distribution_figure(ds: xr.Dataset):
    """Box plots of the per-frame blur (pixels) per strategy: one panel per case and stiffness, log scale, with
    the sharp-frame threshold (camera attrs of comparison.nc) as a dashed line."""
    cases, stiffness = ds.case.values, ds.stiffness.values
    names = [str(s) for s in ds.strategy.values]
    fig, axes = plt.subplots(
        cases.size,
        stiffness.size,
        figsize=(4.2 * stiffness.size, 3.4 * cases.size),
        squeeze=False,
        sharey=True,
        constrained_layout=True,
    )
    threshold = ds.attrs.get("camera_sharp_threshold_px")
    for i, case in enumerate(cases):
        for j, k in enumerate(stiffness):
            ax = axes[i, j]
            blur = ds.frame_blur.sel(case=case, stiffness=k)
            data = [blur.sel(strategy=s).values[np.isfinite(blur.sel(strategy=s).values)] for s in names]
            box = ax.boxplot(data, whis=(5, 95), showfliers=True, patch_artist=True, flierprops={"markersize": 2})
            for patch, name in zip(box["boxes"], names, strict=True):
                patch.set_facecolor(colour(name, names))
                patch.set_alpha(0.6)
            if threshold is not None:
                ax.axhline(float(threshold), color="k", ls="--", lw=0.8, label=f"sharp: <= {float(threshold):g} px")
                ax.legend(fontsize=7, loc="upper right")
            ax.set_xticks(np.arange(1, len(names) + 1), names, rotation=30, fontsize=8)
            ax.set(yscale="log", title=f"{case}, K = {k:g} N/m", ylabel="blur per frame (px)" if j == 0 else None)
            ax.grid(True, axis="y", which="both", alpha=0.3)
    fig.suptitle("Image blur per frame (whiskers: 5th-95th percentile)", fontsize=11)
    return fig


def sharp_fraction_figure(ds: xr.Dataset):
    """The fraction of sharp frames per strategy: grouped bars per case and stiffness."""
    names = [str(s) for s in ds.strategy.values]
    groups = [(str(c), float(k)) for c in ds.case.values for k in ds.stiffness.values]
    fig, ax = plt.subplots(figsize=(1.6 + 1.3 * len(groups) * len(names) / 4, 3.8), constrained_layout=True)
    width = 0.8 / len(names)
    x = np.arange(len(groups))
    for n, name in enumerate(names):
        values = [float(ds.sharp_fraction.sel(case=c, stiffness=k, strategy=name)) for c, k in groups]
        ax.bar(x - 0.4 + (n + 0.5) * width, values, width, color=colour(name, names), label=name)
    ax.set_xticks(x, [f"{c}\nK = {k:g} N/m" for c, k in groups], fontsize=8)
    threshold = ds.attrs.get("camera_sharp_threshold_px")
    rule = f"blur <= {float(threshold):g} px" if threshold is not None else "sharp"
    ax.set(ylim=(0, 1.05), ylabel=f"fraction of frames with {rule}", title="Sharp frames per strategy")
    ax.legend(fontsize=8, ncols=min(len(names), 5))
    ax.grid(True, axis="y", alpha=0.3)
    return fig
