"""The vibration stage: helicopter runs with their amplitude spectra and dominant lines (the paper's Fig. 3)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from uavdamp.helicopter.params import Helicopter, Spectrum
from uavdamp.signals import spectrum


def _spectra(signals: np.ndarray, dt: float, options: Spectrum) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(freq Hz, amplitude spectra (..., f), dominant angular frequency (...) rad/s) along the last axis."""
    flat = signals.reshape(-1, signals.shape[-1])
    spectra, dominant = [], []
    for signal in flat:
        freq_hz, spec = spectrum.amplitude_spectrum(signal, dt, zero_padding=options.zero_padding)
        spectra.append(spec)
        f_min = options.min_omega_rad_s / (2 * np.pi)
        dominant.append(
            2 * np.pi * spectrum.dominant_frequency(signal, dt, min_freq_hz=f_min, zero_padding=options.zero_padding)
        )
    shape = signals.shape[:-1]
    return freq_hz, np.reshape(spectra, (*shape, -1)), np.reshape(dominant, shape)


def _stacked(runs: dict[str, xr.Dataset]) -> xr.Dataset:
    """The runs' mount motion on a `rotor` dimension (a flight run also holds its pilot's record: left out)."""
    rotors = list(runs)
    motion = [runs[r][["mount_displacement", "mount_rotation"]] for r in rotors]
    if len({m.time.size for m in motion}) != 1 or any(
        np.abs(m.time.values - motion[0].time.values).max() > 1e-6 for m in motion
    ):
        raise ValueError("runs: sampled at different times (every run needs helicopter.solver's duration and step)")
    # a flight run's times are its record's (start subtracted): the same samples up to round-off
    ds = xr.concat(motion, dim=xr.DataArray(rotors, dims="rotor"), combine_attrs="override", join="override")
    ds.attrs = {}
    return ds


def vibration(heli: Helicopter, runs: dict[str, xr.Dataset], options: Spectrum) -> xr.Dataset:
    """Combine runs keyed by rotor state ("balanced", "imbalanced", and the flight runs "hover", "forward") with their
    spectra.

    Adds the amplitude spectrum of each mount's displacement and of the rotation per axis (Hann window,
    `options.zero_padding` times the length) and the dominant angular frequency above `options.min_omega_rad_s`,
    where the free-floating fuselage's slow rigid-body drift (no aerodynamic restoring force here) is excluded.
    """
    rotors = list(runs)
    ds = _stacked(runs)
    ds["rotor"].attrs = {"units": "1", "long_name": "main rotor state"}
    spacing = np.diff(ds.time.values)
    dt = float(spacing.mean())
    if np.ptp(spacing) > 1e-6 * dt:
        raise ValueError("runs: time samples are not uniformly spaced")
    freq_hz, amp, dominant = _spectra(
        ds.mount_displacement.transpose("rotor", "mount", "axis", "time").values, dt, options
    )
    _, rot_amp, rot_dominant = _spectra(ds.mount_rotation.transpose("rotor", "axis", "time").values, dt, options)
    ds = ds.assign_coords(omega=("omega", 2 * np.pi * freq_hz, {"units": "rad s-1", "long_name": "angular frequency"}))
    above = f"dominant angular frequency above {options.min_omega_rad_s} rad/s"
    hann = "single-sided amplitude spectrum (Hann window)"
    ds["amplitude_spectrum"] = (
        ("rotor", "mount", "axis", "omega"),
        amp,
        {"units": "m", "long_name": f"{hann} of the mount displacement"},
    )
    ds["rotation_spectrum"] = (
        ("rotor", "axis", "omega"),
        rot_amp,
        {"units": "rad", "long_name": f"{hann} of the rotation"},
    )
    ds["dominant_omega"] = (
        ("rotor", "mount", "axis"),
        dominant,
        {"units": "rad s-1", "long_name": f"{above}, displacement"},
    )
    ds["rotation_dominant_omega"] = (
        ("rotor", "axis"),
        rot_dominant,
        {"units": "rad s-1", "long_name": f"{above}, rotation"},
    )
    ds["rotor_angle_error"] = (
        "rotor",
        [runs[r].attrs["rotor_angle_error_rad"] for r in rotors],
        {"units": "rad", "long_name": "main rotor angle minus Omega t at the end of the run"},
    )
    ds["flight"] = (
        "rotor",
        [runs[r].attrs.get("flight", "vacuum") for r in rotors],
        {"units": "1", "long_name": "flight condition (vacuum: no aerodynamics or gravity, the paper's)"},
    )
    ds["mass_imbalance_factor"] = (
        "rotor",
        [1.0 if r == "balanced" else heli.imbalance.mass_factor for r in rotors],
        {"units": "1", "long_name": "mass scale of the imbalanced blade"},
    )
    return ds
