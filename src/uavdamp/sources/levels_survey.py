"""The levels survey: every input the study uses (helicopter runs, the study's cases, stated sources, flight logs)
read at the mount in the units its field states levels in, per line in g and in/s 0-peak (`levels.line_levels`,
each line located in the record), ArduPilot's VIBE per axis (`levels.vibe`) and the lateral 1/rev against the
hover track-and-balance limit (`levels.track_and_balance`); the mount's rotation std beside them.

A record's lines are its source's own: a helicopter input's k/rev of the main rotor and the tail rotor's 1/rev and
blade pass; a stated source's stated lines; a flight log's largest peak per axis within its band (`band_peaks`:
the log names no line of its own below its Nyquist frequency). A flight log's VIBE is that of its logged
acceleration; every other input's is that of its displacement's second derivative (`levels.acceleration_from_
displacement`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from uavdamp.settings import require, setting
from uavdamp.signals import spectrum
from uavdamp.sources import stated
from uavdamp.sources.levels import (
    AXES,
    TRACK_AND_BALANCE_SOURCE,
    acceleration_from_displacement,
    line_levels,
    rotor_lines,
    track_and_balance,
    vibe,
    vibe_settle_s,
)


@dataclass(frozen=True)
class LevelsSection:
    """The config section ``levels``: how each input's levels are read (`survey`)."""

    settle_s: float = setting(default=10.0)  # s, a helicopter run's start left out (its trim transient)
    orders: tuple[int, ...] = setting(default=(1, 2, 3, 4))  # the main rotor's lines k/rev read on a helicopter input
    source_duration_s: float = setting(default=10.0)  # s, of each stated source generated for its levels

    def validate(self, where: str) -> None:
        require(self.settle_s >= 0, f"{where}.settle_s", f"must be >= 0, got {self.settle_s}")
        require(
            self.source_duration_s > 2 * vibe_settle_s(),
            f"{where}.source_duration_s",
            f"must exceed {2 * vibe_settle_s():.2f} s (VIBE's settling twice), got {self.source_duration_s}",
        )
        require(
            len(self.orders) > 0 and min(self.orders) >= 1 and len(set(self.orders)) == len(self.orders),
            f"{where}.orders",
            f"must be distinct integers >= 1, got {list(self.orders)}",
        )


@dataclass(frozen=True)
class Record:
    """One input's translation at the mount (x, y, z inertial; x forward, y left, z up), sampled every `dt` s:
    a displacement (3, n; m) or, for an accelerometer log, the measured acceleration (3, n; m s-2), whose VIBE is
    then the log's own; the lines to read (name -> Hz) and, where known, the mount's rotation (3, n; rad)."""

    kind: str  # what the input is: "helicopter run", "case", "stated source", "flight log"
    description: str
    dt: float
    lines_hz: dict = field(default_factory=dict)
    displacement_m: np.ndarray | None = None
    acceleration_m_s2: np.ndarray | None = None
    rotation_rad: np.ndarray | None = None


def record_levels(record: Record) -> xr.Dataset:
    """One record's levels (`line_levels`, located), its VIBE per axis (NaN for a record no longer than twice
    `vibe_settle_s`, 1.59 s) and its rotation's std per axis."""
    if (record.displacement_m is None) == (record.acceleration_m_s2 is None):
        raise ValueError("record: give exactly one of displacement_m and acceleration_m_s2")
    n = np.shape(record.acceleration_m_s2 if record.acceleration_m_s2 is not None else record.displacement_m)[-1]
    lines = resolved(record.lines_hz, n * record.dt)
    if record.acceleration_m_s2 is not None:
        accel = np.asarray(record.acceleration_m_s2, dtype=float)
        ds = line_levels(accel, record.dt, lines, kind="acceleration")
    else:
        disp = np.asarray(record.displacement_m, dtype=float)
        ds = line_levels(disp, record.dt, lines)
        accel = acceleration_from_displacement(disp, record.dt)
    rotation = np.full(len(AXES), np.nan) if record.rotation_rad is None else np.std(record.rotation_rad, axis=-1)
    long_enough = accel.shape[-1] * record.dt > 2 * vibe_settle_s()  # else NaN: VIBE's 2 Hz filter has not settled
    ds["vibe_m_s2"] = ("axis", vibe(accel, record.dt) if long_enough else np.full(len(AXES), np.nan))
    ds["rotation_std_rad"] = ("axis", rotation)
    return ds


