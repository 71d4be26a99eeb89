"""The benchmark's scenarios (issue 13): helicopter runs over imbalance, rotor speed and tail rotor, and synthetics.

Names come from the config's ``benchmark`` section (`scenario_specs`): every combination of
helicopter.imbalance_mass_factor x rotor_speed_ratio x tail_rotor ("heli_m0.5_r1.1_tail_on"), and the entries of
the list ``synthetic`` by their `name`. `split` puts each one, seeded, in the tuning or the evaluation set.
`scenario_input` makes one scenario's mount input: a dataset with `mount_displacement` (axis (y, z), time), m.

Helicopter: `uavdamp.helicopter.run` with the imbalanced blade's mass factor, both rotor speeds scaled by the ratio
(main rotor `omega_rad_s`; the tail rotor at its `omega_running_rad_s` when on, stopped when off), then
`uavdamp.excitation.cases_dataset`: high-passed and each axis's dominant line scaled to amplitude_m (per_axis, as
the study's case 1). Synthetic kinds (choices): "sweep", a linear chirp of amplitude_m over `freq_hz` (y upwards,
z downwards); "tones", two sines per axis of amplitude_m each (`freq_y_hz`, `freq_z_hz`); "random", white noise
from a seeded `numpy.random.Generator` band-passed (4th-order Butterworth, zero phase) to `band_hz`, each axis scaled
to the RMS of a sine of amplitude_m.
"""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np
import xarray as xr
from scipy.signal import butter, chirp, sosfiltfilt

from uavdamp import helicopter as H
from uavdamp.excitation import cases_dataset

KINDS = ("helicopter", "sweep", "tones", "random")
_ATTRS = {"units": "m", "long_name": "fuselage displacement at the platform mount (input)"}


def scenario_specs(cfg: dict) -> dict[str, dict]:
    """{name: spec} of every scenario of the config's benchmark section (spec["kind"] in KINDS)."""
    heli = cfg["helicopter"]
    specs = {}
    for mass, ratio, tail in itertools.product(
        heli["imbalance_mass_factor"], heli["rotor_speed_ratio"], heli["tail_rotor"]
    ):
        name = f"heli_m{float(mass):g}_r{float(ratio):g}_tail_{'on' if tail else 'off'}"
        specs[name] = {
            "kind": "helicopter",
            "mass_factor": float(mass),
            "speed_ratio": float(ratio),
            "tail_rotor": bool(tail),
        }
    for entry in cfg.get("synthetic", []):
        spec = {k: v for k, v in entry.items() if k != "name"}
        name = str(entry.get("name"))
        if spec.get("kind") not in KINDS[1:]:
            raise ValueError(f"benchmark.synthetic.{name}.kind: must be one of {KINDS[1:]}, got {spec.get('kind')!r}")
        if name in specs or not name.replace("_", "").isalnum():
            raise ValueError(f"benchmark.synthetic.{name}: the name must be new and alphanumeric (with _)")
        specs[name] = dict(spec)
    return specs


def split(names, tuning_fraction: float, seed: int) -> dict[str, str]:
    """{name: "tuning" | "evaluation"}: a seeded random `tuning_fraction` of the sorted names (at least one of each)."""
    names = sorted(names)
    if not 0 < tuning_fraction < 1:
        raise ValueError(f"benchmark.split.tuning_fraction: must be in (0, 1), got {tuning_fraction}")
    if len(names) < 2:
        raise ValueError(f"benchmark: need at least 2 scenarios to split, got {len(names)}")
    n_tune = min(max(int(round(tuning_fraction * len(names))), 1), len(names) - 1)
    order = np.random.default_rng(seed).permutation(len(names))
    tuning = {names[i] for i in order[:n_tune]}
    return {name: ("tuning" if name in tuning else "evaluation") for name in names}


