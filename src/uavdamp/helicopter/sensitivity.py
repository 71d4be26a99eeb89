"""Sensitivity of the imbalanced helicopter's dominant fuselage lines to its uncertain parameters.

One run changes one parameter from the config's helicopter (one at a time); each run gives, per axis, the
dominant angular frequency and the amplitude of that spectral line (Hann window, single-sided).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import xarray as xr

from uavdamp.helicopter import model as H
from uavdamp.helicopter.flightdata import run as flight_run
from uavdamp.helicopter.params import Helicopter, SolverOptions, Spectrum
from uavdamp.settings import revalidate
from uavdamp.signals import spectrum as spectra

BASELINE = "baseline"


def _main(heli: Helicopter, **changes) -> Helicopter:
    return replace(heli, main_rotor=replace(heli.main_rotor, **changes))


def _fuselage_scale(heli: Helicopter, scale: np.ndarray) -> Helicopter:
    fuselage = heli.fuselage
    inertia = tuple(float(i * s) for i, s in zip(fuselage.inertia, scale, strict=True))
    scaled = replace(fuselage, inertia=inertia, inertia_xz=fuselage.inertia_xz * float(scale[0]))
    return replace(heli, fuselage=scaled)


# parameter -> (unit, long name, how it changes the helicopter, its value in a helicopter)
PARAMETERS = {
    "lag_stiffness_n_m_rad": (
        "N m rad-1",
        "lag hinge spring",
        lambda h, v: _main(h, lag_stiffness=v),
        lambda h: h.main_rotor.lag_stiffness,
    ),
    "lag_damping_n_m_s_rad": (
        "N m s rad-1",
        "lag damper",
        lambda h, v: _main(h, lag_damping=v),
        lambda h: h.main_rotor.lag_damping,
    ),
    "hinge_offset_m": (
        "m",
        "flap and lag hinge offset",
        lambda h, v: _main(h, hinge_offset=v),
        lambda h: h.main_rotor.hinge_offset,
    ),
    "feather_stiffness_n_m_rad": (
        "N m rad-1",
        "pitch-link (feather) spring",
        lambda h, v: _main(h, feather_stiffness=v),
        lambda h: h.main_rotor.feather_stiffness,
    ),
    "imbalance_mass_factor": (
        "1",
        "mass scale of the imbalanced blade",
        lambda h, v: replace(h, imbalance=replace(h.imbalance, mass_factor=v)),
        lambda h: h.imbalance.mass_factor,
    ),
    "fuselage_inertia_scale": (
        "1",
        "scale of all fuselage inertias (Ixx, Iyy, Izz, Ixz) from the config's",
        lambda h, v: _fuselage_scale(h, np.full(3, v)),
        lambda h: 1.0,
    ),
    "fuselage_ixx_scale": (
        "1",
        "scale of the fuselage roll inertia Ixx (and Ixz) from the config's",
        lambda h, v: _fuselage_scale(h, np.array([v, 1.0, 1.0])),
        lambda h: 1.0,
    ),
}


def varied(heli: Helicopter, parameter: str, value: float) -> Helicopter:
    """`heli` with one parameter set to `value` (units: PARAMETERS); BASELINE leaves it unchanged."""
    if parameter == BASELINE:
        return heli
    if parameter not in PARAMETERS:
        raise ValueError(f"sensitivity parameter {parameter!r}: not one of {sorted(PARAMETERS)}")
    out = PARAMETERS[parameter][2](heli, float(value))
    revalidate(out, "helicopter")
    return out


def parse_run_name(name: str) -> tuple[str, float]:
    """(parameter, value) of a run name "baseline" or "<parameter>=<value>" (the rules' wildcard); baseline: NaN."""
    if name == BASELINE:
        return BASELINE, float("nan")
    parameter, _, value = name.partition("=")
    if parameter not in PARAMETERS or not value:
        raise ValueError(f"sensitivity run {name!r}: expected 'baseline' or '<parameter>=<value>'")
    return parameter, float(value)


def dominant_lines(
    run: xr.Dataset, *, rotor_omega_rad_s: float, min_omega_rad_s: float, zero_padding: int
) -> xr.Dataset:
    """Per axis of a `helicopter.run` result's first mount point: the dominant angular frequency (rad/s) above
    `min_omega_rad_s`,
    that line's amplitude (m), and the amplitude of the rotor's 1/rev line (m, the largest within one
    frequency bin 2 pi / T of `rotor_omega_rad_s`). Amplitudes: Hann-window single-sided spectrum."""
    time = run.time.values
    dt = float(np.mean(np.diff(time)))
    bin_rad_s = 2 * np.pi / (time[-1] - time[0] + dt)
    omega, amplitude, rotor = [], [], []
    for axis in H.AXES:
        freq_hz, spec = spectra.amplitude_spectrum(
            run.mount_displacement.isel(mount=0).sel(axis=axis).values, dt, zero_padding=zero_padding
        )
        w = 2 * np.pi * freq_hz
        band = np.flatnonzero(w >= min_omega_rad_s)
        if band.size == 0:
            raise ValueError(f"min_omega_rad_s: {min_omega_rad_s} rad/s is above the Nyquist frequency")
        peak = band[np.argmax(spec[band])]
        omega.append(w[peak])
        amplitude.append(spec[peak])
        rotor.append(spec[np.abs(w - rotor_omega_rad_s) <= bin_rad_s].max())
    axis = ("axis", list(H.AXES), {"units": "1", "long_name": "axis (x forward, y left, z up)"})
    return xr.Dataset(
        {
            "dominant_omega": (
                "axis",
                omega,
                {"units": "rad s-1", "long_name": f"dominant angular frequency above {min_omega_rad_s} rad/s"},
            ),
            "dominant_amplitude": (
                "axis",
                amplitude,
                {"units": "m", "long_name": "amplitude of the dominant line (Hann-window single-sided spectrum)"},
            ),
            "rotor_line_amplitude": (
                "axis",
                rotor,
                {
                    "units": "m",
                    "long_name": "amplitude of the 1/rev line (largest within one frequency bin of the rotor speed)",
                },
            ),
        },
        coords={"axis": axis},
    )


def run(heli: Helicopter, name: str, options: SolverOptions, flight: str = "vacuum") -> xr.Dataset:
    """One sensitivity run (`name`: "baseline" or "<parameter>=<value>") of the imbalanced helicopter in flight
    condition `flight` (vacuum: `helicopter.run`; hover, forward: `helicopter.flight_run`, `heli` a FlightRun): the
    mount motion on a `run` dimension, with every parameter's value as a coordinate."""
    parameter, value = parse_run_name(name)
    changed = varied(heli, parameter, value)
    if flight == "vacuum":
        result = H.run(changed, options)
    else:
        result = flight_run(replace(changed, solver=options), flight)[0][["mount_displacement", "mount_rotation"]]
    values = {p: (value if p == parameter else nominal(heli)) for p, (_, _, _, nominal) in PARAMETERS.items()}
    result.attrs = {}
    return result.expand_dims(run=[name]).assign_coords(
        run=("run", [name], {"units": "1", "long_name": "sensitivity run"}),
        parameter=("run", [parameter], {"units": "1", "long_name": "parameter changed from the config's"}),
        **{p: ("run", [v], {"units": PARAMETERS[p][0], "long_name": PARAMETERS[p][1]}) for p, v in values.items()},
    )


def combine(runs: list[xr.Dataset], *, rotor_omega_rad_s: float, spectrum: Spectrum) -> xr.Dataset:
    """The dominant lines (`dominant_lines`, with the vibration stage's `spectrum` options) of each run from `run`,
    concatenated along `run` with the runs' parameter coordinates (variable attributes kept, global ones dropped)."""
    min_omega_rad_s, zero_padding = spectrum.min_omega_rad_s, spectrum.zero_padding
    lines = []
    for ds in runs:
        one = ds.isel(run=0)
        found = dominant_lines(
            one, rotor_omega_rad_s=rotor_omega_rad_s, min_omega_rad_s=min_omega_rad_s, zero_padding=zero_padding
        )
        coords = {name: ds[name] for name in ds.coords if ds[name].dims == ("run",)}
        lines.append(found.expand_dims(run=ds.run.values).assign_coords(coords))
    out = xr.concat(lines, dim="run", combine_attrs="override")
    out.attrs = {}
    return out
