"""The controller benchmark on the payload: the gyro-stabilised gimbal (``payload.gimbal``) on the six-axis isolators
(``payload.six_axis``, ``payload.wire_rope``) under the benchmark's scenarios, the payload stage's laws tuned on the
tuning set and scored on the evaluation set.

The scenarios are the benchmark's (``benchmark.helicopter``, ``synthetic``, ``sources``: the paper's amplitudes) and
the stated sources ``benchmark.payload.sources`` names (flyable levels), the latter split apart by the same seeded
rule (`split`). Each runs `uavdamp.study.payload.compare_inputs` with the payload section the config names, narrowed
to the gimbal on the rigid mount and ``benchmark.payload.mounts`` (`benchmark_section`), over
``benchmark.duration_s``. The controllers (`controllers`), per mount:

- ``rigid``: the gimbal on a rigid mount (J = 1 by definition);
- ``passive_tuned``: the constant C of ``payload.damping_n_s_m`` whose mean J over the tuning set is least;
- ``passive_oracle``: each scenario's own best candidate C, a bound and not a controller (it knows the scenario);
- ``skyhook_tuned``: on-off skyhook (`uavdamp.study.payload_laws`) with the c_on of least tuning-set mean J;
- ``scheduled`` and ``anfis``: C from the tracked lines through the payload table and the payload ANFIS, untuned
  (the table and the model are fixed before the benchmark);
- ``mr_off``, ``mr_on``, ``mr_skyhook``, ``mr_scheduled``: the MR damper's runs (``payload.mr``; six_axis only).

J of a run is its criterion (``benchmark.payload.criterion``, a metric of `uavdamp.study.payload_runs.METRICS`
where lower is better) over the rigid mount's on the same scenario; a tie in the tuning goes to the lesser C.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from uavdamp.benchmark import scenarios
from uavdamp.camera.optics import CameraModel
from uavdamp.contract import MountMotion
from uavdamp.platform import PlatformParams
from uavdamp.settings import require, setting
from uavdamp.study.payload import PayloadInput, PayloadSection, compare_inputs
from uavdamp.study.payload_runs import METRICS, SIX_AXIS_MOUNTS, metric_attrs

# the camera's metrics of `METRICS` where lower is better and the rigid mount's is not 0 (skew_px is, on a global
# shutter; blur_p95 below the sharp threshold)
CRITERIA = (
    "los_std",
    "los_detrended_std",
    "los_roll_rms",
    "los_peak_to_peak",
    "jitter_within_exposure",
    "drift_frame_to_frame",
)


@dataclass(frozen=True)
class PayloadBenchmark:
    """The config section ``benchmark.payload`` (module docstring)."""

    enabled: bool = setting(default=True)  # false: the benchmark runs on the paper's head alone
    mounts: tuple[str, ...] = setting(default=("six_axis",))  # of SIX_AXIS_MOUNTS
    criterion: str = setting(default="los_std")  # of CRITERIA: tuned and ranked
    sources: tuple[str, ...] = setting(default=())  # stated sources run as scenarios of this benchmark alone

    def validate(self) -> None:
        w = "benchmark.payload."
        ok = 0 < len(self.mounts) == len(set(self.mounts)) and set(self.mounts) <= set(SIX_AXIS_MOUNTS)
        require(ok, w + "mounts", f"must be distinct names of {list(SIX_AXIS_MOUNTS)}, got {list(self.mounts)}")
        require(self.criterion in CRITERIA, w + "criterion", f"must be one of {list(CRITERIA)}, got {self.criterion!r}")
        require(len(set(self.sources)) == len(self.sources), w + "sources", "names must be unique")


def split(base: dict[str, str], sources, tuning_fraction: float, seed: int) -> dict[str, str]:
    """The benchmark's split of its scenarios (`base`, {name: set}) with the stated sources `sources` split apart by
    the same seeded rule (`uavdamp.benchmark.scenarios.split`), so that the scenarios keep their sets; a single
    source is evaluated."""
    names = sorted(sources)
    taken = sorted(set(names) & set(base))
    if taken:
        raise ValueError(f"benchmark.payload.sources: {taken} are names of the benchmark's scenarios")
    if len(names) < 2:
        return base | dict.fromkeys(names, "evaluation")
    return base | scenarios.split(names, tuning_fraction, seed)


def benchmark_section(section: PayloadSection, bench: PayloadBenchmark, duration_s: float) -> PayloadSection:
    """The payload section the benchmark runs: the gimbal alone, on the rigid mount and `bench.mounts`, over
    `duration_s` (s), no stated source, one worker."""
    mounts = ("rigid", *bench.mounts)
    return dataclasses.replace(
        section, payloads=("gimbal",), mounts=mounts, duration_s=duration_s, sources=(), threads=1
    )


def run_scenario(
    name: str,
    description: str,
    time: np.ndarray,
    mount: MountMotion,
    section: PayloadSection,
    platform: PlatformParams,
    camera: CameraModel,
    table: xr.Dataset,
    model,
) -> xr.Dataset:
    """The payload comparison of one scenario (time s, mount motion) with the section of `benchmark_section`, the
    payload table `table` and the payload ANFIS `model`: `compare_inputs`' dataset, over ``input`` = [name]."""
    return compare_inputs([PayloadInput(name, description, time, mount)], section, platform, camera, table, model)


