"""The benchmark's scenarios: helicopter runs over imbalance, rotor speed and tail rotor, measured flights, synthetics.

Names come from the config's ``benchmark`` section (`scenario_specs`): every combination of helicopter.flight x
imbalance_mass_factor x rotor_speed_ratio x tail_rotor x mount ("heli_m0.5_r1.1_tail_on_at_cg" in vacuum,
"heli_hover_m0.5_r1.1_at_cg" in flight: a flying helicopter has its tail rotor on, so tail_rotor false exists in
vacuum only), and the entries of the lists ``synthetic`` and ``flight_logs`` by their `name`. `split` puts each one,
seeded, in the tuning or the evaluation set. `scenario_input` makes one scenario's mount input: a dataset with
`mount_displacement` and `mount_rotation` (axis x, y, z; time), m and rad.

Helicopter: in vacuum `uavdamp.helicopter.run`, in hover or forward flight `uavdamp.helicopter.flight_run` (trim,
release, pilot), with the imbalanced blade's mass factor, both rotor speeds scaled by the ratio (main rotor
`omega_rad_s`; the tail rotor at its `omega_running_rad_s` when on, stopped when off), then
`uavdamp.sources.excitation.cases_dataset`: high-passed and each axis's dominant line scaled to amplitude_m (per_axis,
as the study's case 1). Measured flights (``benchmark.flight_logs``, kind "flight_log"): a window of a configured log,
as measured (`uavdamp.sources.excitation.case_input`, the study's `Case`). Synthetic entries are named uses of
the stated sources' kinds sweep, tones and random at amplitude_m (`uavdamp.sources.stated`: their keys, rules and
generator), and ``benchmark.sources`` names stated sources taken as stated: one source system for both experiments.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, replace

import numpy as np
import xarray as xr

from uavdamp import helicopter as H
from uavdamp.contract import MountMotion
from uavdamp.helicopter import FLIGHTS, HelicopterRun
from uavdamp.settings import require, setting
from uavdamp.sources import stated
from uavdamp.sources.excitation import MOTIONS, Case, case_input

KINDS = ("helicopter", *stated.SYNTHETIC, "flight_log", "source")
_ATTRS = {"units": "m", "long_name": "translation of the platform mount (input), inertial frame"}
_ROTATION_ATTRS = {"units": "rad", "long_name": "rotation vector of the platform mount (input), inertial frame"}
_W = "benchmark."


@dataclass(frozen=True)
class HelicopterScenarios:
    """The helicopter scenarios' grid (``benchmark.helicopter``): every combination is one scenario."""

    imbalance_mass_factor: tuple[float, ...] = setting()  # 1, mass scale of the imbalanced main blade
    rotor_speed_ratio: tuple[float, ...] = setting()  # 1, both rotor speeds relative to the config's
    tail_rotor: tuple[bool, ...] = setting()  # stopped (false) or running (true)
    mount: tuple[str, ...] = setting()  # mount points (helicopter.mount_points_m) whose motion is the input
    motion: str = setting()  # planar (y, z translation) | full (translation and rotation): `excitation.Case`
    flight: tuple[str, ...] = setting()  # flight conditions (FLIGHTS)

    def validate(self) -> None:
        for key in ("imbalance_mass_factor", "rotor_speed_ratio"):
            values = getattr(self, key)
            require(bool(values) and min(values) > 0, f"{_W}helicopter.{key}", f"must be > 0, got {list(values)}")
        require(
            self.motion in MOTIONS, f"{_W}helicopter.motion", f"must be one of {list(MOTIONS)}, got {self.motion!r}"
        )
        for k, flight in enumerate(self.flight):
            require(flight in FLIGHTS, f"{_W}helicopter.flight[{k}]", f"must be one of {list(FLIGHTS)}, got {flight!r}")


