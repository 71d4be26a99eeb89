"""The payload stage on the results page: its table (each mount at its best constant C) and its findings (the
least line of sight per input against the gimbal makers' 175 µrad, the best skyhook run and the scheduled law)."""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd
import xarray as xr

from uavdamp.results.page import MISSING, Table, fmt, signed

ANCHOR_RAD = 175e-6  # ±0.01 deg: the angular vibration range gimbal makers quote


def payload_table(ds: xr.Dataset) -> Table:
    """Line-of-sight rms (µrad) per input and payload: rigid, and each isolator at its best constant C."""
    records = []
    for i, p in itertools.product(ds.input.values, ds.payload.values):
        record = {"input": str(i), "payload": str(p)}
        for m in ds.mount.values:
            los, best = ds.los_std.sel(input=i, payload=p, mount=m), ds.best_damping.sel(input=i, payload=p, mount=m)
            if m == "rigid":
                record["rigid (µrad)"] = fmt(float(los.max()) * 1e6, 3)
            else:
                c = float(best)
                value = MISSING if not np.isfinite(c) else f"{fmt(float(los.sel(damping=c)) * 1e6, 3)} ({fmt(c, 3)})"
                record[f"{m} (µrad, at C N s/m)"] = value
        records.append(record)
    note = (
        "Line-of-sight rms over the settled window; each isolator at its best constant C; lower is better; '-': not "
        f"modelled. Anchor: ±0.01° = {ANCHOR_RAD * 1e6:g} µrad."
    )
    return Table("Payloads and mounts", pd.DataFrame(records), note, 2)


def payload_findings(ds: xr.Dataset) -> list[str]:
    """Per input, the payload and mount of least line of sight (at its best constant C) against the 175 µrad
    anchor, and the best skyhook run and the scheduled law on each six-axis isolator against it
    (`_skyhook_finding`)."""
    out = []
    for i in ds.input.values:
        los = ds.los_std.sel(input=i)
        p, m, c = np.unravel_index(int(np.nanargmin(los.values)), los.shape)
        value = float(los.values[p, m, c])
        where = f"{ds.payload.values[p]} on the {ds.mount.values[m]} mount"
        damping = "" if ds.mount.values[m] == "rigid" else f" at C = {fmt(float(ds.damping.values[c]), 3)} N s/m"
        side = "within" if value <= ANCHOR_RAD else "above"
        text = (
            f"**{i}.** Least line of sight at a constant C: {where}{damping}, {fmt(value * 1e6, 3)} µrad rms "
            f"({side} 175 µrad)"
        )
        if "input_rotation_rms" in ds and float(ds.input_rotation_rms.sel(input=i)) == 0.0:
            text += "; this input does not rotate the mount, so a balanced camera sees none of it"
        out.append(text + "." + _skyhook_finding(ds, i) + _mr_finding(ds, i) + _detrended_finding(ds, i))
    return out


MOUNT_WORDS = {"six_axis": "the six-axis isolator", "wire_rope": "the wire-rope isolator"}


def _law_mounts(ds: xr.Dataset, name) -> list[str]:
    """The mounts the laws ran on for input `name` (finite ``law_los_std``), in the dataset's order."""
    if "law_los_std" not in ds:
        return []
    law = ds.law_los_std.sel(input=name)
    return [str(m) for m in ds.mount.values if np.isfinite(law.sel(mount=m).values).any()]


def _detrended_finding(ds: xr.Dataset, name) -> str:
    """The gimbal on the six-axis isolator without the slow drift (``los_detrended_std``, at its best constant C,
    and under skyhook where run) ('' without)."""
    if "los_detrended_std" not in ds or "six_axis" not in ds.mount.values or "gimbal" not in ds.payload.values:
        return ""
    runs = ds.los_detrended_std.sel(input=name, payload="gimbal", mount="six_axis")
    k = int(np.nanargmin(runs.values))
    text = (
        f" Without the slow drift (rms about a quadratic over the window), the gimbal on the six-axis isolator gives "
        f"{fmt(float(runs.values[k]) * 1e6, 3)} µrad at C = {fmt(float(ds.damping.values[k]), 3)} N s/m"
    )
    if "six_axis" in _law_mounts(ds, name) and "law_los_detrended_std" in ds:
        laws = ds.law_los_detrended_std.sel(input=name, mount="six_axis")
        text += f", {fmt(float(_skyhook(laws).min()) * 1e6, 3)} µrad under skyhook"
        if "scheduled" in ds.law.values:
            text += f", {fmt(float(laws.sel(law='scheduled')) * 1e6, 3)} µrad under the scheduled law"
    return text + "."


def _skyhook(law: xr.DataArray) -> xr.DataArray:
    """The ideal dampers' skyhook runs of a per-law variable (skyhook_C)."""
    return law.isel(law=[k for k, n in enumerate(law.law.values) if str(n).startswith("skyhook_")])


