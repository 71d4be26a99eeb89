"""The vibration stage: helicopter runs with their amplitude spectra and dominant lines (the paper's Fig. 3)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from uavdamp import spectrum
from uavdamp.helicopter.model import AXES
from uavdamp.helicopter.params import Helicopter, Spectrum


def vibration(heli: Helicopter, runs: dict[str, xr.Dataset], options: Spectrum) -> xr.Dataset:
    """Combine runs keyed by rotor state ("balanced", "imbalanced") with their spectra.

    Adds the amplitude spectrum of each axis (Hann window, `options.zero_padding` times the length) and the
    dominant angular frequency above `options.min_omega_rad_s`, where the free-floating fuselage's slow
    rigid-body drift (no aerodynamic restoring force here) is excluded.
    """
    min_omega_rad_s, zero_padding = options.min_omega_rad_s, options.zero_padding
    rotors = list(runs)
    ds = xr.concat([runs[r] for r in rotors], dim=xr.DataArray(rotors, dims="rotor"), combine_attrs="override")
    ds.attrs = {}
    ds["rotor"].attrs = {"units": "1", "long_name": "main rotor state"}
    spacing = np.diff(ds.time.values)
    dt = float(spacing.mean())
    if np.ptp(spacing) > 1e-6 * dt:
        raise ValueError("runs: time samples are not uniformly spaced")
    amp, dominant = [], np.empty((len(rotors), len(AXES)))
    for i, r in enumerate(rotors):
        for j, a in enumerate(AXES):
            signal = ds.displacement.sel(rotor=r, axis=a).values
            freq_hz, spec = spectrum.amplitude_spectrum(signal, dt, zero_padding=zero_padding)
            amp.append(spec)
            dominant[i, j] = (
                2
                * np.pi
                * spectrum.dominant_frequency(
                    signal, dt, min_freq_hz=min_omega_rad_s / (2 * np.pi), zero_padding=zero_padding
                )
            )
    amp = np.reshape(amp, (len(rotors), len(AXES), -1))
    ds = ds.assign_coords(omega=("omega", 2 * np.pi * freq_hz, {"units": "rad s-1", "long_name": "angular frequency"}))
    ds["amplitude_spectrum"] = (
        ("rotor", "axis", "omega"),
        amp,
        {"units": "m", "long_name": "single-sided amplitude spectrum of the displacement (Hann window)"},
    )
    ds["dominant_omega"] = (
        ("rotor", "axis"),
        dominant,
        {"units": "rad s-1", "long_name": f"dominant angular frequency above {min_omega_rad_s} rad/s"},
    )
    ds["rotor_angle_error"] = (
        "rotor",
        [runs[r].attrs["rotor_angle_error_rad"] for r in rotors],
        {"units": "rad", "long_name": "main rotor angle minus Omega t at the end of the run"},
    )
    ds["mass_imbalance_factor"] = (
        "rotor",
        [1.0 if r == "balanced" else heli.imbalance.mass_factor for r in rotors],
        {"units": "1", "long_name": "mass scale of the imbalanced blade"},
    )
    return ds
