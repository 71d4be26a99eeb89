"""Payload figures: the camera's line of sight (µrad rms) per payload and mount against the isolator's damping, one
panel per input, beside the gimbal makers' ±0.01° (175 µrad) angular-vibration anchor."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.legend_handler import HandlerTuple  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from uavdamp.contract import STANDARD_GRAVITY as G  # noqa: E402
from uavdamp.plots.style import number, plain_log_ticks  # noqa: E402

URAD_PER_RAD = 1e6
LAW_FILLS = {"six_axis": None, "wire_rope": "none"}  # the laws' markers per mount: filled (gimbal colour), hollow
HOLLOW_SCALE = 1.5  # a hollow marker's size over a filled one's: a ring around it where the two mounts agree
LAW_WORDS = {"six_axis": "filled six-axis", "wire_rope": "hollow wire rope"}
LAW_MARKERS = {  # the law runs' families (`_kind`): marker, size, legend text
    "skyhook": ("*", 10, "skyhook (x: c_on"),
    "scheduled": ("D", 6, "scheduled law (x: its mean C)"),
    "anfis": ("^", 7, "payload ANFIS (x: its mean C)"),
    "mr_held": ("s", 6, "MR damper at 0 / 2.25 V (x: its C)"),
    "mr_skyhook": ("P", 8, "MR damper, skyhook (x: C at 2.25 V)"),
    "mr_scheduled": ("X", 8, "MR damper, scheduled (x: mean C)"),
}
ANCHOR_URAD = 175.0  # ±0.01 deg: the angular vibration range gimbal makers quote (DJI)
FLOOR_URAD = 10.0  # the axes' lower limit: values below it are drawn on it as downward triangles
COLORS = {"paper_head": "tab:red", "balanced_head": "tab:orange", "gimbal": "tab:blue"}
STYLES = {"rigid": ":", "yz": "--", "six_axis": "-", "wire_rope": (0, (7, 2, 1, 2, 1, 2))}  # wire rope: dash-dot-dot
LABELS = {
    "paper_head": "paper's head",
    "balanced_head": "head, balanced",
    "gimbal": "stabilised gimbal",
    "rigid": "rigid",
    "yz": "Y-Z isolator",
    "six_axis": "six-axis isolator",
    "wire_rope": "six-axis, wire rope",
}


def line_of_sight_figure(ds: xr.Dataset) -> Figure:
    """LOS rms (µrad, log) against the constant damping C (N s/m, log) per payload (colour) and mount (line
    style), one panel per input (`input`); the rigid mount, which has no damper, is a level line; the gimbal's
    sensor-noise floor (`floor_los_std`) dash-dotted grey where present; the law runs (`LAW_MARKERS`: skyhook
    stars at their c_on, the scheduled law a diamond and the payload ANFIS a triangle at their mean C, the MR
    damper's runs squares, a plus and a cross) filled on the six-axis isolator, hollow on the wire rope; values
    below FLOOR_URAD on the axis as downward triangles."""
    inputs = [str(i) for i in ds.input.values]
    ncols = min(3, len(inputs))
    nrows = int(np.ceil(len(inputs) / ncols))
    fig = Figure(figsize=(4.6 * ncols + 2.2, 3.4 * nrows + 0.6), layout="constrained")
    axes = np.atleast_1d(fig.subplots(nrows, ncols, sharex=True, squeeze=False)).ravel()
    c = ds.damping.values
    los = ds.los_std * URAD_PER_RAD
    for ax, name in zip(axes, inputs, strict=False):
        for payload in ds.payload.values:
            for mount in ds.mount.values:
                y = los.sel(input=name, payload=payload, mount=mount).values
                if not np.any(np.isfinite(y)):
                    continue
                color, below = COLORS.get(str(payload)), y < FLOOR_URAD
                style = STYLES.get(str(mount), "-")
                ax.plot(c, np.maximum(y, FLOOR_URAD), ls=style, color=color, marker="o", ms=3, lw=1.3)
                if np.any(below):  # e.g. a balanced head under a source without rotation: no line of sight at all
                    ax.plot(c[below], np.full(below.sum(), FLOOR_URAD), "v", color=color, ms=7, clip_on=False)
        _laws(ax, ds, name)
        ax.axhline(ANCHOR_URAD, color="k", lw=0.8, alpha=0.6)
        ax.annotate("±0.01° (175 µrad)", (1.0, ANCHOR_URAD), xycoords=("axes fraction", "data"), ha="right",
                    va="bottom", fontsize=7, alpha=0.8)  # fmt: skip
        if "floor_los_std" in ds and "gimbal" in ds.payload.values:
            floor = float(ds.floor_los_std.sel(payload="gimbal")) * URAD_PER_RAD
            if floor > 0:
                ax.axhline(floor, color="0.5", lw=0.8, ls="-.")
                ax.annotate("gimbal's noise floor", (0.0, floor), xycoords=("axes fraction", "data"), ha="left",
                            va="top", fontsize=7, color="0.4")  # fmt: skip
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_ylim(bottom=FLOOR_URAD)
        plain_log_ticks(ax, "y")
        plain_log_ticks(ax, "x")
        title = str(ds.input_description.sel(input=name).item()) if "input_description" in ds else name
        ax.set_title(_wrap(f"{name}: {title}", 55), fontsize=9)
        ax.set_ylabel("line of sight rms (µrad)")
        ax.grid(True, which="both", alpha=0.3)
    for ax in axes[len(inputs) :]:
        ax.set_visible(False)
    for ax in axes[-ncols:]:
        ax.set_xlabel("damping C of the isolator's dampers (N s/m)")
    fig.legend(*_legend(ds), loc="outside right upper", fontsize=8, handler_map={tuple: HandlerTuple(ndivide=None)})
    window = f"over {number(float(ds.attrs.get('settle_s', 0)))}-{number(float(ds.attrs.get('duration_s', 0)))} s"
    fig.suptitle(f"Camera line of sight per payload and mount ({window})", fontsize=11)
    return fig


def _kind(law: str) -> str:
    """The figure's family of a law run: skyhook, scheduled, anfis, mr_held, mr_skyhook, mr_scheduled."""
    if law.startswith("skyhook_"):
        return "skyhook"
    return "mr_held" if law in ("mr_off", "mr_on") else law


def _laws(ax, ds: xr.Dataset, name) -> None:
    """The laws of input `name` on each mount they ran on (`LAW_MARKERS`), at their c_on (skyhook) or mean C;
    filled on the six-axis isolator, hollow on the wire rope."""
    if "law_los_std" not in ds:
        return
    x = ds.law_c_on.sel(input=name).values
    if "law_damping_mean" in ds:  # the x of a law without c_on
        x = np.where(np.isfinite(x), x, ds.law_damping_mean.sel(input=name).values)
    kinds = np.array([_kind(str(n)) for n in ds.law.values])
    for mount, fill in LAW_FILLS.items():
        if mount not in ds.mount.values:
            continue
        y = np.maximum(ds.law_los_std.sel(input=name, mount=mount).values * URAD_PER_RAD, FLOOR_URAD)
        for kind, (marker, size, _) in LAW_MARKERS.items():
            which = (kinds == kind) & np.isfinite(y)
            if which.any():
                ax.add_line(_marker(marker, fill, size, x[which], y[which]))


def _legend(ds: xr.Dataset) -> tuple[list, list[str]]:
    """Proxy entries: a colour per payload, a line style per mount, each family of law runs present (the anchor
    and the noise floor lines are labelled on the axes)."""
    handles = [Line2D([], [], color=COLORS.get(str(p)), lw=2) for p in ds.payload.values]
    labels = [LABELS.get(str(p), str(p)) for p in ds.payload.values]
    handles += [Line2D([], [], color="0.3", ls=STYLES.get(str(m), "-"), lw=1.3) for m in ds.mount.values]
    labels += [LABELS.get(str(m), str(m)) for m in ds.mount.values]
    if "law_los_std" not in ds:
        return handles, labels
    for kind, (marker, size, text) in LAW_MARKERS.items():
        names = [str(n) for n in ds.law.values if _kind(str(n)) == kind]
        mounts = [
            m for m in LAW_FILLS if m in ds.mount.values and np.isfinite(ds.law_los_std.sel(mount=m, law=names)).any()
        ]
        if not mounts:
            continue
        if kind == "skyhook":
            text = f"{text}; c_off {number(float(ds.damping.min()))} N s/m)"
        handles.append(tuple(_marker(marker, LAW_FILLS[m], size) for m in mounts))
        labels.append(f"gimbal, {text}:\n{' / '.join(LAW_WORDS[m] for m in mounts)}")
    return handles, labels


def _marker(marker: str, fill: str | None, size: float, x=(), y=()) -> Line2D:
    """A law's markers at (x, y): filled in the gimbal's colour (fill None) or hollow and larger."""
    size = size if fill is None else size * HOLLOW_SCALE
    return Line2D(x, y, ls="", marker=marker, mec=COLORS["gimbal"], mfc=fill or COLORS["gimbal"], mew=1.2, ms=size)


def _wrap(text: str, width: int) -> str:
    """Text broken at spaces into lines of at most `width` characters."""
    lines, line = [], ""
    for word in text.split():
        if line and len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}".strip()
    lines.append(line)
    return "\n".join(lines[:3]) + (" …" if len(lines) > 3 else "")


