"""Study figures: analogues of the paper's Figs. 10-13 and every strategy side by side."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from uavdamp.plots.style import (  # noqa: E402
    TIME_WINDOW_S,
    early_peak,
    move_from_start,
    plain_log_ticks,
    stiffness_label,
    time_window_label,
)

COLOURS = {
    "rigid": "tab:gray",
    "passive": "tab:red",
    "optimal_passive": "tab:orange",
    "anfis": "tab:blue",
    "skyhook": "tab:green",
}
_OTHERS = ("tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan", "black")
LINESTYLES = {"rigid": "-", "passive": "--", "optimal_passive": "-.", "anfis": "-", "skyhook": ":"}
_OTHER_STYLES = ((0, (5, 1, 1, 1)), (0, (3, 1, 1, 1, 1, 1)), (0, (1, 1)), (0, (8, 2)))
# a law that changes C more often than this (changes per s) is drawn as its running mean over MEAN_WINDOW_S
FAST_SWITCHING_PER_S = 10.0
MEAN_WINDOW_S = 0.1


def colour(strategy: str, names=()) -> str:
    """The colour of a strategy: fixed for the paper's ones, else by its position among the others in `names`."""
    if strategy in COLOURS:
        return COLOURS[strategy]
    others = [str(n) for n in names if str(n) not in COLOURS] or [strategy]
    return _OTHERS[others.index(strategy) % len(_OTHERS)] if strategy in others else _OTHERS[0]


def linestyle(strategy: str, names=()) -> str | tuple:
    """The line style of a strategy (colour alone does not separate five overlapping lines)."""
    if strategy in LINESTYLES:
        return LINESTYLES[strategy]
    others = [str(n) for n in names if str(n) not in LINESTYLES] or [strategy]
    return _OTHER_STYLES[others.index(strategy) % len(_OTHER_STYLES)] if strategy in others else "-"


def _style(strategy: str, names=()) -> dict:
    """Colour, style and width of a strategy's line; the rigid mount drawn wide and light, behind the others."""
    if strategy == "rigid":
        return {"color": colour(strategy), "ls": "-", "lw": 2.2, "alpha": 0.45, "zorder": 1}
    return {"color": colour(strategy, names), "ls": linestyle(strategy, names), "lw": 1.2, "zorder": 2}


def _mm_from_start(da: xr.DataArray) -> np.ndarray:
    """Displacement in mm relative to its value at t = 0 (the input's offset; `style.move_from_start`)."""
    return 1e3 * move_from_start(da.values)


def _fast_switching(time: np.ndarray, damping: np.ndarray) -> bool:
    """True when C changes more than FAST_SWITCHING_PER_S times per second (an on-off law switching every step)."""
    finite = np.isfinite(damping)
    if finite.sum() < 2 or time[-1] <= time[0]:
        return False
    changes = np.count_nonzero(np.diff(damping[finite]))
    return changes / (time[-1] - time[0]) > FAST_SWITCHING_PER_S


def _running_mean(time: np.ndarray, values: np.ndarray, window_s: float) -> np.ndarray:
    """Centred running mean over `window_s` (samples uniform in time; shorter windows at the ends)."""
    n = max(1, int(round(window_s / (time[1] - time[0]))))
    kernel = np.ones(n)
    return np.convolve(values, kernel, mode="same") / np.convolve(np.ones_like(values), kernel, mode="same")