def _mr_finding(ds: xr.Dataset, name) -> str:
    """The MR damper's runs on the six-axis isolator against the gimbal's best constant C there ('' without)."""
    if "law_los_std" not in ds or "mr_off" not in ds.law.values or "six_axis" not in _law_mounts(ds, name):
        return ""
    laws = ds.law_los_std.sel(input=name, mount="six_axis")
    best = float(ds.los_std.sel(input=name, payload="gimbal", mount="six_axis").min())
    words = {"mr_off": "held at 0 V", "mr_on": "at 2.25 V", "mr_skyhook": "under skyhook", "mr_scheduled": "scheduled"}
    values = {n: float(laws.sel(law=n)) for n in words if n in ds.law.values}
    parts = [f"{words[n]} {fmt(v * 1e6, 3)} µrad ({signed(100 * (v / best - 1), 2)} %)" for n, v in values.items()]
    lo, hi = (float(ds.law_damping_mean.sel(input=name, law=n)) for n in ("mr_off", "mr_on"))
    return (
        f" An MR damper on each element (c_eq {fmt(lo, 2)}-{fmt(hi, 2)} N s/m at the reference stroke): "
        + ", ".join(parts)
        + ", against the best constant C."
    )


# the laws that plan C from the tracked lines: (their words, what the percentage is against)
PLANNED_LAWS = {
    "scheduled": (
        "The scheduled law there (C from the tracked lines through the payload table",
        " against the best constant C",
    ),
    "anfis": ("The payload ANFIS there (C from two DOFs' tracked frequencies", ""),
}


def _skyhook_finding(ds: xr.Dataset, name) -> str:
    """Per mount the laws ran on, the best skyhook run, the scheduled law and the payload ANFIS against the
    gimbal's best constant C on that mount ('' without)."""
    text = ""
    for mount in _law_mounts(ds, name):
        law = _skyhook(ds.law_los_std.sel(input=name, mount=mount))
        k = int(np.nanargmin(law.values))
        best = float(ds.los_std.sel(input=name, payload="gimbal", mount=mount).min())
        value, c_on = float(law.values[k]), float(_skyhook(ds.law_c_on.sel(input=name)).values[k])
        text += (
            f" Skyhook on {MOUNT_WORDS[mount]} (gimbal): {fmt(value * 1e6, 3)} µrad at c_on = {fmt(c_on, 3)} N s/m, "
            f"{signed(100 * (value / best - 1), 2)} % against its best constant C ({fmt(best * 1e6, 3)} µrad)."
        )
        for law, (words, tail) in PLANNED_LAWS.items():
            if law in ds.law.values:
                run = ds.sel(input=name, law=law, mount=mount)
                value, mean = float(run.law_los_std), float(run.law_damping_mean)
                text += (
                    f" {words}; mean {fmt(mean, 2)} N s/m): {fmt(value * 1e6, 3)} µrad, "
                    f"{signed(100 * (value / best - 1), 2)} %{tail}."
                )
    return text


def benchmark_payload_table(ds: xr.Dataset) -> Table:
    """The benchmark on the payload: per mount and controller, its tuned setting, mean / worst J over the
    evaluation set and the criterion's evaluation mean (µrad for an angle)."""
    criterion = ds.attrs["criterion"]
    angle = ds[criterion].attrs.get("units") == "rad"
    records = []
    for m, c in itertools.product(ds.mount.values, ds.controller.values):
        at = {"mount": m, "controller": c}
        mean, worst = (float(ds[v].sel(at)) for v in ("J_mean", "J_worst"))
        value = float(ds[f"{criterion}_mean"].sel(at)) * (1e6 if angle else 1.0)
        setting = {"passive_tuned": "tuned_damping", "skyhook_tuned": "tuned_c_on"}.get(str(c))
        records.append(
            {
                "mount": str(m),
                "controller": str(c),
                "tuned (N s/m)": fmt(float(ds[setting].sel(mount=m)), 3) if setting else MISSING,
                "J mean / worst": MISSING if not np.isfinite(mean) else f"{fmt(mean, 3)} / {fmt(worst, 3)}",
                f"{criterion} ({'µrad' if angle else ds[criterion].attrs['units']})": fmt(value, 3),
            }
        )
    n = int((ds.set == "evaluation").sum())
    note = (
        f"The gimbal on each isolator over {n} evaluation scenarios: J = {criterion} over the rigid mount's on the "
        "same scenario (lower is better); the constant C and skyhook's c_on tuned on the tuning scenarios only; "
        "passive_oracle: each scenario's own best constant C (a bound)."
    )
    return Table("Controller benchmark on the payload", pd.DataFrame(records), note, 2)


def benchmark_payload_finding(ds: xr.Dataset) -> str:
    """Per mount, the controller of least mean J over the evaluation set against the tuned constant C and the
    per-scenario best constant C."""
    parts = []
    for m in ds.mount.values:
        mean = ds.J_mean.sel(mount=m)
        real = mean.drop_sel(controller=["rigid", "passive_oracle"])
        best = str(real.controller.values[int(np.nanargmin(real.values))])
        values = {c: float(mean.sel(controller=c)) for c in (best, "passive_tuned", "passive_oracle")}
        oracle = f"{fmt(values['passive_oracle'], 3)} for each scenario's own best constant C"
        where = f"on {MOUNT_WORDS.get(str(m), str(m))} the least mean J over the evaluation set is"
        if best == "passive_tuned":
            parts.append(f"{where} the tuned constant C's, {fmt(values[best], 3)}: no law beats it ({oracle})")
        else:
            parts.append(
                f"{where} {best}'s, {fmt(values[best], 3)}, against {fmt(values['passive_tuned'], 3)} for the "
                f"tuned constant C and {oracle}"
            )
    return (
        f"**Controller benchmark on the payload** ({ds.attrs['criterion']}, J = 1: rigid mount): "
        + "; ".join(parts)
        + "."
    )
