"""The payload comparison: the paper's pan-tilt head, the same head balanced, and a gyro-stabilised gimbal, each on
a rigid mount, the paper's Y-Z isolator and a six-axis isolator (rubber-ball or wire-rope elements), over constant
damping candidates.

Payloads: ``paper_head`` (the platform as configured: the camera's centre of mass off the tilt axis),
``balanced_head`` (the same with the camera's centre of mass on the axes: ``camera_com_x_m`` = ``camera_com_z_m`` = 0)
and ``gimbal`` (`uavdamp.platform.gimbal`, designed from ``payload.gimbal``). Mounts: ``rigid`` (no isolator),
``yz`` (the paper's isolator, K = ``yz_stiffness_n_m``: the heads on their own plant, the gimbal on
`uavdamp.platform.six_axis.paper_yz`), ``six_axis`` (`six_axis_isolator`: the gimbal only; the heads' plant has
a Y-Z isolator alone, so NaN) and ``wire_rope`` (its elements with Bouc-Wen hysteresis, ``payload.wire_rope``:
`uavdamp.platform.wire_rope`; the gimbal only). Every run is scored by `uavdamp.study.payload_runs.run_metrics`;
the inputs are the study's cases and the stated sources ``payload.sources`` names (`inputs`, `compare_inputs`).

Choices and assumptions:
- The gimbal's moving mass besides the camera (brackets, motors) is `MECHANISM_MASS_KG` (choice); the isolated
  payload is camera (the platform's, ``platform.structure``: one camera on every payload) + mechanism + plate
  (``six_axis.plate_mass_kg``): 0.9 + 0.3 + 0.3 = 1.5 kg by default, its
  centre of mass ``com_height_m`` above the elements' plane, the plate (a thin square of side 2 ``half_spacing_m``)
  in that plane and the gimbal's axes (the balanced camera's centre of mass, the optical centre) above it at the
  height that puts the whole centre of mass there (`gimbal_height`: 0.075 m by default). The same point carries
  the gimbal on every mount; the mount motion is that of the mount's reference point (the elements' centre).
- One-way coupling: the gimbal motors' reaction torque on the isolated body is left out of the body's motion
  (`uavdamp.platform.gimbal_loop.design_report` sizes it).
- Every gimbal run draws its IMU noise from a fresh Generator of ``payload.seed`` (common random numbers: runs
  differ by the mount alone); ``floor_los_std`` is the gimbal on a still mount (the heads': 0).
- The six-axis isolator carries the gimbal's gravity (geometric stiffness); every element's damper is semi-active
  at the candidate C along x, y and z. Its modes by default (`uavdamp.study.payload_design.design_dataset`):
  2.77 Hz (x + ry), 2.79 (y + rx),
  5.81 (z), 6.48 (rz), 7.86 (ry + x), 8.17 Hz (rx + y); the Y-Z isolator's under the 1.5 kg gimbal: 4.11 Hz (y, z,
  the rest near-rigid at 1 kHz); the gimbal's rate loops cross at 40 Hz (50 deg; whole loop 39.7 deg, 9.6 dB),
  its attitude loops at 8 Hz. The heads' Y-Z damper takes the same C (within the platform's damper
  bounds); a head's roll is the mount's (`uavdamp.study.payload_runs`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import xarray as xr

from uavdamp import parallel
from uavdamp.camera.optics import CameraModel
from uavdamp.contract import MountMotion, is_multiple
from uavdamp.platform import PlatformParams
from uavdamp.platform.gimbal import GimbalParams, design
from uavdamp.platform.plants import Plants
from uavdamp.settings import ConfigError, require, setting
from uavdamp.sources.excitation import case_motion
from uavdamp.sources.stated import StatedSource, motion
from uavdamp.study import payload_laws as laws
from uavdamp.study import payload_runs as runs
from uavdamp.study.payload_anfis import AnfisLaw, AnfisPayloadSection
from uavdamp.study.payload_runs import (  # noqa: F401 (the helpers' public face)
    MECHANISM_MASS_KG,
    SIX_AXIS_MOUNTS,
    gimbal_height,
    gimbal_mass,
    gimbal_params,
    gimbal_payload,
    isolator,
    resampled,
    six_axis_isolator,
    yz_isolator,
)
from uavdamp.study.payload_schedule import ScheduleSection, Table
from uavdamp.study.payload_sections import GimbalSection, MRSection, SixAxisSection, WireRopeSection
from uavdamp.study.payload_table import TableSection
from uavdamp.study.payload_table import check as check_table

PAYLOADS = ("paper_head", "balanced_head", "gimbal")
MOUNTS = ("rigid", "yz", "six_axis", "wire_rope")
HEADS = ("paper_head", "balanced_head")


@dataclass(frozen=True)
class PayloadSection:
    """The config section ``payload`` (module docstring), SI units."""

    payloads: tuple[str, ...] = setting(default=PAYLOADS)
    mounts: tuple[str, ...] = setting(default=MOUNTS)
    duration_s: float = setting(default=5.0)  # s, of each input from its start
    settle_s: float = setting(default=1.0)  # s, metrics over [settle_s, duration_s]
    time_step_s: float = setting(default=5.0e-4)  # s, the runs' grid
    yz_stiffness: float = setting("yz_stiffness_n_m", default=1000.0)  # N m-1, K of the Y-Z isolator
    damping: tuple[float, ...] = setting("damping_n_s_m", default=(1.0, 3.0, 10.0, 30.0, 100.0))  # N s m-1
    seed: int = setting(default=0)  # the gimbal IMU's noise
    skyhook_lag: float = setting("skyhook_lag_s", default=0.0)  # s, the skyhook damper's lag (0: ideal; choice)
    # N s m-1, the skyhook runs' off damping (None: the least damping candidate; choice)
    skyhook_c_off: float | None = setting("skyhook_c_off_n_s_m", default=None)
    threads: int = setting(default=1)  # joblib workers over the inputs (the rule's threads; not in the results)
    sources: tuple[str, ...] = setting(default=())  # stated sources run beside the study's cases
    gimbal: GimbalSection = setting(default=GimbalSection())
    six_axis: SixAxisSection = setting(default=SixAxisSection())
    wire_rope: WireRopeSection = setting(default=WireRopeSection())  # the mount wire_rope: six_axis, Bouc-Wen
    mr: MRSection = setting(default=MRSection())  # MR dampers on the six-axis isolator's elements (six_axis_force)
    schedule: ScheduleSection = setting(default=ScheduleSection())  # the scheduled law (payload_schedule)
    anfis: AnfisPayloadSection = setting(default=AnfisPayloadSection())  # the payload ANFIS (payload_anfis)
    table: TableSection = setting(default=TableSection())  # the closed-form table of the best C (payload_table)

    @property
    def c_off(self) -> float:
        """N s m-1, the skyhook runs' off damping: ``skyhook_c_off_n_s_m``, or the least damping candidate."""
        return float(min(self.damping) if self.skyhook_c_off is None else self.skyhook_c_off)

    def with_camera(self, structure) -> PayloadSection:
        """The section with the gimbal carrying the platform's camera (``platform.structure.camera_mass_kg`` and
        ``camera_size_m`` of `structure`): one camera on every payload."""
        camera = {"camera_mass": float(structure.camera_mass), "camera_size": tuple(structure.camera_size)}
        return dataclasses.replace(self, gimbal=dataclasses.replace(self.gimbal, **camera))

    def validate(self) -> None:
        w = "payload."
        for key, allowed in (("payloads", PAYLOADS), ("mounts", MOUNTS)):
            names = getattr(self, key)
            ok = 0 < len(names) == len(set(names)) and set(names) <= set(allowed)
            require(ok, w + key, f"must be distinct names of {list(allowed)}, got {list(names)}")
        require(self.duration_s > 0, w + "duration_s", f"must be > 0, got {self.duration_s}")
        ok = 0 <= self.settle_s < self.duration_s
        require(ok, w + "settle_s", f"must lie in [0, duration_s), got {self.settle_s}")
        period = 1.0 / self.gimbal.loop_rate_hz
        ok = self.time_step_s > 0 and is_multiple(period, self.time_step_s)
        require(ok, w + "time_step_s", f"({self.time_step_s} s) must divide the gimbal loop period {period} s")
        require(self.yz_stiffness > 0, w + "yz_stiffness_n_m", f"must be > 0, got {self.yz_stiffness}")
        require(self.skyhook_lag >= 0, w + "skyhook_lag_s", f"must be >= 0, got {self.skyhook_lag}")
        off = self.skyhook_c_off
        ok = off is None or (off > 0 and any(c > off for c in self.damping))
        require(ok, w + "skyhook_c_off_n_s_m", f"must be > 0 and below a damping candidate (c_on), got {off}")
        c = self.damping
        ok = len(c) > 0 and len(set(c)) == len(c) and min(c) >= 0
        require(ok, w + "damping_n_s_m", f"needs distinct values >= 0 N s m-1, got {list(c)}")
        require(self.seed >= 0, w + "seed", f"must be >= 0, got {self.seed}")
        require(len(set(self.sources)) == len(self.sources), w + "sources", "names must be unique")
        try:
            six_axis_isolator(self, c[0])
        except ValueError as error:
            raise ConfigError(f"{w}six_axis: the isolator cannot carry the payload ({error})") from None
        check_table(self)

    @property
    def middle_damping(self) -> float:
        """The middle candidate C (the upper middle of an even count), N s m-1."""
        return float(sorted(self.damping)[len(self.damping) // 2])


def head_platform(platform: PlatformParams, payload: str, time_step: float) -> PlatformParams:
    """The platform of a head payload on the runs' grid (time_step s; the update period rounded to a multiple of
    it: a constant law needs no particular one); ``balanced_head`` with the camera's centre of mass on the axes."""
    s = platform.structure
    if payload == "balanced_head":
        s = dataclasses.replace(s, camera_com_x=0.0, camera_com_z=0.0)
    period = time_step * max(1, round(platform.isolator.update_period / time_step))
    return dataclasses.replace(
        platform,
        structure=s,
        solver=dataclasses.replace(platform.solver, time_step=time_step),
        isolator=dataclasses.replace(platform.isolator, update_period=period),
    )


def modelled(payload: str, mount: str) -> bool:
    """False where the comparison has no model: a head on a six-axis mount (its plant has a Y-Z isolator only)."""
    return not (payload in HEADS and mount in SIX_AXIS_MOUNTS)


@dataclass(frozen=True)
class _Setup:
    """What every run of one comparison shares."""

    section: PayloadSection
    gimbal: GimbalParams
    gains: dict
    lever: tuple[float, float, float]  # m, the gimbal's axes from the mount's reference point
    plants: dict  # head payload -> its Plants
    camera: CameraModel
    table: Table | None = None  # the payload table at the six-axis isolator's K: the scheduled law (None: none)
    anfis: AnfisLaw | None = None  # the payload ANFIS as a law (None: none)


def _setup(section: PayloadSection, platform: PlatformParams, camera: CameraModel, table=None, model=None) -> _Setup:
    heads = [p for p in section.payloads if p in HEADS]
    if heads and "yz" in section.mounts:
        lo, hi = platform.damping_min, platform.damping_max
        ok = lo <= min(section.damping) and max(section.damping) <= hi
        require(ok, "payload.damping_n_s_m", f"the heads' damper takes [{lo}, {hi}] N s m-1: {section.damping}")
    plants = {p: Plants(head_platform(platform, p, section.time_step_s)) for p in heads}
    g = gimbal_params(section)
    limit = section.schedule.max_decay_time
    k = section.six_axis.stiffness[2]
    at_k = None if table is None else Table.of(table, k, limit)
    law = None if model is None or at_k is None else AnfisLaw.of(model, section.anfis.dofs, k, at_k)
    return _Setup(section, g, design(g), (0.0, 0.0, gimbal_height(section)), plants, camera, at_k, law)


def _input(time, mount: MountMotion, section: PayloadSection) -> tuple[np.ndarray, MountMotion]:
    """The input from its start on the runs' grid, cut at duration_s; ValueError naming payload.duration_s.

    Band-limited (`resampled`): the gimbal's IMU reads the mount's acceleration, the second derivative of the
    motion, and a linear interpolation's is a train of spikes at the input's samples."""
    t = np.asarray(time, dtype=float)
    grid, moved = resampled(t - t[0], mount, section.time_step_s)
    n = int(round(section.duration_s / section.time_step_s)) + 1
    if grid.size < n:
        raise ValueError(f"payload.duration_s: {section.duration_s} s is longer than the input ({grid[-1]} s)")
    return grid[:n], MountMotion(moved.translation[:, :n], moved.rotation[:, :n])


def _bodies(setup: _Setup, t: np.ndarray, moved: MountMotion, mount: str, dampings) -> list[runs.BodyMotion]:
    """The gimbal's body on `mount` at each C of `dampings` (N s m-1; the rigid mount's one body whatever the C)
    under the gridded input (t s, moved); the wire rope's candidates integrated side by side."""
    s = setup.section
    if mount == "rigid":
        return [runs.rigid_motion(t, moved)]
    if mount == "wire_rope":
        return runs.hysteretic_motions(s, list(dampings), t, moved)
    return [runs.isolated_motion(isolator(s, mount, c), t, moved) for c in dampings]


def _gimbal(setup: _Setup, t: np.ndarray, bodies: list[runs.BodyMotion]) -> list[runs.Series]:
    """The gimbal on each of `bodies`, side by side (`payload_runs.gimbal_series` with the section's sensor errors
    and seed)."""
    s = setup.section
    errors = s.gimbal.sensor_errors
    return runs.gimbal_series(setup.gimbal, setup.gains, t, bodies, setup.lever, sensor_errors=errors, seed=s.seed)


def _values(setup: _Setup, t: np.ndarray, moved: MountMotion) -> dict[str, np.ndarray]:
    """Every metric of `payload_runs.METRICS` over (payload, mount, damping) under the gridded input (`_input`);
    NaN where not modelled, the rigid mount's value at every C. The gimbal's runs of every mount and C side by side."""
    s = setup.section
    values = {name: np.full((len(s.payloads), len(s.mounts), len(s.damping)), math.nan) for name in runs.METRICS}
    cells, bodies = [], []  # (payload index, mount index, damping index), and the gimbal's bodies in that order
    for (i, payload), (j, where) in ((a, b) for a in enumerate(s.payloads) for b in enumerate(s.mounts)):
        if not modelled(payload, where):
            continue
        candidates = _candidates(s, where)
        if payload in HEADS:
            for k, c in candidates:
                series = runs.head_series(setup.plants[payload], where, t, moved, s.yz_stiffness, c)
                _store(values, (i, j, k), runs.run_metrics(t, series, setup.camera, s.settle_s, s.duration_s))
        else:
            cells += [(i, j, k) for k, _ in candidates]
            bodies += _bodies(setup, t, moved, where, [c for _, c in candidates])
    for cell, series in zip(cells, _gimbal(setup, t, bodies) if bodies else [], strict=True):
        _store(values, cell, runs.run_metrics(t, series, setup.camera, s.settle_s, s.duration_s))
    return values


def _store(values: dict[str, np.ndarray], cell: tuple, metrics: dict[str, float]) -> None:
    """Each metric of one run into its array at `cell` (payload, mount, damping index)."""
    for name, value in metrics.items():
        values[name][cell] = value


def _candidates(section: PayloadSection, mount: str) -> list:
    """(index, C) of the damping candidates on `mount`: the rigid mount's one run fills every index."""
    return [(slice(None), math.nan)] if mount == "rigid" else list(enumerate(section.damping))


def _floor(setup: _Setup) -> np.ndarray:
    """LOS rms (rad) of each payload on a still mount: the gimbal's sensor floor, 0 for a head."""
    s = setup.section
    out = np.zeros(len(s.payloads))
    if "gimbal" in s.payloads:
        t = np.arange(int(round(s.duration_s / s.time_step_s)) + 1) * s.time_step_s
        still = MountMotion(np.zeros((3, t.size)), np.zeros((3, t.size)))
        (series,) = _gimbal(setup, t, _bodies(setup, t, still, "rigid", [math.nan]))
        out[s.payloads.index("gimbal")] = runs.run_metrics(t, series, setup.camera, s.settle_s, s.duration_s)["los_std"]
    return out


def compare_payloads(
    time,
    mount: MountMotion,
    section: PayloadSection,
    platform: PlatformParams,
    camera: CameraModel,
    table=None,
    model=None,
) -> xr.Dataset:
    """Every payload x mount x damping candidate (module docstring) under the mount motion (time s, any start;
    the first ``duration_s`` of it on the ``time_step_s`` grid): the metrics of `payload_runs.METRICS` over
    (payload, mount, damping), NaN where not modelled (`modelled`), the rigid mount's the same at every C;
    ``best_damping`` (payload, mount) the C of the least ``los_std`` (NaN: rigid, not modelled) and
    ``floor_los_std`` (payload) the LOS rms on a still mount; with the payload table `table` (``payload/table.nc``)
    also the scheduled law (`uavdamp.study.payload_schedule`), and with the payload ANFIS `model` (a
    `DampingModel` of `uavdamp.study.payload_anfis`) its law. Assumptions: module docstring."""
    setup = _setup(section, platform, camera, table, model)
    t, moved = _input(time, mount, section)
    return _dataset(setup, _values(setup, t, moved), _floor(setup), laws.law_values(setup, t, moved))


class PayloadInput(NamedTuple):
    """One input of the comparison: its name, a description, time (s) and the mount motion."""

    name: str
    description: str
    time: np.ndarray
    mount: MountMotion


def inputs(cases: xr.Dataset, sources: dict[str, StatedSource], section: PayloadSection) -> list[PayloadInput]:
    """The study's cases (a `uavdamp.sources.excitation` cases dataset) and the stated sources ``payload.sources``
    names (`sources`: name -> `StatedSource`, generated over ``duration_s``), in that order."""
    found = []
    for case in cases.case.values:
        text = str(cases.description.sel(case=case).item()) if "description" in cases else ""
        found.append(PayloadInput(str(case), text, cases.time.values, case_motion(cases, case)))
    for k, name in enumerate(section.sources):
        require(name in sources, f"payload.sources[{k}]", f"{name!r} is not a stated source ({sorted(sources)})")
        t, moved, _ = motion(sources[name], section.duration_s)
        found.append(PayloadInput(name, sources[name].description or sources[name].kind, t, moved))
    return found


def compare_inputs(
    found: list[PayloadInput],
    section: PayloadSection,
    platform: PlatformParams,
    camera: CameraModel,
    table=None,
    model=None,
) -> xr.Dataset:
    """`compare_payloads` of every input, stacked over ``input`` (with ``input_description``); the still mount's
    ``floor_los_std`` once (it does not depend on the input). The inputs run on ``threads`` joblib workers
    (`uavdamp.parallel.run`): the same numbers on any count."""
    require(len(found) > 0, "payload.sources", "no input: the study has no case and payload.sources is empty")
    floor = _floor(_setup(section, platform, camera))
    gridded = [_input(i.time, i.mount, section) for i in found]  # each input resampled once
    tasks = [(_one_input, (section, platform, camera, t, moved, floor, table, model)) for t, moved in gridded]
    per_input = parallel.run(tasks, section.threads)
    names = [i.name for i in found]
    ds = xr.concat([d.drop_vars("floor_los_std") for d in per_input], dim="input", combine_attrs="override")
    ds = ds.assign_coords(input=("input", names, {"units": "1", "long_name": "input (study case or stated source)"}))
    ds["input_description"] = ("input", [i.description for i in found], {"units": "1", "long_name": "the input"})
    rotation = [float(np.sqrt(np.sum(np.var(moved.rotation, axis=1)))) for _, moved in gridded]
    ds["input_rotation_rms"] = ("input", rotation, {"units": "rad", "long_name": "the mount's rotation rms (3 axes)"})
    ds["floor_los_std"] = per_input[0].floor_los_std
    return ds


def _one_input(section, platform, camera, t, moved: MountMotion, floor: np.ndarray, table, model) -> xr.Dataset:
    """One gridded input's comparison (a task of `compare_inputs`: its own setup, so that it runs in a worker)."""
    setup = _setup(section, platform, camera, table, model)
    return _dataset(setup, _values(setup, t, moved), floor, laws.law_values(setup, t, moved))


def _best_damping(section: PayloadSection, los_std: np.ndarray) -> np.ndarray:
    """(payload, mount) the candidate C of the least LOS rms; NaN for the rigid mount and where not modelled."""
    out = np.full(los_std.shape[:2], math.nan)
    for i, j in np.ndindex(out.shape):
        if section.mounts[j] != "rigid" and np.isfinite(los_std[i, j]).any():
            out[i, j] = section.damping[int(np.nanargmin(los_std[i, j]))]
    return out


def _dataset(setup: _Setup, values: dict, floor: np.ndarray, law_values: dict) -> xr.Dataset:
    s = setup.section
    law_data, law_coord = laws.law_variables(law_values, s)
    dims = ("payload", "mount", "damping")
    data = {name: (dims, v, runs.metric_attrs(name)) for name, v in values.items()}
    data["best_damping"] = (
        ("payload", "mount"),
        _best_damping(s, values["los_std"]),
        {"units": "N s m-1", "long_name": "constant damping of the least line-of-sight rms (NaN: rigid mount)"},
    )
    data["floor_los_std"] = (
        ("payload",),
        floor,
        {"units": "rad", "long_name": "line-of-sight rms on a still mount (the gimbal's sensor floor; heads 0)"},
    )
    data |= law_data
    coords = law_coord | {
        "payload": ("payload", list(s.payloads), {"units": "1", "long_name": "camera payload"}),
        "mount": ("mount", list(s.mounts), {"units": "1", "long_name": "camera mount (isolator)"}),
        "damping": ("damping", np.asarray(s.damping, dtype=float), {"units": "N s m-1", "long_name": "damping C"}),
    }
    attrs = {
        "title": "Camera payloads (pan-tilt heads, stabilised gimbal) on rigid, Y-Z and six-axis mounts",
        "settle_s": s.settle_s,
        "duration_s": s.duration_s,
        "time_step_s": s.time_step_s,
        "yz_stiffness_N_m": s.yz_stiffness,
        "gimbal_payload_mass_kg": gimbal_payload(s).mass,
        "gimbal_height_m": setup.lever[2],
        "seed": s.seed,
        "coupling": "one-way: the gimbal motors' reaction torque on the isolated body is left out",
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)