def _damping_axis(ax, values) -> None:
    """C axis: logarithmic only where C spans more than a decade; plain numbers, not 2 x 10^0, otherwise."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v) & (v > 0)]
    if v.size and v.max() / v.min() > 10:
        ax.set_yscale("log")
        plain_log_ticks(ax)
    else:
        ax.ticklabel_format(axis="y", style="plain", useOffset=False)


def rigid_mount_figure(
    ds: xr.Dataset, case: str, axis: str = "y", window_s: float = TIME_WINDOW_S, early_s: float = 0.5
):
    """Fig. 10 analogue: the camera without isolation, with the input and the paper's 1.5 mm mark, over the first
    `window_s` of the run (`style.TIME_WINDOW_S`).

    Both curves are drawn relative to their value at t = 0 (the input's offset: `style.move_from_start`); the
    title's peak is the largest such move up to `early_s`."""
    full = ds.sel(case=case)
    part = full.sel(time=slice(0, window_s))
    camera = full.camera_displacement.sel(stiffness=ds.stiffness[0], strategy="rigid", axis=axis)
    fig, ax = plt.subplots(figsize=(8, 3.8), constrained_layout=True)
    ax.plot(part.time, _mm_from_start(part.mount_displacement.sel(mount_axis=axis)), color="0.6", lw=0.8, label="input")
    ax.plot(part.time, _mm_from_start(camera.sel(time=slice(0, window_s))), color="k", lw=1.2, label="camera")
    for sign in (1, -1):
        ax.axhline(sign * 1.5, color="tab:red", ls=":", lw=0.8, label="paper: 1.5 mm" if sign > 0 else None)
    ax.axvline(early_s, color="0.3", ls="--", lw=0.6)
    peak, at = early_peak(camera.time.values, 1e3 * camera.values, early_s)
    ax.plot(at, float(np.sign(_mm_from_start(camera)[camera.time.values == at][0])) * peak, "o", color="tab:red")
    ax.set(
        xlabel=time_window_label(full.time.values, window_s),
        ylabel=f"{axis.upper()} from its start (mm)",
        title=f"{case}: camera {axis.upper()} on a rigid mount\n"
        f"largest move from the start before {early_s:g} s (dot): {peak:.2f} mm; paper: > 1.5 mm",
    )
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    return fig


def passive_vs_anfis_figure(
    ds: xr.Dataset, case: str, axis: str, stiffness: float, window_s: float = TIME_WINDOW_S, early_s: float = 0.5
):
    """Figs. 11 and 13 analogue: the camera with passive and with ANFIS semi-active damping, and C(t), over the
    first `window_s` of the run (`style.TIME_WINDOW_S`).

    The camera is drawn relative to its value at t = 0 (the input's offset, the same for both: the platform
    starts at rest there; `style.move_from_start`); each legend entry gives the largest such move up to
    `early_s`, marked on its curve."""
    full = ds.sel(case=case, stiffness=stiffness)
    part = full.sel(time=slice(0, window_s))
    fig, (ax, axc) = plt.subplots(2, 1, figsize=(8, 5.2), sharex=True, height_ratios=[3, 1.3], constrained_layout=True)
    for strategy in ("passive", "anfis"):
        camera = full.camera_displacement.sel(strategy=strategy, axis=axis)
        peak, at = early_peak(camera.time.values, 1e3 * camera.values, early_s)
        move = _mm_from_start(camera)
        ax.plot(
            part.time,
            move[: part.sizes["time"]],
            color=colour(strategy),
            ls=linestyle(strategy),
            lw=1.2,
            label=f"{strategy}: {peak:.3f} mm at {at:.2f} s",
        )
        ax.plot(at, move[camera.time.values == at][0], "o", color=colour(strategy), ms=5)
        axc.step(
            part.time, part.damping.sel(strategy=strategy), where="post", color=colour(strategy), ls=linestyle(strategy)
        )
    ax.axvline(early_s, color="0.3", ls="--", lw=0.6)
    ax.set(ylabel=f"camera {axis.upper()} from its start (mm)")
    fig.suptitle(f"{case}, {stiffness_label(stiffness)}: passive vs ANFIS semi-active")
    fig.legend(
        *ax.get_legend_handles_labels(),
        fontsize=8,
        title=f"largest move from the start before {early_s:g} s (dot)",
        title_fontsize=8,
        loc="outside lower center",
        ncols=2,
    )
    axc.set(xlabel=time_window_label(full.time.values, window_s), ylabel="C (N s/m)")
    _damping_axis(axc, part.damping.sel(strategy=["passive", "anfis"]).values)
    return fig


def tracked_frequency_figure(ds: xr.Dataset, case: str, axis: str = "z"):
    """Fig. 12 analogue: the dominant frequency of the input chosen at every update.

    Updates without an estimate (NaN: not enough signal yet) are marked on the time axis; the title says how
    many there are."""
    fig, ax = plt.subplots(figsize=(8, 3.4), constrained_layout=True)
    freq = ds.tracked_freq.sel(case=case, axis=axis)
    ax.plot(ds.update_time, freq, "o-", color="tab:blue", label="estimate")
    missing = ~np.isfinite(freq.values)
    if missing.any():
        ax.plot(
            ds.update_time.values[missing],
            np.full(missing.sum(), 0.0),
            "x",
            color="tab:red",
            transform=ax.get_xaxis_transform(),
            clip_on=False,
            label="no estimate (NaN)",
        )
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    note = (
        f"{int(missing.sum())} of {missing.size} updates without an estimate"
        if missing.any()
        else "an estimate at every update"
    )
    ax.set(
        xlabel="time (s)",
        ylabel="dominant frequency (Hz)",
        xlim=(0, float(ds.update_time.max()) * 1.03),
        title=f"{case}: dominant {axis.upper()} frequency tracked by the controller ({note})",
    )
    ax.grid(alpha=0.3)
    return fig


def _camera_panel(ax, part: xr.Dataset, k: float, axis: str, names: list[str]) -> None:
    """Camera `axis` of every strategy from its start; the rigid mount clipped where its scale would hide the rest."""
    moves = {s: _mm_from_start(part.camera_displacement.sel(stiffness=k, strategy=s, axis=axis)) for s in names}
    for strategy, move in moves.items():
        ax.plot(part.time.values, move, **_style(strategy, names))
    title = f"{stiffness_label(k)}, {axis.upper()}"
    isolated = [np.nanmax(np.abs(m)) for s, m in moves.items() if s != "rigid"]
    if "rigid" in moves and isolated and np.nanmax(np.abs(moves["rigid"])) > 2.5 * max(isolated):
        ax.set_ylim(-1.15 * max(isolated), 1.15 * max(isolated))  # the rigid mount's scale would hide them
        title += " (rigid clipped)"
    ax.set(ylabel=f"camera {axis.upper()} from start (mm)", title=title)


def _damping_panel(ax, part: xr.Dataset, k: float, names: list[str]) -> set[str]:
    """C(t) of every isolated strategy; returns the fast-switching ones, drawn as their running mean."""
    time, shown, averaged = part.time.values, [], set()
    for strategy in names:
        damping = part.damping.sel(stiffness=k, strategy=strategy).values
        if strategy == "rigid" or not np.isfinite(damping).any():
            continue
        if _fast_switching(time, damping):
            averaged.add(strategy)
            damping = _running_mean(time, damping, MEAN_WINDOW_S)
            ax.plot(time, np.where(damping > 0, damping, np.nan), **_style(strategy, names))
        else:
            ax.step(time, damping, where="post", **_style(strategy, names))
        shown.append(damping)
    ax.set(ylabel="C (N s/m)", title=f"{stiffness_label(k)}: damping")
    _damping_axis(ax, np.concatenate(shown) if shown else [])
    return averaged


# the metrics panel's markers (a log axis: points, not bars, which would need a base)
STD_MARKER, PEAK_MARKER = "o", "D"


def _metrics_panel(ax, full: xr.Dataset, k: float, names: list[str], early_s: float) -> None:
    """Per strategy: the std over the whole run (filled dot) and the largest move before `early_s` (hollow
    diamond), on a log axis."""
    x = np.arange(len(names))
    std = 1e3 * np.sqrt((full.std_total.sel(stiffness=k) ** 2).sum("axis")).values
    camera = full.camera_displacement.sel(stiffness=k)
    time = full.time.values
    peak = [max(early_peak(time, 1e3 * camera.sel(strategy=s, axis=a), early_s)[0] for a in ("y", "z")) for s in names]
    for i, name in enumerate(names):
        c = colour(name, names)
        ax.plot(x[i] - 0.12, std[i], STD_MARKER, color=c, ms=7, ls="none")
        ax.plot(x[i] + 0.12, peak[i], PEAK_MARKER, mfc="none", mec=c, mew=1.6, ms=7, ls="none")
    ax.set_xticks(x, names, rotation=30, ha="right", fontsize=8)
    ax.set(ylabel="camera (mm)", yscale="log", title=f"{stiffness_label(k)}: metrics", xlim=(-0.6, len(names) - 0.4))
    ax.margins(y=0.12)
    plain_log_ticks(ax)
    ax.grid(True, axis="y", which="both", alpha=0.3)


def strategies_figure(ds: xr.Dataset, case: str, window_s: float = TIME_WINDOW_S, early_s: float = 0.5):
    """Every strategy side by side for one case: camera y and z and C(t) per stiffness over the first `window_s`
    of the run (`style.TIME_WINDOW_S`), and the metrics (markers on a log axis).

    Camera displacements are drawn from their value at t = 0 (the input's offset). A law switching faster than
    FAST_SWITCHING_PER_S is drawn as its running mean over MEAN_WINDOW_S, so it does not hide the others. One
    legend (strategies) and one key (metrics) beside the panels."""
    names = [str(s) for s in ds.strategy.values]
    n_k = ds.sizes["stiffness"]
    fig, axes = plt.subplots(
        n_k, 4, figsize=(16, 3.2 * n_k + 0.9), layout="constrained", squeeze=False, width_ratios=[1.2, 1.2, 1, 1]
    )
    full = ds.sel(case=case)
    part = full.sel(time=slice(0, window_s))
    averaged = set()
    for row, k in enumerate(ds.stiffness.values):
        for col, axis in enumerate(("y", "z")):
            _camera_panel(axes[row, col], part, k, axis, names)
        averaged |= _damping_panel(axes[row, 2], part, k, names)
        _metrics_panel(axes[row, 3], full, k, names, early_s)
    for ax in axes[-1, :3]:
        ax.set_xlabel(time_window_label(full.time.values, window_s))
    lines = [
        Line2D(
            [],
            [],
            **{**_style(s, names), "zorder": None},
            label=s + (f" (mean over {MEAN_WINDOW_S:g} s)" if s in averaged else ""),
        )
        for s in names
    ]
    fig.legend(handles=lines, loc="outside right upper", fontsize=8, title="strategy", title_fontsize=8)
    keys = [
        Line2D([], [], marker=STD_MARKER, color="0.4", ls="none", label="std, whole run\n(y, z combined)"),
        Line2D(
            [],
            [],
            marker=PEAK_MARKER,
            mfc="none",
            mec="0.4",
            mew=1.6,
            ls="none",
            label=f"largest move\nbefore {early_s:g} s\n(max of y, z)",
        ),
    ]
    fig.legend(handles=keys, loc="outside right lower", fontsize=8, title="metrics", title_fontsize=8)
    fig.suptitle(f"{case}: all strategies (camera drawn from its position at t = 0)", fontsize=12)
    return fig


def blur_distribution_figure(ds: xr.Dataset):
    """Box plots of the per-frame blur (pixels) per strategy: one panel per case and stiffness, log scale, with
    the sharp-frame threshold (camera attrs of comparison.nc) as a dashed line; medians black."""
    cases, stiffness = ds.case.values, ds.stiffness.values
    names = [str(s) for s in ds.strategy.values]
    fig, axes = plt.subplots(
        cases.size,
        stiffness.size,
        figsize=(4.2 * stiffness.size, 3.4 * cases.size + 0.4),
        squeeze=False,
        sharey=True,
        layout="constrained",
    )
    threshold = ds.attrs.get("camera_sharp_threshold_px")
    for i, case in enumerate(cases):
        for j, k in enumerate(stiffness):
            ax = axes[i, j]
            blur = ds.frame_blur.sel(case=case, stiffness=k)
            data = [blur.sel(strategy=s).values[np.isfinite(blur.sel(strategy=s).values)] for s in names]
            box = ax.boxplot(
                data,
                whis=(5, 95),
                showfliers=True,
                patch_artist=True,
                flierprops={"markersize": 2},
                medianprops={"color": "k", "lw": 1.6},
            )
            for patch, name in zip(box["boxes"], names, strict=True):
                patch.set_facecolor(colour(name, names))
                patch.set_alpha(0.6)
            if threshold is not None:
                ax.axhline(float(threshold), color="k", ls="--", lw=0.8)
            ax.set_xticks(np.arange(1, len(names) + 1), names, rotation=30, ha="right", fontsize=8)
            ax.set(
                yscale="log", title=f"{case}, {stiffness_label(k)}", ylabel="blur per frame (px)" if j == 0 else None
            )
            ax.grid(True, axis="y", which="both", alpha=0.3)
    handles = [Line2D([], [], color="k", lw=1.6, label="median")]
    if threshold is not None:
        handles.append(Line2D([], [], color="k", ls="--", lw=0.8, label=f"sharp: <= {float(threshold):g} px"))
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), fontsize=8)
    fig.suptitle("Image blur per frame (boxes: quartiles; whiskers: 5th-95th percentile)", fontsize=11)
    return fig