def _stack(runs: list[xr.Dataset], split: dict[str, str]) -> xr.Dataset:
    """The scenario runs over ``scenario`` (the gimbal's values; the rigid mount kept apart), with their set."""
    ds = xr.concat(runs, dim="input", data_vars="all", coords="minimal", compat="override", join="exact")
    ds = ds.sel(payload="gimbal", drop=True).rename(input="scenario")
    names = [str(s) for s in ds.scenario.values]
    missing = sorted(set(names) - set(split))
    if missing:
        raise ValueError(f"benchmark.payload: scenarios {missing} are in no set of the split")
    sets = (
        "scenario",
        [split[n] for n in names],
        {"units": "1", "long_name": "set of the scenario: tuning or evaluation"},
    )
    return ds.assign_coords(scenario=("scenario", names, {"units": "1", "long_name": "scenario"}), set=sets)


def _tuned(j: xr.DataArray, over: str, tuning: xr.DataArray) -> xr.DataArray:
    """(mount) the `over` coordinate's value of least mean J over the tuning scenarios (the first of a tie; NaN
    where no value has a finite mean)."""
    mean = j.where(tuning).mean("scenario", skipna=True).transpose("mount", over).values
    out = np.full(mean.shape[0], math.nan, dtype=object)
    for m, row in enumerate(mean):
        if np.isfinite(row).any():
            out[m] = j[over].values[int(np.nanargmin(row))]
    return xr.DataArray(out, dims="mount", coords={"mount": j.mount})


def controllers(ds: xr.Dataset) -> list[str]:
    """The controllers of a stacked run (module docstring), in order."""
    laws = [str(n) for n in ds.law.values] if "law" in ds.dims else []
    skyhook = ["skyhook_tuned"] if any(n.startswith("skyhook_") for n in laws) else []
    return ["rigid", "passive_tuned", "passive_oracle", *skyhook, *(n for n in laws if not n.startswith("skyhook_"))]


def _pick(values: xr.DataArray, over: str, choice: xr.DataArray) -> xr.DataArray:
    """(scenario, mount) `values` at each mount's `choice` of the `over` coordinate (NaN where the choice is NaN:
    no tuned value)."""
    columns = []
    for m in values.mount.values:
        c = choice.sel(mount=m).item()
        found = isinstance(c, str) or (c is not None and math.isfinite(c))
        column = values.sel(mount=m).sel({over: c}) if found else values.sel(mount=m).isel({over: 0}) * math.nan
        columns.append(column.drop_vars(over))
    return xr.concat(columns, "mount")


def _columns(ds: xr.Dataset, names: list[str], criterion: str) -> tuple[dict, xr.DataArray, xr.DataArray | None]:
    """({metric: (scenario, mount, controller)} of every controller, the tuned C and c_on per mount (None: no
    skyhook run)); `ds` the stacked runs."""
    mounts = [str(m) for m in ds.mount.values if m != "rigid"]
    rigid = {m: ds[m].sel(mount="rigid").isel(damping=0, drop=True) for m in METRICS}
    on = ds.sel(mount=mounts)
    tuning = ds.set == "tuning"
    c_tuned = _tuned(on[criterion] / rigid[criterion], "damping", tuning).astype(float)
    oracle = on[criterion].fillna(np.inf).argmin("damping")
    skyhook = [str(n) for n in ds.law.values if str(n).startswith("skyhook_")] if "skyhook_tuned" in names else []
    on_tuned = _tuned(on[f"law_{criterion}"].sel(law=skyhook) / rigid[criterion], "law", tuning) if skyhook else None
    out = {}
    for metric in METRICS:
        picks = {
            "rigid": rigid[metric].expand_dims(mount=mounts),
            "passive_tuned": _pick(on[metric], "damping", c_tuned),
            "passive_oracle": on[metric].isel(damping=oracle).drop_vars("damping"),
        }
        if on_tuned is not None:
            picks["skyhook_tuned"] = _pick(on[f"law_{metric}"], "law", on_tuned)
        columns = [picks[n] if n in picks else on[f"law_{metric}"].sel(law=n, drop=True) for n in names]
        out[metric] = xr.concat(columns, "controller").transpose("scenario", "mount", "controller")
    return out, c_tuned, on_tuned


def gather(runs: list[xr.Dataset], split: dict[str, str], criterion: str) -> xr.Dataset:
    """Every metric of `METRICS` per (scenario, mount, controller), J of `criterion`, its mean and worst over the
    evaluation set, the tuned C and c_on per mount and the set of each scenario (module docstring)."""
    ds = _stack(runs, split)
    names = controllers(ds)
    values, c_tuned, on_tuned = _columns(ds, names, criterion)
    mounts = [str(m) for m in ds.mount.values if m != "rigid"]
    out = xr.Dataset(coords={"scenario": ds.scenario, "set": ds.set, "mount": mounts, "controller": names})
    for metric, value in values.items():
        out[metric] = value.assign_attrs(metric_attrs(metric))
    if "input_description" in ds:
        out["scenario_description"] = ds.input_description.assign_attrs(units="1", long_name="the scenario")
    return _scored(out, ds, criterion, c_tuned, on_tuned)


