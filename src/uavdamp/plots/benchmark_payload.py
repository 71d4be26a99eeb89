"""The benchmark on the payload's figure: J per controller and evaluation scenario, one panel per mount."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402


def criteria_figure(ds: xr.Dataset) -> Figure:
    """Per mount, every evaluation scenario's J (points, log scale) and the evaluation mean (bar) per controller;
    the tuning scenarios' J as open points beside them."""
    mounts = [str(m) for m in ds.mount.values]
    names = [str(c) for c in ds.controller.values]
    fig, axes = plt.subplots(len(mounts), 1, figsize=(10, 3.6 * len(mounts)), squeeze=False, constrained_layout=True)
    x = np.arange(len(names))
    for ax, mount in zip(axes[:, 0], mounts, strict=True):
        j = ds.J.sel(mount=mount).transpose("scenario", "controller").values
        evaluation = (ds.set == "evaluation").values
        ax.bar(x, ds.J_mean.sel(mount=mount).values, width=0.6, color="0.85", label="evaluation mean")
        for rows, style, label in (
            (evaluation, dict(color="C0"), "evaluation scenario"),
            (~evaluation, dict(facecolor="none", edgecolor="C1"), "tuning scenario"),
        ):
            offset = 0.12 if label.startswith("tuning") else -0.12
            for row in j[rows]:
                ax.scatter(x + offset, row, s=14, **style, label=label)
                label = None
        ax.axhline(1.0, color="k", lw=0.8, ls="--")
        ax.set_yscale("log")
        ax.set_xticks(x, names, rotation=30, ha="right")
        ax.set_ylabel(f"J ({ds.attrs['criterion']} / rigid)")
        ax.set_title(f"Gimbal on the {mount} isolator: J per damping law (dashed: rigid mount)", fontsize=10)
        ax.legend(fontsize=8, loc="upper left")
    return fig
