"""The closed-loop study: every input case, isolator stiffness and damping strategy, with metrics.

Strategies (src/uavdamp/control.py), all within the same damper bounds:
rigid (no isolator), passive (constant C from the config), optimal_passive (the best constant C
for the case and stiffness, by the same criterion as the reference table), anfis (the paper's
semi-active control: tracked f_y, f_z and K into the ANFIS, C updated every update period) and
skyhook (Karnopp's on-off skyhook, switched every solver step).

Metrics per (case, stiffness, strategy, axis): `peak_early`, the largest |camera displacement| up
to `early_s` (paper: 0.5 s); `std_total`, its standard deviation over the whole run; `std_settled`,
over [settle_s, end] (paper: both strategies converge after about 1 s); and per (case, stiffness,
strategy) the energy the damper dissipated, sum over axes of the integral of C v_rel^2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from uavdamp import control, criterion, spectrum
from uavdamp.platform import PlatformParams, PlatformSimulator

STRATEGIES = ("rigid", "passive", "optimal_passive", "anfis", "skyhook")


@dataclass(frozen=True)
class StudyOptions:
    """The config's `study` section, less the cases (SI units, frequencies in Hz)."""

    stiffness: tuple[float, ...]  # N m-1
    passive_damping: float  # N s m-1
    optimal_candidates: int  # number of log-spaced candidate C for the optimal passive search
    early_s: float  # s
    settle_s: float  # s
    window: float  # s, tracking window
    min_freq_hz: float
    max_freq_hz: float
    min_cycles: float
    zero_padding: int
    initial_freq_hz: float  # Hz, the frequency assumed before the first estimate (the rotor's 1/rev)

    @classmethod
    def from_config(cls, cfg: dict) -> "StudyOptions":
        track = cfg["tracking"]
        return cls(stiffness=tuple(float(k) for k in cfg["stiffness"]), passive_damping=float(cfg["passive_damping"]),
                   optimal_candidates=int(cfg["optimal_candidates"]), early_s=float(cfg["early_s"]),
                   settle_s=float(cfg["settle_s"]), window=float(track["window"]),
                   min_freq_hz=float(track["min_freq_hz"]), max_freq_hz=float(track["max_freq_hz"]),
                   min_cycles=float(track["min_cycles"]), zero_padding=int(track["zero_padding"]),
                   initial_freq_hz=float(track["initial_freq_hz"]))


def _strategies(options: StudyOptions, params: PlatformParams, model, stiffness: float, run) -> tuple[list, dict]:
    """The strategies for one case and stiffness; `run(strategy)` simulates one (for the optimum)."""
    bounds = control.DamperBounds.from_params(params)
    c_low = max(bounds.c_min, 1e-3)
    candidates = np.geomspace(c_low, bounds.c_max, options.optimal_candidates)
    optimum = control.optimal_passive(
        lambda c: criterion.camera_criterion(run(control.passive(c, bounds)).camera_displacement,
                                             (0.0, float("inf"))),
        candidates, bounds)
    c_initial = float(bounds.clip(model.predict([[options.initial_freq_hz, options.initial_freq_hz, stiffness]])[0]))
    anfis = control.AnfisDamping(model, stiffness, bounds, c_initial, window=options.window,
                                 min_freq_hz=options.min_freq_hz, max_freq_hz=options.max_freq_hz,
                                 zero_padding=options.zero_padding, min_cycles=options.min_cycles)
    strategies = [control.rigid(), control.passive(options.passive_damping, bounds), optimum.strategy(),
                  anfis.strategy(), control.Skyhook(bounds, params.time_step).strategy()]
    return strategies, {"optimal_damping": optimum.c, "anfis_initial_damping": c_initial}