@dataclass(frozen=True)
class Synthetic:
    """A synthetic scenario (an entry of ``benchmark.synthetic``): a named use of a stated source of kind sweep,
    tones or random (`uavdamp.sources.stated.StatedSource`: its rules, its generator) at benchmark.amplitude_m."""

    name: str = setting()
    kind: str = setting()
    freq_hz: tuple[float, ...] | None = setting(default=None)  # Hz, sweep: [start, end]
    freq_y_hz: tuple[float, ...] | None = setting(default=None)  # Hz, tones on y
    freq_z_hz: tuple[float, ...] | None = setting(default=None)  # Hz, tones on z
    band_hz: tuple[float, ...] | None = setting(default=None)  # Hz, random: band-pass [low, high]
    seed: int | None = setting(default=None)  # random: seed of the generator

    def source(self, amplitude_m: float) -> stated.StatedSource:
        """The stated source this scenario uses, at `amplitude_m` m."""
        keys = {k: getattr(self, k) for k in ("freq_hz", "freq_y_hz", "freq_z_hz", "band_hz", "seed")}
        return stated.StatedSource(kind=self.kind, amplitude_m=amplitude_m, **keys)

    def validate(self, where: str) -> None:
        ok = self.kind in stated.SYNTHETIC
        require(ok, f"{where}.kind", f"must be one of {list(stated.SYNTHETIC)}, got {self.kind!r}")
        takes = self._keys()
        for key in ("freq_hz", "freq_y_hz", "freq_z_hz", "band_hz", "seed"):
            given = getattr(self, key) is not None
            require(
                given == (key in takes),
                f"{where}.{key}",
                f"kind {self.kind!r} takes {takes} (amplitude: {_W}amplitude_m)",
            )
        self.source(1.0).validate(where)  # the ranges: the stated source's own rules

    def _keys(self) -> list[str]:
        """The keys the kind takes here: the stated source's (`stated.KINDS`) but its amplitude."""
        return [k for k in stated.KINDS[self.kind] if k != "amplitude_m"]

    def spec(self) -> dict:
        """{"kind": ..., and the kind's keys}."""
        return {"kind": self.kind, **{k: _plain(getattr(self, k)) for k in self._keys()}}


def _plain(value):
    return list(value) if isinstance(value, tuple) else value


@dataclass(frozen=True)
class MeasuredScenario:
    """A measured-flight scenario (an entry of ``benchmark.flight_logs``): a window of a configured flight log
    (``flight_logs.NAME``), as measured (`uavdamp.sources.excitation.Case` with amplitude_scaling: measured)."""

    name: str = setting()
    flight_log: str = setting()  # a name of the flight_logs section
    window_s: tuple[float, ...] | None = setting(default=None, length=2)  # s of the log's clock
    motion: str = setting(default="full")  # planar | full

    def validate(self, where: str) -> None:
        ok = self.motion in MOTIONS
        require(ok, f"{where}.motion", f"must be one of {list(MOTIONS)}, got {self.motion!r}")

    def case(self) -> Case:
        """The scenario as a study case."""
        return Case(
            flight_log=self.flight_log, window_s=self.window_s, amplitude_scaling="measured", motion=self.motion
        )


@dataclass(frozen=True, kw_only=True)
class ScenarioOptions:
    """The scenario jobs' view of ``benchmark``: run length, amplitude, the helicopter grid and the synthetics."""

    duration_s: float = setting()  # s
    amplitude_m: float = setting()  # m
    highpass_hz: float = setting()  # Hz, helicopter inputs
    band_hz: tuple[float, ...] = setting(length=2)  # Hz, where the helicopter inputs' dominant line is read
    helicopter: HelicopterScenarios = setting()
    synthetic: tuple[Synthetic, ...] = setting()
    flight_logs: tuple[MeasuredScenario, ...] = setting(default=())
    sources: tuple[str, ...] = setting(default=())  # names of the ``sources`` section, each one scenario as stated

    def validate(self) -> None:
        require(self.duration_s > 0, _W + "duration_s", f"must be > 0, got {self.duration_s}")
        require(self.amplitude_m > 0, _W + "amplitude_m", f"must be > 0, got {self.amplitude_m}")
        require(0 < self.band_hz[0] < self.band_hz[1], _W + "band_hz", f"need 0 < low < high, got {list(self.band_hz)}")
        names = [s.name for s in (*self.synthetic, *self.flight_logs)] + list(self.sources)
        require(len(set(names)) == len(names), _W + "synthetic", f"names must be unique, got {names}")