def helicopter_input(
    heli_cfg: dict, spec: dict, *, duration: float, highpass_hz: float, amplitude: float, band_hz: tuple[float, float]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(time s, y m, z m) of one helicopter scenario (module docstring); heli_cfg: the config's helicopter section."""
    heli = H.Helicopter.from_config(heli_cfg)
    ratio = spec["speed_ratio"]
    tail = heli_cfg["tail_rotor"]["omega_running_rad_s"] * ratio if spec["tail_rotor"] else 0.0
    heli = replace(
        heli,
        imbalance_mass_factor=spec["mass_factor"],
        main_rotor=replace(heli.main_rotor, omega_rad_s=heli.main_rotor.omega_rad_s * ratio),
    )
    heli = heli.with_tail_rotor_speed(tail)
    heli.validate()
    run = H.run(heli, H.SolverOptions.from_config({**heli_cfg["solver"], "duration": duration}))
    case = {"run": "run", "amplitude": amplitude, "amplitude_reading": "dominant", "amplitude_scaling": "per_axis"}
    ds = cases_dataset({"run": run}, {"case": case}, duration=duration, highpass_hz=highpass_hz, band_hz=band_hz)
    y, z = (ds.mount_displacement.sel(case="case", axis=a).values for a in ("y", "z"))
    return ds.time.values, y, z


def synthetic_input(spec: dict, *, duration: float, amplitude: float, time_step: float):
    """(time s, y m, z m) of one synthetic scenario (module docstring), sampled every time_step s."""
    t = np.arange(int(round(duration / time_step)) + 1) * time_step
    kind = spec["kind"]
    if kind == "sweep":
        f0, f1 = spec["freq_hz"]
        y = amplitude * chirp(t, f0, duration, f1, method="linear", phi=-90)
        z = amplitude * chirp(t, f1, duration, f0, method="linear", phi=-90)
    elif kind == "tones":
        y, z = (amplitude * sum(np.sin(2 * np.pi * f * t) for f in spec[key]) for key in ("freq_y_hz", "freq_z_hz"))
    elif kind == "random":
        rng = np.random.default_rng(int(spec["seed"]))
        sos = butter(4, spec["band_hz"], btype="bandpass", fs=1.0 / time_step, output="sos")
        y, z = (sosfiltfilt(sos, rng.standard_normal(t.size)) for _ in range(2))
        y, z = (x * amplitude / np.sqrt(2.0) / np.std(x) for x in (y, z))
    else:
        raise ValueError(f"benchmark.synthetic kind: must be one of {KINDS[1:]}, got {kind!r}")
    return t, y, z


def scenario_input(name: str, cfg: dict, heli_cfg: dict, time_step: float) -> xr.Dataset:
    """The named scenario's input dataset: mount_displacement (axis, time), m; cfg: the benchmark section."""
    specs = scenario_specs(cfg)
    if name not in specs:
        raise ValueError(f"benchmark scenario: unknown {name!r} (known: {sorted(specs)})")
    spec, duration, amplitude = specs[name], float(cfg["duration_s"]), float(cfg["amplitude_m"])
    if spec["kind"] == "helicopter":
        t, y, z = helicopter_input(
            heli_cfg,
            spec,
            duration=duration,
            highpass_hz=float(cfg["highpass_hz"]),
            amplitude=amplitude,
            band_hz=tuple(cfg["band_hz"]),
        )
    else:
        t, y, z = synthetic_input(spec, duration=duration, amplitude=amplitude, time_step=time_step)
    return xr.Dataset(
        {"mount_displacement": (("axis", "time"), np.stack([y, z]), _ATTRS)},
        coords={
            "axis": ("axis", ["y", "z"], {"units": "1", "long_name": "direction (y lateral, z up)"}),
            "time": ("time", t, {"units": "s", "long_name": "time"}),
        },
        attrs={
            "scenario": name,
            "kind": spec["kind"],
            "spec": ", ".join(f"{k}={v}" for k, v in spec.items() if k != "kind"),
        },
    )