def resolved(lines_hz: dict[str, float], record_s: float) -> dict[str, float]:
    """The lines a record of record_s s resolves (`levels.line_levels`: apart by more than 2 / T), in order: a line
    within 2 / T of one kept earlier is left out (a log's peaks, found on the whole log, on a shorter case)."""
    kept: dict[str, float] = {}
    for name, f in lines_hz.items():
        if all(abs(f - g) > 2.0 / record_s for g in kept.values()):
            kept[name] = f
    return kept


def survey(records: dict[str, Record]) -> xr.Dataset:
    """The levels of every input (name -> `Record`) on dims (input, line, axis): each input's own lines, in its
    order, padded with NaN (``line_name`` ""); VIBE and rotation std per axis; the lateral 1/rev against the
    track-and-balance limit where an input has a "1/rev" line (NaN elsewhere)."""
    if not records:
        raise ValueError("records: no input to survey")
    per = {name: record_levels(r) for name, r in records.items()}
    width = max(1, max(ds.sizes["line"] for ds in per.values()))
    shape = (len(per), width, len(AXES))
    table = {v: np.full(shape, np.nan) for v in ("accel_g", "velocity_in_s", "displacement_m")}
    freq, names = np.full(shape[:2], np.nan), np.full(shape[:2], "", dtype=object)
    ratio = np.full(len(per), np.nan)
    for i, ds in enumerate(per.values()):
        n = ds.sizes["line"]
        for v in table:
            table[v][i, :n] = ds[v].transpose("line", "axis").values
        freq[i, :n], names[i, :n] = ds.freq_hz.values, ds.line.values
        if "1/rev" in ds.line.values:
            ratio[i] = float(track_and_balance(ds).limit_ratio)
    first = next(iter(per.values()))
    out = xr.Dataset(coords={"input": ("input", list(per), {"units": "1", "long_name": "vibration input"})})
    out["axis"] = ("axis", list(AXES), first.axis.attrs)
    out["line"] = ("line", np.arange(width), {"units": "1", "long_name": "line index within an input"})
    out["line_name"] = (("input", "line"), names.astype(str), {"units": "1", "long_name": 'line ("": none)'})
    out["freq_hz"] = (("input", "line"), freq, {"units": "Hz", "long_name": "line frequency, located in the record"})
    for v, values in table.items():
        out[v] = (("input", "line", "axis"), values, first[v].attrs)
    vibe_attrs = {"units": "m s-2", "long_name": "ArduPilot VIBE of the translational acceleration (steady level)"}
    out["vibe_m_s2"] = (("input", "axis"), np.array([ds.vibe_m_s2.values for ds in per.values()]), vibe_attrs)
    rot = np.array([ds.rotation_std_rad.values for ds in per.values()])
    out["rotation_std_rad"] = (("input", "axis"), rot, {"units": "rad", "long_name": "the mount's rotation std"})
    out["track_and_balance_ratio"] = (
        "input",
        ratio,
        {"units": "1", "long_name": f"lateral 1/rev velocity over the limit ({TRACK_AND_BALANCE_SOURCE})"},
    )
    for v, attrs in (("kind", "what the input is"), ("description", "the input")):
        out[v] = ("input", [getattr(r, v) for r in records.values()], {"units": "1", "long_name": attrs})
    return out


def band_peaks(accel_m_s2, dt: float, band_hz: tuple[float, float]) -> dict[str, float]:
    """{"peak x": Hz, ...}: each axis's largest spectral peak of an acceleration record (3, n) within band_hz
    (`spectrum.dominant_frequency`), an axis's peak left out when it lies within 2 / T of one already kept (the
    lines a record without named lines, a flight log, is read at)."""
    a = np.atleast_2d(np.asarray(accel_m_s2, dtype=float))
    resolution = 2.0 / (a.shape[-1] * dt)
    peaks: dict[str, float] = {}
    for axis, row in zip(AXES, a, strict=True):
        f = spectrum.dominant_frequency(row, dt, min_freq_hz=band_hz[0], max_freq_hz=band_hz[1])
        if np.isfinite(f) and all(abs(f - g) > resolution for g in peaks.values()):
            peaks[f"peak {axis}"] = f
    return peaks


def helicopter_lines(rotor_hz: float, orders, tail_hz: float, tail_blades: int) -> dict[str, float]:
    """A helicopter input's lines (Hz): the main rotor's k/rev for k in `orders`, the tail's 1/rev and blade pass."""
    return {**rotor_lines(rotor_hz, orders), "tail 1/rev": tail_hz, f"tail {tail_blades}/rev": tail_blades * tail_hz}