MOUNT_COLORS = {"rigid": "0.35", "yz": "tab:green", "six_axis": "tab:purple", "wire_rope": "tab:brown"}
MOUNT_WIDTHS = {"rigid": 3.2, "yz": 1.8, "six_axis": 1.4}  # wide to narrow: a curve another hides shows around it
CARRIED_STYLES = {"fixed": "--", "gimbal": "-"}
CARRIED_LABELS = {"fixed": "camera fixed to the mount", "gimbal": "stabilised gimbal"}


def transmissibility_figure(design: xr.Dataset) -> Figure:
    """The isolator makers' curves to the line of sight (`uavdamp.study.transmissibility`): top, |line of sight|
    per mount rotation about the same axis (rad/rad); middle, |line of sight| (all axes) per mount acceleration
    along x, y, z (µrad per g); mount by colour, fixed camera or gimbal by line style, the six-axis isolator's
    modes as ticks on the top axes; with a wire-rope mount, a bottom row of the isolators' per-axis curves
    (`uavdamp.study.payload_design.isolator_curves`). A zero response (a fixed camera on the rigid mount under a
    translation) is not drawn."""
    rows = 3 if "wire_rope_transmissibility" in design else 2
    fig = Figure(figsize=(14.0, 3.8 * rows), layout="constrained")
    axes = fig.subplots(rows, 3, sharex=True)
    f = design.frequency.values
    for row, (name, dim, scale) in enumerate(
        (("los_per_rotation", "axis", 1.0), ("los_per_acceleration", "direction", G * URAD_PER_RAD))
    ):
        for ax, label in zip(axes[row], design[dim].values, strict=True):
            drawn = 0
            for mount in design.mount.values:
                for carried in design.carried.values:
                    y = design[name].sel({"mount": mount, "carried": carried, dim: label}).values * scale
                    y = np.where(y > 1e-12 * scale, y, np.nan)  # zero to rounding: none
                    color, style = MOUNT_COLORS.get(str(mount)), CARRIED_STYLES.get(str(carried))
                    drawn += int(np.any(np.isfinite(y)))
                    ax.plot(f, y, style, color=color, lw=MOUNT_WIDTHS.get(str(mount), 1.4), alpha=0.85)
            _mode_ticks(ax, design)
            ax.set_xscale("log")
            if drawn:
                ax.set_yscale("log")
            else:
                ax.text(0.5, 0.5, "no line of sight on any mount", transform=ax.transAxes, ha="center", va="center")
                ax.set_yticks([])
            ax.grid(True, which="both", alpha=0.3)
            plain_log_ticks(ax, "x")
            if row == 0:
                ax.set_title(f"{label}: line of sight per mount {label}", fontsize=10)
                ax.set_ylabel("line of sight / mount rotation (rad/rad)")
            else:
                ax.set_title(f"all axes: line of sight per mount acceleration along {label}", fontsize=10)
                ax.set_ylabel("line of sight (µrad per g)")
                ax.set_xlabel("frequency of the mount's sine motion (Hz)")
    if rows == 3:
        _isolator_row(axes[2], design)
        for ax in axes[1]:
            ax.set_xlabel("")
    fig.legend(*_transmissibility_legend(design), loc="outside right upper", fontsize=8)
    damping = number(float(design.attrs.get("damping_N_s_m", np.nan)))
    title = f"Mount motion to camera line of sight, closed form (isolators at C = {damping} N s/m)"
    if rows == 3:
        title += "\nbottom row: the isolators per axis (the wire rope in the time domain, per sine amplitude)"
    fig.suptitle(title, fontsize=11)
    return fig