def scenario_specs(options: ScenarioOptions) -> dict[str, dict]:
    """{name: spec} of every scenario (spec["kind"] in KINDS)."""
    heli = options.helicopter
    specs = {}
    grid = itertools.product(
        heli.flight, heli.imbalance_mass_factor, heli.rotor_speed_ratio, heli.tail_rotor, heli.mount
    )
    for flight, mass, ratio, tail, mount in grid:
        if flight == "vacuum":
            name = f"heli_m{float(mass):g}_r{float(ratio):g}_tail_{'on' if tail else 'off'}_at_{mount}"
        elif tail:
            name = f"heli_{flight}_m{float(mass):g}_r{float(ratio):g}_at_{mount}"
        else:
            continue  # a flying helicopter has its tail rotor on
        specs[name] = {
            "kind": "helicopter",
            "flight": flight,
            "mass_factor": float(mass),
            "speed_ratio": float(ratio),
            "tail_rotor": tail,
            "mount": mount,
        }
    for entry in options.synthetic:
        require(entry.name not in specs, f"{_W}synthetic.{entry.name}", "the name is taken by a helicopter scenario")
        specs[entry.name] = entry.spec()
    for entry in options.flight_logs:
        require(entry.name not in specs, f"{_W}flight_logs.{entry.name}", "the name is taken by another scenario")
        window = None if entry.window_s is None else list(entry.window_s)
        specs[entry.name] = {"kind": "flight_log", "flight_log": entry.flight_log, "window_s": window}
    for name in options.sources:
        require(name not in specs, f"{_W}sources", f"{name!r}: the name is taken by another scenario")
        specs[name] = {"kind": "source", "source": name}
    return specs


def flight_log_of(options: ScenarioOptions, name: str) -> str | None:
    """The flight log (a name of ``flight_logs``) scenario `name` reads, None for the others."""
    return next((entry.flight_log for entry in options.flight_logs if entry.name == name), None)


@dataclass(frozen=True)
class Split:
    """The seeded split of the scenarios into the tuning and the evaluation set (``benchmark.split``)."""

    tuning_fraction: float = setting()  # 1
    seed: int = setting()

    def validate(self) -> None:
        ok = 0 < self.tuning_fraction < 1
        require(ok, _W + "split.tuning_fraction", f"must lie in (0, 1), got {self.tuning_fraction}")


def split(names, tuning_fraction: float, seed: int) -> dict[str, str]:
    """{name: "tuning" | "evaluation"}: a seeded random `tuning_fraction` of the sorted names (at least one of each)."""
    names = sorted(names)
    if len(names) < 2:
        raise ValueError(f"benchmark: need at least 2 scenarios to split, got {len(names)}")
    n_tune = min(max(int(round(tuning_fraction * len(names))), 1), len(names) - 1)
    order = np.random.default_rng(seed).permutation(len(names))
    tuning = {names[i] for i in order[:n_tune]}
    return {name: ("tuning" if name in tuning else "evaluation") for name in names}


def helicopter_input(heli: HelicopterRun, spec: dict, options: ScenarioOptions) -> tuple[np.ndarray, MountMotion, str]:
    """(time s, mount motion, warning) of one helicopter scenario (module docstring); `heli` a FlightRun for a flight
    one; the warning of a flight run flown on an unconverged trim (helicopter.flight.allow_unconverged), else ""."""
    ratio = spec["speed_ratio"]
    running = heli.tail_rotor.omega_running_rad_s * ratio
    heli = replace(
        heli,
        imbalance=replace(heli.imbalance, mass_factor=spec["mass_factor"]),
        main_rotor=replace(heli.main_rotor, omega_rad_s=heli.main_rotor.omega_rad_s * ratio),
        tail_rotor=replace(heli.tail_rotor, omega_running_rad_s=running),
        solver=replace(heli.solver, duration=options.duration_s),
    )
    flight = spec.get("flight", "vacuum")
    if flight == "vacuum":
        heli = heli.with_tail_rotor_speed(running if spec["tail_rotor"] else 0.0)
        run = H.run(heli, heli.solver)
    else:
        run = H.flight_run(heli, flight)[0]
    case = Case(
        run="run",
        mount=spec["mount"],
        amplitude=options.amplitude_m,
        amplitude_reading="dominant",
        amplitude_scaling="per_axis",
        motion=options.helicopter.motion,
    )
    t, motion, _ = case_input(
        run, case, "benchmark", duration=options.duration_s, highpass_hz=options.highpass_hz, band_hz=options.band_hz
    )
    return t - t[0], motion, run.attrs.get("warning", "")


