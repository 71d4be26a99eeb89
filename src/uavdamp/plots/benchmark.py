"""Benchmark figures: controllers x criteria (mean and worst over the evaluation set), and box plots over scenarios."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

MIN_BOX_SCENARIOS = 5  # fewer evaluation scenarios: every scenario drawn as a point, no box


def _dampers(ds: xr.Dataset, dampers) -> list[str]:
    """The dampers to draw: those named, else every damper of the dataset on which some controller ran."""
    names = [str(d) for d in ds.damper.values] if dampers is None else list(dampers)
    return [d for d in names if dampers is not None or np.isfinite(ds.J_mean.sel(damper=d).values).any()]


def _ink(image, value: float) -> str:
    """Black on a light cell of the image's colour map, white on a dark one (luminance of the cell's colour)."""
    r, g, b, _ = image.cmap(image.norm(value))
    return "k" if 0.299 * r + 0.587 * g + 0.114 * b > 0.5 else "w"


def criteria_figure(ds: xr.Dataset, dampers=None):
    """Heat maps of log10 J (controllers x criteria): one row per damper (default: every damper a controller ran
    with), the evaluation mean at each stiffness then the worst across; '-' where a controller did not run."""
    rows = _dampers(ds, dampers)
    cols = [(name, k) for name in ("J_mean", "J_worst") for k in ds.stiffness.values]
    size = (min(16.0, 3.6 * len(cols) + 1.5), min(9.0, 1.4 + 2.6 * len(rows)))
    fig, axes = plt.subplots(len(rows), len(cols), figsize=size, squeeze=False, constrained_layout=True)
    for r, damper in enumerate(rows):
        for c, (name, k) in enumerate(cols):
            ax = axes[r, c]
            values = ds[name].sel(stiffness=k, damper=damper).transpose("controller", "criterion").values
            shown = np.log10(np.maximum(values, 10**-2.5))  # J = 0 (e.g. no unsharp frame) at the colour scale's end
            image = ax.imshow(np.ma.masked_invalid(shown), cmap="viridis_r", vmin=-2.5, vmax=0.5, aspect="auto")
            ax.set_facecolor("0.9")
            for (i, j), v in np.ndenumerate(values):
                text, colour = ("-", "0.4") if not np.isfinite(v) else (f"{v:.3g}", _ink(image, shown[i, j]))
                ax.text(j, i, text, ha="center", va="center", fontsize=6.5, color=colour)
            bottom, left = r == len(rows) - 1, c == 0
            ax.set_xticks(range(ds.criterion.size), ds.criterion.values if bottom else [], rotation=35, ha="right")
            ax.set_yticks(range(ds.controller.size), ds.controller.values if left else [])
            ax.tick_params(labelsize=7)
            ax.set_title(f"{damper}: {'mean' if name == 'J_mean' else 'worst'} J, K = {k:g} N/m", fontsize=8.5)
    fig.colorbar(image, ax=axes, label="log10 J (J = 1: rigid mount; '-': not run)", shrink=0.6)
    return fig


def boxplot_figure(ds: xr.Dataset, criteria=("los_std", "blur_p95", "displacement_std"), dampers=None):
    """J over the evaluation scenarios per controller, one row per criterion, one column per K, the dampers side by side
    in colour: box plots from `MIN_BOX_SCENARIOS` scenarios up, every scenario as a point below that."""
    shown_dampers = _dampers(ds, dampers)
    stiffness = ds.stiffness.values
    evaluation = ds.J.where(ds.set == "evaluation", drop=True)
    n = evaluation.scenario.size
    fig, axes = plt.subplots(
        len(criteria),
        len(stiffness),
        figsize=(min(16.0, 8 * len(stiffness)), min(11.5, 3.2 * len(criteria))),
        squeeze=False,
        constrained_layout=True,
    )
    names = [str(c) for c in ds.controller.values]
    width = 0.8 / len(shown_dampers)
    for col, k in enumerate(stiffness):
        for row, criterion in enumerate(criteria):
            ax = axes[row, col]
            for m, damper in enumerate(shown_dampers):
                at = evaluation.sel(stiffness=k, criterion=criterion, damper=damper)
                data = [at.sel(controller=c).values for c in names]
                data = [d[np.isfinite(d)] for d in data]
                positions = np.arange(1, len(names) + 1) - 0.4 + width * (m + 0.5)
                colour = f"C{m}"
                if n >= MIN_BOX_SCENARIOS:
                    kept = [(p, d) for p, d in zip(positions, data, strict=True) if d.size]
                    if kept:
                        ax.boxplot(
                            [d for _, d in kept],
                            positions=[p for p, _ in kept],
                            widths=0.9 * width,
                            showfliers=True,
                            boxprops={"color": colour},
                            whiskerprops={"color": colour},
                            capprops={"color": colour},
                            medianprops={"color": "k", "lw": 1.2},
                            flierprops={"markeredgecolor": colour, "markersize": 3},
                        )
                else:
                    for p, d in zip(positions, data, strict=True):
                        if d.size:  # not run: no points
                            ax.plot(np.full(d.size, p), d, "o", color=colour, ms=4, alpha=0.8)
                ax.plot([], [], "s", color=colour, label=f"{damper} damper")
            ax.set_xticks(range(1, len(names) + 1), names, rotation=35, ha="right", fontsize=8)
            ax.set_xlim(0.5, len(names) + 0.5)
            ax.set_yscale("log")
            ax.set_ylabel(f"J {criterion} (1; rigid = 1)")
            shown = "boxes" if n >= MIN_BOX_SCENARIOS else "points"
            ax.set_title(f"K = {k:g} N/m, {n} evaluation scenarios ({shown})", fontsize=9)
    axes[0, -1].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    return fig


def _shown(value: float) -> str:
    return f"{value:.3g}"


def ranking(ds: xr.Dataset, stiffness: float, criterion: str, damper: str) -> str:
    """The best two controllers on a criterion's evaluation mean J ('=' where they are equal to the shown three
    digits, '<' otherwise); for a frame-phase criterion, whether the lead exceeds the spread over the frame clock's
    phase (the leader's highest-phase mean below the runner-up's lowest)."""
    at = {"stiffness": stiffness, "damper": damper}
    mean = ds.J_mean.sel(criterion=criterion, **at).to_series().drop("rigid", errors="ignore").dropna().sort_values()
    if mean.size < 2:
        return f"{criterion}: fewer than two controllers"
    first, second = mean.index[:2]
    relation = "=" if _shown(mean.iloc[0]) == _shown(mean.iloc[1]) else "<"  # equal to the shown digits: a tie
    text = f"{criterion}: {first} {_shown(mean.iloc[0])} {relation} {second} {_shown(mean.iloc[1])}"
    if "phased" in ds.dims and criterion in ds.phased.values:
        high = float(ds.J_high_mean.sel(phased=criterion, controller=first, **at))
        low = float(ds.J_low_mean.sel(phased=criterion, controller=second, **at))
        verdict = "beyond the frame-phase spread" if high < low else "within the frame-phase spread: no ranking"
        text += f" ({first} up to {high:.3g}, {second} from {low:.3g}: {verdict})"
    return text


def identical_rows(ds: xr.Dataset, rows: dict[str, tuple], stiffness: float, damper: str) -> list[str]:
    """A remark per group of controllers whose table rows are identical (every run cell equal as shown), with the
    share of their demands below the damper's range (`demand_below_range_mean`) where the data has it."""
    groups = {}
    for name, cells in rows.items():
        if name != "rigid" and any(c != "-" for c in cells):
            groups.setdefault(cells, []).append(name)
    out = []
    for names in (g for g in groups.values() if len(g) > 1):
        text = f"- identical rows: {', '.join(names)}"
        if "demand_below_range_mean" in ds:
            at = {"stiffness": stiffness, "damper": damper}
            shares = [float(ds.demand_below_range_mean.sel(controller=n, **at)) for n in names]
            text += f"; share of their demands below the {damper} damper's range: " + ", ".join(
                f"{n} {100 * v:.0f} %" for n, v in zip(names, shares, strict=True)
            )
        out.append(text)
    return out