AMPLITUDE_STYLES = ("-", "--", ":")  # the wire rope's curves, smallest amplitude first


def _isolator_row(axes, design: xr.Dataset) -> None:
    """The isolator maker's per-axis curves: the six-axis isolator's closed form and the wire rope's at each
    amplitude (time domain), payload translation per mount translation along x, y, z."""
    f = design.isolator_frequency.values
    for ax, direction in zip(axes, design.direction.values, strict=True):
        y = design.six_axis_transmissibility.sel(direction=direction).values
        ax.plot(f, y, color=MOUNT_COLORS["six_axis"], lw=3.0, alpha=0.6, label="six-axis (closed form)")
        for style, amplitude in zip(AMPLITUDE_STYLES, design.excitation_amplitude.values, strict=False):
            y = design.wire_rope_transmissibility.sel(direction=direction, excitation_amplitude=amplitude).values
            label = f"wire rope, {number(float(amplitude) * 1e3)} mm sine"
            ax.plot(f, y, style, color=MOUNT_COLORS["wire_rope"], lw=1.4, marker="o", ms=2.5, label=label)
        ax.axhline(1.0, color="0.5", lw=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
        plain_log_ticks(ax, "x")
        plain_log_ticks(ax, "y")
        ax.set_title(f"{direction}: the isolator alone, payload / mount translation", fontsize=10)
        ax.set_ylabel("transmissibility (m/m)")
        ax.set_xlabel("frequency of the mount's sine motion (Hz)")
    axes[0].legend(fontsize=7, loc="lower left")


def _mode_ticks(ax, design: xr.Dataset) -> None:
    """The six-axis isolator's rigid-body modes as short ticks at the top of the axes."""
    if "mode_frequency" not in design or "six_axis" not in design.mount.values:
        return
    for mode in design.mode_frequency.sel(mount="six_axis").values:
        if np.isfinite(mode):
            ax.axvline(mode, ymin=0.93, ymax=1.0, color=MOUNT_COLORS["six_axis"], lw=1.5)


def _transmissibility_legend(design: xr.Dataset) -> tuple[list, list[str]]:
    drawn = [m for m in design.mount.values if np.isfinite(design.los_per_rotation.sel(mount=m)).any()]
    handles = [Line2D([], [], color=MOUNT_COLORS.get(str(m)), lw=MOUNT_WIDTHS.get(str(m), 2)) for m in drawn]
    labels = [LABELS.get(str(m), str(m)) for m in drawn]
    handles += [Line2D([], [], color="0.3", ls=CARRIED_STYLES.get(str(c)), lw=1.4) for c in design.carried.values]
    labels += [CARRIED_LABELS.get(str(c), str(c)) for c in design.carried.values]
    if "mode_frequency" in design and "six_axis" in design.mount.values:
        handles.append(Line2D([], [], color=MOUNT_COLORS["six_axis"], lw=1.5))
        labels.append("six-axis isolator modes (ticks)")
    return handles, labels
