"""Levels figure: every input's lines at the mount (g), its lateral 1/rev (in/s) against the track-and-balance
limit and its VIBE against ArduPilot's guidance, one row per input (`uavdamp.sources.levels_survey.survey`)."""

from __future__ import annotations

import re

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from uavdamp.plots.style import plain_log_ticks  # noqa: E402
from uavdamp.sources.levels import (  # noqa: E402
    TRACK_AND_BALANCE_DAMAGE_IN_S,
    TRACK_AND_BALANCE_LIMIT_IN_S,
    VIBE_GUIDANCE_M_S2,
)

# g 0-peak, the order of magnitude of a fuselage's N/rev lines the figure shades (assumption: no table read)
N_PER_REV_BAND_G = (0.05, 0.5)
# each panel's range; a value below it is drawn on its left edge as a left-pointing triangle
LIMITS = {"g": (1e-5, 10.0), "in_s": (1e-3, 100.0), "vibe": (1e-2, 100.0)}
CATEGORIES = {  # line category -> marker, colour
    "1/rev": ("o", "tab:red"),
    "2/rev to (N-1)/rev": ("^", "tab:orange"),
    "N/rev and harmonics": ("s", "tab:blue"),
    "tail rotor": ("D", "tab:green"),
    "multirotor blade pass": ("v", "tab:purple"),
    "log's band peak": ("x", "black"),
}


def category(name: str, blades: int) -> str:
    """A line's category by its name ("k/rev", "tail ...", "motor ...", "peak ...") and the main rotor's blades."""
    found = re.fullmatch(r"(\d+)/rev", name)
    if found:
        k = int(found.group(1))
        return "1/rev" if k == 1 else ("N/rev and harmonics" if k % blades == 0 else "2/rev to (N-1)/rev")
    for prefix, cat in (("tail", "tail rotor"), ("motor", "multirotor blade pass"), ("peak", "log's band peak")):
        if name.startswith(prefix):
            return cat
    raise ValueError(f"line {name!r}: no category")


def levels_figure(ds: xr.Dataset) -> Figure:
    """Three panels sharing one row per input: each line's largest axis (g, log) with the N/rev band shaded, the
    lateral 1/rev velocity (in/s, log) against the limit and the damage level, the largest axis's VIBE (m s-2);
    each on its `LIMITS`, a value below them as a triangle on the left edge."""
    inputs = [str(i) for i in ds.input.values]
    rows = np.arange(len(inputs))[::-1]
    fig = Figure(figsize=(15.5, 0.36 * len(inputs) + 2.0), layout="constrained")
    ax_g, ax_v, ax_vibe = fig.subplots(1, 3, sharey=True, width_ratios=(1.4, 1.0, 1.0))
    ax_g.axvspan(*N_PER_REV_BAND_G, color="tab:blue", alpha=0.12, lw=0, label="fuselage N/rev, order (assumption)")
    blades = int(ds.attrs.get("rotor_blades", 4))
    seen = set()
    for row, name in zip(rows, inputs, strict=True):
        one = ds.sel(input=name)
        for k, line in enumerate(one.line_name.values):
            g = float(one.accel_g.isel(line=k).max())
            if not line or not g > 0:
                continue
            cat = category(str(line), blades)
            marker, colour = CATEGORIES[cat]
            ax_g.plot(
                max(g, LIMITS["g"][0]), row, marker, color=colour, mfc="none", ms=6, label=None if cat in seen else cat
            )
            seen.add(cat)
            if g < LIMITS["g"][0]:
                ax_g.plot(LIMITS["g"][0], row, "<", color=colour, ms=6)
    _stems(ax_v, rows, ds.track_and_balance_ratio.values * TRACK_AND_BALANCE_LIMIT_IN_S, "tab:red", LIMITS["in_s"])
    for x, text, style in (
        (TRACK_AND_BALANCE_LIMIT_IN_S, "track-and-balance limit", "--"),
        (TRACK_AND_BALANCE_DAMAGE_IN_S, "may damage the aircraft", ":"),
    ):
        ax_v.axvline(x, color="black", ls=style, lw=1, label=f"{x:g} in/s: {text}")
    _stems(ax_vibe, rows, ds.vibe_m_s2.max("axis").values, "tab:grey", LIMITS["vibe"])
    for (label, x), style in zip(VIBE_GUIDANCE_M_S2.items(), ("-", "--", ":"), strict=True):
        ax_vibe.axvline(x, color="black", ls=style, lw=1, label=f"{x:g} m/s²: {label}")
    ax_g.set_yticks(rows, inputs)
    ax_g.set_xlabel("line acceleration, largest axis (g, 0-peak)")
    ax_v.set_xlabel("lateral 1/rev velocity (in/s, 0-peak)")
    ax_vibe.set_xlabel("VIBE, largest axis (m/s²)")
    for ax, limits in zip((ax_g, ax_v, ax_vibe), LIMITS.values(), strict=True):
        ax.set_xscale("log")
        ax.set_xlim(*limits)
        plain_log_ticks(ax, "x")
        ax.grid(True, axis="x", which="major", alpha=0.3)
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), fontsize=8, frameon=False, ncols=2)
    ax_g.set_title("lines at the mount")
    ax_v.set_title("1/rev against track and balance")
    ax_vibe.set_title("VIBE against ArduPilot's guidance")
    return fig


def _stems(ax, rows: np.ndarray, values: np.ndarray, colour: str, limits: tuple[float, float]) -> None:
    """A dot at each row's value with a stem from the panel's left edge (NaN: none; below the edge: a triangle on
    it)."""
    ok = np.isfinite(values)
    low = ok & (values < limits[0])
    shown = np.clip(values[ok], limits[0], None)
    ax.hlines(rows[ok], limits[0], shown, color=colour, lw=2, alpha=0.6)
    ax.plot(values[ok & ~low], rows[ok & ~low], "o", color=colour)
    ax.plot(np.full(low.sum(), limits[0]), rows[low], "<", color=colour, ms=7)