def run_study(cases: xr.Dataset, platform: dict, model, options: StudyOptions) -> xr.Dataset:
    """Simulate every case x stiffness x strategy; return the comparison dataset."""
    params = PlatformParams.from_config(platform)
    simulators = {mount: PlatformSimulator(params, mount=mount) for mount in control.MOUNTS}
    time = cases.time.values
    n_case, n_k, n_s = cases.sizes["case"], len(options.stiffness), len(STRATEGIES)
    camera = damping = energy = None
    extras = {"optimal_damping": np.full((n_case, n_k), np.nan), "anfis_initial_damping": np.full((n_case, n_k), np.nan)}
    for i, case in enumerate(cases.case.values):
        y = cases.mount_displacement.sel(case=case, axis="y").values
        z = cases.mount_displacement.sel(case=case, axis="z").values
        for j, stiffness in enumerate(options.stiffness):
            def run(strategy):
                return simulators[strategy.mount].run(time, y, z, stiffness=stiffness, damping=strategy.damping,
                                                      update_period=strategy.update_period)

            strategies, found = _strategies(options, params, model, stiffness, run)
            for key, value in found.items():
                extras[key][i, j] = value
            for s, strategy in enumerate(strategies):
                out = run(strategy)
                if camera is None:
                    grid_time = out.time.values
                    camera = np.full((n_case, n_k, n_s, 2, grid_time.size), np.nan)
                    damping = np.full((n_case, n_k, n_s, grid_time.size), np.nan)
                    energy = np.full((n_case, n_k, n_s), np.nan)
                camera[i, j, s] = out.camera_displacement.values
                damping[i, j, s] = out.damping.values
                if strategy.mount == "isolated":
                    v2 = (out.isolator_velocity.values ** 2).sum(axis=0)
                    energy[i, j, s] = float(np.sum(out.damping.values[:-1] * v2[:-1]) * params.time_step)
    ds = xr.Dataset(
        {
            "camera_displacement": (("case", "stiffness", "strategy", "axis", "time"), camera,
                                    {"units": "m", "long_name": "camera displacement (inertial, from rest)"}),
            "damping": (("case", "stiffness", "strategy", "time"), damping,
                        {"units": "N s m-1", "long_name": "isolator damping applied from this time on (NaN: rigid)"}),
            "energy_dissipated": (("case", "stiffness", "strategy"), energy,
                                  {"units": "J", "long_name": "energy dissipated by the damper over the run"}),
            "optimal_damping": (("case", "stiffness"), extras["optimal_damping"],
                                {"units": "N s m-1", "long_name": "best constant damping for the case (optimal_passive)"}),
            "anfis_initial_damping": (("case", "stiffness"), extras["anfis_initial_damping"],
                                      {"units": "N s m-1", "long_name": "ANFIS damping before the first frequency estimate"}),
            "mount_displacement": (("case", "axis", "time"),
                                   cases.mount_displacement.interp(time=grid_time).values,
                                   {"units": "m", "long_name": "fuselage displacement at the platform mount (input)"}),
        },
        coords={
            "case": cases.case,
            "stiffness": ("stiffness", np.asarray(options.stiffness), {"units": "N m-1", "long_name": "isolator stiffness K"}),
            "strategy": ("strategy", list(STRATEGIES), {"units": "1", "long_name": "damping strategy"}),
            "axis": cases.axis,
            "time": ("time", grid_time, {"units": "s", "long_name": "time"}),
        },
    )
    ds = ds.merge(tracked_frequencies(cases, options, params.update_period))
    return ds.merge(metrics(ds, options))


def tracked_frequencies(cases: xr.Dataset, options: StudyOptions, update_period: float) -> xr.Dataset:
    """`tracked_freq` (case, axis, update_time), Hz: what the ANFIS controller sees every update (s)."""
    time = cases.time.values
    rows, update = [], None
    for case in cases.case.values:
        row = []
        for axis in cases.axis.values:
            update, freq = spectrum.track_dominant(
                time, cases.mount_displacement.sel(case=case, axis=axis).values, update_period=update_period,
                window=options.window, min_freq_hz=options.min_freq_hz, max_freq_hz=options.max_freq_hz,
                zero_padding=options.zero_padding, min_cycles=options.min_cycles)
            row.append(freq)
        rows.append(row)
    return xr.Dataset(
        {"tracked_freq": (("case", "axis", "update_time"), np.asarray(rows),
                          {"units": "Hz", "long_name": "dominant input frequency tracked at each update (NaN: too early)"})},
        coords={"update_time": ("update_time", update, {"units": "s", "long_name": "damping update time"})},
    )


def metrics(ds: xr.Dataset, options: StudyOptions) -> xr.Dataset:
    """peak_early, std_total and std_settled (case, stiffness, strategy, axis), m."""
    cam = ds.camera_displacement
    early = cam.sel(time=slice(0.0, options.early_s + 1e-9))
    settled = cam.sel(time=slice(options.settle_s, None))
    dims = ("case", "stiffness", "strategy", "axis")
    return xr.Dataset({
        "peak_early": (dims, np.abs(early).max("time").transpose(*dims).values,
                       {"units": "m", "long_name": f"largest |camera displacement| up to {options.early_s} s"}),
        "std_total": (dims, cam.std("time").transpose(*dims).values,
                      {"units": "m", "long_name": "standard deviation of the camera displacement, whole run"}),
        "std_settled": (dims, settled.std("time").transpose(*dims).values,
                        {"units": "m", "long_name": f"standard deviation of the camera displacement after {options.settle_s} s"}),
    })