def markdown_table(ds: xr.Dataset, damper: str = "ideal", criteria=None) -> str:
    """The README table: mean / worst J per controller and criterion over the evaluation set, per stiffness; a
    frame-phase criterion also gives [lowest - highest phase] means; then the leader per criterion (`ranking`)."""
    criteria = list(ds.criterion.values) if criteria is None else list(criteria)
    phased = list(ds.phased.values) if "phased" in ds.dims else []
    lines = []
    for k in ds.stiffness.values:
        lines += [
            f"K = {k:g} N/m, {damper} damper (mean / worst J over the evaluation set; J = 1: rigid; "
            "[..]: the frame-phase spread of the mean; '-': not run, see tuned_on)",
            "",
            "| controller | " + " | ".join(criteria) + " |",
            "|---" * (len(criteria) + 1) + "|",
        ]
        rows = {}
        for c in ds.controller.values:
            cells = []
            for x in criteria:
                at = {"controller": c, "stiffness": k, "damper": damper}
                mean, worst = float(ds.J_mean.sel(criterion=x, **at)), float(ds.J_worst.sel(criterion=x, **at))
                if not np.isfinite(mean):
                    cells.append("-")
                    continue
                cell = f"{_shown(mean)} / {_shown(worst)}"
                if x in phased:
                    low, high = (float(ds[v].sel(phased=x, **at)) for v in ("J_low_mean", "J_high_mean"))
                    cell += f" [{low:.3g}-{high:.3g}]"
                cells.append(cell)
            lines.append(f"| {c} | " + " | ".join(cells) + " |")
            rows[str(c)] = tuple(cells)
        lines += ["", *(f"- {ranking(ds, k, x, damper)}" for x in criteria), *identical_rows(ds, rows, k, damper), ""]
    if "tuned_on" in ds.coords:
        tuned = {
            str(c): sorted({str(v) for v in ds.tuned_on.sel(controller=c).values} - {""}) for c in ds.controller.values
        }
        lines += [
            "Tuned on (per criterion family): " + "; ".join(f"{c}: {', '.join(v)}" for c, v in tuned.items() if v),
            "",
        ]
    return "\n".join(lines)