def _scored(out: xr.Dataset, ds: xr.Dataset, criterion: str, c_tuned, on_tuned) -> xr.Dataset:
    """`gather`'s dataset with J, its evaluation mean and worst, the tuned settings and the attributes."""
    j = out[criterion] / out[criterion].sel(controller="rigid")
    out["J"] = j.assign_attrs(units="1", long_name=f"{criterion} over the rigid mount's on the same scenario")
    evaluation = out.set == "evaluation"
    out["J_mean"] = j.where(evaluation).mean("scenario").assign_attrs(units="1", long_name="mean J, evaluation set")
    out["J_worst"] = j.where(evaluation).max("scenario").assign_attrs(units="1", long_name="worst J, evaluation set")
    out["J_tuning_mean"] = j.where(~evaluation).mean("scenario").assign_attrs(units="1", long_name="mean J, tuning set")
    crit = out[criterion].where(evaluation).mean("scenario")
    out[f"{criterion}_mean"] = crit.assign_attrs(
        metric_attrs(criterion) | {"long_name": f"mean {criterion}, evaluation set"}
    )
    out["tuned_damping"] = c_tuned.assign_attrs(units="N s m-1", long_name="passive_tuned's constant C")
    c_on = (
        [float(str(v).removeprefix("skyhook_")) if isinstance(v, str) else math.nan for v in on_tuned.values]
        if on_tuned is not None
        else [math.nan] * out.sizes["mount"]
    )
    out["tuned_c_on"] = ("mount", c_on, {"units": "N s m-1", "long_name": "skyhook_tuned's c_on"})
    out["floor_los_std"] = ((), float(ds.floor_los_std.isel(scenario=0)), dict(ds.floor_los_std.attrs))
    out["mount"].attrs = {"units": "1", "long_name": "the gimbal's isolator"}
    out["controller"].attrs = {
        "units": "1",
        "long_name": "damping law (benchmark.payload: src/uavdamp/benchmark/payload.py)",
    }
    out.attrs = {
        "title": "Controller benchmark on the payload: the gimbal on six-axis isolators",
        "criterion": criterion,
        "coupling": ds.attrs.get("coupling", ""),
        "duration_s": ds.attrs.get("duration_s", math.nan),
        "settle_s": ds.attrs.get("settle_s", math.nan),
    }
    return out


def _setting(ds: xr.Dataset, mount: str, name: str) -> str:
    """The tuned setting of a controller on `mount`, as text."""
    if name == "passive_tuned":
        return f"C = {float(ds.tuned_damping.sel(mount=mount)):g} N s/m"
    if name == "skyhook_tuned":
        return f"c_on = {float(ds.tuned_c_on.sel(mount=mount)):g} N s/m"
    return "best C per scenario" if name == "passive_oracle" else ""


def markdown_table(ds: xr.Dataset) -> str:
    """Per mount, a Markdown table of every controller: its tuned setting, mean and worst J over the evaluation set,
    mean J over the tuning set, the criterion's evaluation mean (µrad where it is an angle) and the mean jitter MTF
    at the pixel Nyquist."""
    criterion = ds.attrs["criterion"]
    scale, unit = (1e6, "µrad") if ds[criterion].attrs.get("units") == "rad" else (1.0, ds[criterion].attrs["units"])
    n = int((ds.set == "evaluation").sum())
    lines = []
    for mount in ds.mount.values:
        lines += [
            f"**{mount}**: J = {criterion} over the rigid mount's, {n} evaluation scenarios (lower is better)",
            "",
            f"| controller | setting | mean J | worst J | tuning mean J | mean {criterion} ({unit}) | mean MTF |",
            "|---|---|---:|---:|---:|---:|---:|",
        ]
        for name in ds.controller.values:
            at = {"mount": mount, "controller": name}
            mean, worst, tuning = (float(ds[v].sel(at)) for v in ("J_mean", "J_worst", "J_tuning_mean"))
            evaluation = ds.set == "evaluation"
            value = float(ds[f"{criterion}_mean"].sel(at)) * scale
            mtf = float(ds.mtf_nyquist.sel(at).where(evaluation).mean("scenario"))
            cells = [f"{x:.3g}" if math.isfinite(x) else "-" for x in (mean, worst, tuning, value, mtf)]
            lines.append(f"| {name} | {_setting(ds, str(mount), str(name))} | " + " | ".join(cells) + " |")
        lines.append("")
    floor = float(ds.floor_los_std) * 1e6
    lines.append(f"The gimbal on a still mount (its sensor floor): line of sight {floor:.3g} µrad rms.")
    return "\n".join(lines) + "\n"