def synthetic_input(spec: dict, *, duration: float, amplitude: float, time_step: float):
    """(time s, y m, z m) of one synthetic scenario (module docstring), sampled every time_step s: the stated
    sources' generator (`uavdamp.sources.stated.synthetic_yz`), so a study case and a scenario of one kind agree."""
    if spec["kind"] not in stated.SYNTHETIC:
        raise ValueError(f"benchmark.synthetic kind: must be one of {list(stated.SYNTHETIC)}, got {spec['kind']!r}")
    return stated.synthetic_yz(spec["kind"], spec, duration=duration, amplitude=amplitude, time_step=time_step)


def measured_input(entry: MeasuredScenario, log: xr.Dataset, options: ScenarioOptions):
    """(time s from 0, MountMotion) of a measured-flight scenario from its log (`uavdamp.read_flight_log`)."""
    t, motion, _ = case_input(
        log,
        entry.case(),
        f"{_W}flight_logs.{entry.name}",
        duration=options.duration_s,
        highpass_hz=options.highpass_hz,
        band_hz=options.band_hz,
    )
    return t, motion


def scenario_input(
    name: str,
    options: ScenarioOptions,
    heli: HelicopterRun,
    time_step: float,
    log: xr.Dataset | None = None,
    source: stated.StatedSource | None = None,
) -> xr.Dataset:
    """The named scenario's input dataset: mount_displacement and mount_rotation (axis x, y, z; time), m and rad;
    a flight_log scenario needs its `log` (`uavdamp.read_flight_log`), a source scenario its stated `source`
    (``sources.NAME``), taken as stated over benchmark.duration_s."""
    specs = scenario_specs(options)
    if name not in specs:
        raise ValueError(f"benchmark scenario: unknown {name!r} (known: {sorted(specs)})")
    spec, warning = specs[name], ""
    if spec["kind"] == "helicopter":
        t, motion, warning = helicopter_input(heli, spec, options)
    elif spec["kind"] == "flight_log":
        if log is None:
            raise ValueError(f"benchmark scenario {name!r}: needs the flight log {spec['flight_log']!r}")
        t, motion = measured_input(next(e for e in options.flight_logs if e.name == name), log, options)
    elif spec["kind"] == "source":
        if source is None:
            raise ValueError(f"benchmark scenario {name!r}: needs its stated source sources.{name}")
        t, motion, _ = stated.motion(source, options.duration_s)
    else:
        t, y, z = synthetic_input(spec, duration=options.duration_s, amplitude=options.amplitude_m, time_step=time_step)
        motion = MountMotion.planar(y, z)
    return xr.Dataset(
        {
            "mount_displacement": (("axis", "time"), motion.translation, _ATTRS),
            "mount_rotation": (("axis", "time"), motion.rotation, _ROTATION_ATTRS),
        },
        coords={
            "axis": ("axis", ["x", "y", "z"], {"units": "1", "long_name": "axis (x forward, y left, z up)"}),
            "time": ("time", t, {"units": "s", "long_name": "time"}),
        },
        attrs={
            "scenario": name,
            "kind": spec["kind"],
            "spec": ", ".join(f"{k}={v}" for k, v in spec.items() if k != "kind"),
            **({"warning": warning} if warning else {}),  # a flight run flown on an unconverged trim
        },
    )