def run_record(run: xr.Dataset, name: str, settle_s: float, lines: dict[str, float]) -> Record:
    """A helicopter run's record at its first mount point after settle_s s (the trim's transient left out)."""
    run = run.sel(time=run.time >= run.time.values[0] + settle_s)
    mount = str(run.mount.values[0])
    return Record(
        "helicopter run",
        f"helicopter run '{name}' at the mount '{mount}', after {settle_s:g} s",
        float(run.time[1] - run.time[0]),
        lines,
        run.mount_displacement.sel(mount=mount).transpose("axis", "time").values,
        rotation_rad=run.mount_rotation.transpose("axis", "time").values,
    )


def case_record(cases: xr.Dataset, case: str, lines: dict[str, float]) -> Record:
    """A study case's record (an `excitation` cases dataset): the motion the study runs, as scaled."""
    one = cases.sel(case=case)
    return Record(
        "case",
        f"study case: {one.description.item()}" if "description" in cases else "study case",
        float(cases.time[1] - cases.time[0]),
        lines,
        one.mount_displacement.transpose("mount_axis", "time").values,
        rotation_rad=one.mount_rotation.transpose("mount_axis", "time").values,
    )


def source_record(source: stated.StatedSource, duration_s: float) -> Record:
    """A stated source's record over duration_s s, read at its stated lines (none for a synthetic kind)."""
    t, moved, attrs = stated.motion(source, duration_s)
    table = attrs.get("lines")
    lines = {} if table is None else dict(zip(table.line.values.tolist(), table.freq_hz.values.tolist(), strict=True))
    text = source.description or source.kind
    return Record("stated source", text, float(t[1] - t[0]), lines, moved.translation, rotation_rad=moved.rotation)


def log_record(log: xr.Dataset, description: str) -> Record:
    """A flight log's record (a `flight_log` dataset): its acceleration as logged (the VIBE a log reports), read
    at its `band_peaks` within the log's band_hz."""
    dt = float(log.time[1] - log.time[0])
    accel = log.acceleration.transpose("axis", "time").values
    return Record(
        "flight log",
        f"{description} (acceleration as logged, {log.attrs.get('acc_stream', 'stream not named')})",
        dt,
        band_peaks(accel, dt, tuple(log.attrs["band_hz"])),
        acceleration_m_s2=accel,
        rotation_rad=log.mount_rotation.transpose("axis", "time").values,
    )


def summary_table(ds: xr.Dataset) -> str:
    """A text table of a survey: per input its largest line (name, Hz, g, in/s; over the axes), the lateral
    1/rev's ratio to the track-and-balance limit and the largest VIBE (m s-2)."""
    rows = [f"{'input':34s} {'largest line':>14s} {'Hz':>7s} {'g':>8s} {'in/s':>8s} {'T&B':>6s} {'VIBE':>6s}"]
    for name in ds.input.values:
        one = ds.sel(input=name)
        g = one.accel_g.max("axis")
        if np.all(np.isnan(g.values)):
            line, hz, gv, vel = "-", np.nan, np.nan, np.nan
        else:
            k = int(np.nanargmax(g.values))
            line, hz, gv = str(one.line_name.values[k]), float(one.freq_hz[k]), float(g[k])
            vel = float(one.velocity_in_s.isel(line=k).max())
        ratio, vibe_max = float(one.track_and_balance_ratio), float(one.vibe_m_s2.max())
        rows.append(f"{name:34s} {line:>14s} {hz:7.2f} {gv:8.3g} {vel:8.3g} {ratio:6.2f} {vibe_max:6.2f}")
    return "\n".join(rows)


def collect(
    runs: dict[str, xr.Dataset],
    cases: xr.Dataset,
    uses: dict[str, dict],
    sources: dict[str, stated.StatedSource],
    logs: dict[str, tuple[xr.Dataset, str]],
    options: LevelsSection,
    heli: dict[str, float],
) -> dict[str, Record]:
    """Every input's record, named "run NAME", "case NAME", "source NAME", "log NAME": helicopter runs at the
    helicopter's lines `heli` (Hz); each case (`uses`: case -> its run, source or flight_log key) at the lines of
    what it takes its motion from; stated sources over options.source_duration_s; logs (dataset, description)."""
    from_sources = {n: source_record(s, options.source_duration_s) for n, s in sources.items()}
    from_logs = {n: log_record(log, text) for n, (log, text) in logs.items()}
    records = {f"run {n}": run_record(run, n, options.settle_s, heli) for n, run in runs.items()}
    for case, use in uses.items():
        if "run" in use:
            lines = heli
        else:
            lines = (from_sources[use["source"]] if "source" in use else from_logs[use["flight_log"]]).lines_hz
        records[f"case {case}"] = case_record(cases, case, lines)
    records |= {f"source {n}": r for n, r in from_sources.items()}
    return records | {f"log {n}": r for n, r in from_logs.items()}
