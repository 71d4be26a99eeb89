"""Figures of the camera platform stage: response to a mono-frequency input, rigid vs isolated."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import xarray as xr  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

MM_PER_M = 1e3


def response_figure(
    rigid: xr.Dataset, isolated: xr.Dataset, modes: xr.Dataset | None = None, input_label: str = ""
) -> Figure:
    """Camera displacement in y and z (mm) against time for a rigid and an isolated mount.

    rigid, isolated: responses of `ExudynPlant.run` (or any plant) to the same input;
    modes: optional `modes_dataset`, whose frequencies go into the title;
    input_label: a description of the input for the title (e.g. "7 Hz, 1.3 mm").
    """
    fig = Figure(figsize=(8.0, 5.5), layout="constrained")
    axes = fig.subplots(2, 1, sharex=True)
    time = rigid["time"].values
    for ax, axis in zip(axes, ("y", "z"), strict=True):
        mount = rigid["mount_displacement"].sel(mount_axis=axis).values * MM_PER_M
        ax.plot(time, mount, color="0.6", lw=1.0, label="fuselage (mount) input")
        ax.plot(
            time, rigid["camera_displacement"].sel(axis=axis).values * MM_PER_M, lw=1.0, label="camera, rigid mount"
        )
        ax.plot(
            isolated["time"].values,
            isolated["camera_displacement"].sel(axis=axis).values * MM_PER_M,
            lw=1.2,
            label=(
                f"camera, isolator K = {isolated.attrs['isolator_stiffness_N_m']:g} N/m, "
                f"C = {float(isolated['damping'][0]):g} N s/m"
            ),
        )
        ax.set_ylabel(f"{axis} displacement (mm)")
        ax.grid(True, lw=0.3)
    fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncols=3, fontsize="small")
    axes[-1].set_xlabel("time (s)")
    title = "Camera response to a mono-frequency fuselage input"
    if input_label:
        title += f" ({input_label})"
    if modes is not None:
        freqs = ", ".join(f"{f:.2f}" for f in modes["natural_frequency"].values)
        title += f"\nplatform modes (base clamped): {freqs} Hz"
    fig.suptitle(title)
    return fig