def sharp_fraction_figure(ds: xr.Dataset):
    """The fraction of sharp frames per strategy: grouped bars per case and stiffness, the legend beside. The
    axis runs from 0 to just above the largest fraction (the fractions may all be small)."""
    names = [str(s) for s in ds.strategy.values]
    groups = [(str(c), float(k)) for c in ds.case.values for k in ds.stiffness.values]
    fig, ax = plt.subplots(figsize=(2.8 + 1.3 * len(groups) * len(names) / 4, 3.8), layout="constrained")
    width = 0.8 / len(names)
    x = np.arange(len(groups))
    for n, name in enumerate(names):
        values = [float(ds.sharp_fraction.sel(case=c, stiffness=k, strategy=name)) for c, k in groups]
        ax.bar(x - 0.4 + (n + 0.5) * width, values, width, color=colour(name, names), label=name)
    ax.set_xticks(x, [f"{c}\n{stiffness_label(k)}" for c, k in groups], fontsize=8)
    threshold = ds.attrs.get("camera_sharp_threshold_px")
    rule = f"blur <= {float(threshold):g} px" if threshold is not None else "sharp"
    top = float(np.nanmax(ds.sharp_fraction.values, initial=0.0))
    ax.set(
        ylim=(0, min(1.05, 1.15 * top) if top > 0 else 0.05),
        ylabel=f"sharp frames ({rule})\n/ all frames of the run (1)",
        title="Sharp frames per strategy: share of each run's frames",
    )
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    ax.grid(True, axis="y", alpha=0.3)
    return fig
