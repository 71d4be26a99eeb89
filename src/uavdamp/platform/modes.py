"""The platform's undamped modes with the base clamped, by Exudyn's eigen-analysis (paper Table 1)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from uavdamp.platform.design import COORDINATES, design_stiffness
from uavdamp.platform.exudyn_plant import ExudynPlant
from uavdamp.platform.params import PlatformParams


def natural_frequencies(params) -> tuple[np.ndarray, np.ndarray]:
    """Undamped, base-clamped natural frequencies (Hz, ascending) and mode shapes by eigen-analysis.

    Mode shapes are columns over (displacement m, yaw rad, pitch rad), scaled to a largest component of
    magnitude 1 with that component positive.
    """
    freq_hz, shapes = ExudynPlant(params, clamped=True).eigen()
    shapes = shapes / shapes[np.argmax(np.abs(shapes), axis=0), range(shapes.shape[1])]
    return freq_hz, shapes


def modes_dataset(p: PlatformParams) -> xr.Dataset:
    """Natural frequencies beside the paper's targets, mode shapes and the designed stiffnesses."""
    freq_hz, shapes = natural_frequencies(p)
    k = design_stiffness(p.structure)
    scalar = {
        "displacement_stiffness": (k[0], "N m-1", "structural spring, designed"),
        "yaw_servo_gain": (k[1], "N m rad-1", "yaw servo P gain, designed"),
        "pitch_servo_gain": (k[2], "N m rad-1", "pitch servo P gain, designed"),
        "total_mass": (p.structure.total_mass, "kg", "platform mass including camera"),
    }
    return xr.Dataset(
        {
            "natural_frequency": (
                "mode",
                freq_hz,
                {"units": "Hz", "long_name": "undamped natural frequency, base clamped (Exudyn eigen-analysis)"},
            ),
            "target_frequency": (
                "mode",
                np.sort(p.structure.natural_frequencies_hz),
                {"units": "Hz", "long_name": "target natural frequency (Marichal et al. 2014, Table 1)"},
            ),
            "mode_shape": (
                ("coordinate", "mode"),
                shapes,
                {
                    "units": "1",
                    "long_name": "mode shape, largest component scaled to 1 (displacement in m, angles in rad)",
                },
            ),
            **{name: ((), value, {"units": u, "long_name": text}) for name, (value, u, text) in scalar.items()},
        },
        coords={
            "mode": (
                "mode",
                np.arange(1, freq_hz.size + 1),
                {"units": "1", "long_name": "mode number, ascending frequency"},
            ),
            "coordinate": ("coordinate", list(COORDINATES), {"units": "1", "long_name": "platform joint coordinate"}),
        },
        attrs={"title": "Undamped natural frequencies and mode shapes of the camera platform, base clamped"},
    )
