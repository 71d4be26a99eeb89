"""The payload stage's headline swept over the choices it depends on: the gimbal's estimator crossover, its
accelerometer range, its rate-loop crossover, its gyro's bias, a camera imbalance, the six-axis isolator's
stiffness (its modes), the wire-rope elements' hysteresis (alpha, yield stroke, axes, exponent), the camera's and
the isolated plate's masses, the skyhook runs' off damping and lag, and the scheduled law's eligible damping (the
slowest decay time it allows).

    python benchmarks/payload_sweep.py [CONFIG ...] [--cases reports/excitation/cases.nc] [--only TEXT ...]

Reads the merged config files (default config/config.yaml) and the study's cases written by a run of `all`; for
each variant prints the gimbal's line-of-sight rms (µrad) per input on the rigid mount and on each isolator at its
best constant damping (and that C), and on each six-axis isolator (rubber-ball, wire rope) under on-off skyhook at
its best c_on and under the scheduled law (its mean C over the settled window) with the variant's own payload
table, as a Markdown table.
The numbers in docs/stages/payload.md come from it.
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np
import yaml

from uavdamp import io
from uavdamp.camera.optics import CameraModel
from uavdamp.platform import PlatformParams
from uavdamp.settings import parse, view
from uavdamp.sources.stated import StatedSource
from uavdamp.study import payload, payload_table

URAD = 1e6


def merged(paths: list[str]) -> dict:
    """The config files merged as Snakemake merges them (later files override, section by section)."""
    config: dict = {}
    for path in paths:
        _merge(config, yaml.safe_load(open(path)))
    return config


def _merge(base: dict, over: dict) -> None:
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(base.get(key), dict):
            _merge(base[key], value)
        else:
            base[key] = value


def variants(section: payload.PayloadSection, done: bool = False) -> dict[str, payload.PayloadSection]:
    """The baseline and one change of one choice each (`done`: the baseline and the later half only)."""
    g, six = section.gimbal, section.six_axis
    out = {"baseline (config)": section}

    def gimbal(**change):
        return dataclasses.replace(section, gimbal=dataclasses.replace(g, **change))

    if done:  # the variants measured already (their rows are in docs/stages/payload.md)
        return {k: v for k, v in out.items() if k == "baseline (config)"} | _rest(section, g, six, gimbal)
    out["estimator crossover 0 Hz (gyro alone)"] = gimbal(estimator_crossover_hz=0.0)
    out["estimator crossover 0.16 Hz (1 s)"] = gimbal(estimator_crossover_hz=1 / (2 * np.pi))
    out["accelerometer range 16 g"] = gimbal(accel_range_g=16.0)
    out["rate crossover 20 Hz"] = gimbal(rate_crossover_hz=(20.0, 20.0, 20.0))
    return out | _rest(section, g, six, gimbal)


def _rest(section, g, six, gimbal) -> dict[str, payload.PayloadSection]:
    out = {}
    out["rate crossover 50 Hz (60 Hz with 50 deg cannot be designed at 1 kHz)"] = gimbal(
        rate_crossover_hz=(50.0, 50.0, 50.0)
    )
    out["camera 2 mm above the axes"] = gimbal(imbalance_m=(0.0, 0.0, 0.002))
    stiff = tuple(k * 4 for k in six.stiffness)
    soft = tuple(k / 4 for k in six.stiffness)
    out["six-axis stiffness x 4 (modes x 2)"] = dataclasses.replace(
        section, six_axis=dataclasses.replace(six, stiffness=stiff)
    )
    out["six-axis stiffness / 4 (modes / 2)"] = dataclasses.replace(
        section, six_axis=dataclasses.replace(six, stiffness=soft)
    )
    for deg_s in (0.005, 0.01, 0.1):  # the gyro's residual bias after power-up calibration, every axis (choice: 0)
        out[f"gyro bias {deg_s:g} deg/s"] = gimbal(gyro_bias=(np.radians(deg_s),) * 3)
    for c_off in (0.3, 3.0):  # the skyhook runs' off damping (choice: the least candidate, 1 N s/m)
        out[f"skyhook c_off {c_off:g} N s/m"] = dataclasses.replace(section, skyhook_c_off=c_off)
    for limit in (1.0, 2.5, float("inf")):  # the scheduled law's eligible C (choice: decay within the 0.5 s update)
        chosen = dataclasses.replace(section.schedule, max_decay_time=limit)
        out[f"scheduled max decay time {limit:g} s"] = dataclasses.replace(section, schedule=chosen)
    for c in (3.0, 30.0):  # the scheduled law's C before its first estimate (choice: 10 N s/m)
        chosen = dataclasses.replace(section.schedule, initial_damping=c)
        out[f"scheduled initial C {c:g} N s/m"] = dataclasses.replace(section, schedule=chosen)
    for lag in (0.01, 0.03):  # the skyhook runs' damper: an MR damper's response time is 10-30 ms (assumption)
        out[f"skyhook damper lag {lag * 1e3:g} ms"] = dataclasses.replace(section, skyhook_lag=lag)
    wire = section.wire_rope
    for alpha in (0.2, 0.8):  # the wire rope's post-yield over initial stiffness (choice: 0.5)
        out[f"wire rope alpha {alpha:g}"] = dataclasses.replace(
            section, wire_rope=dataclasses.replace(wire, alpha=alpha)
        )
    for stroke in (1e-4, 1e-2):  # its yield stroke z_max (choice: 1 mm)
        chosen = dataclasses.replace(wire, yield_stroke=stroke)
        out[f"wire rope yield stroke {stroke * 1e3:g} mm"] = dataclasses.replace(section, wire_rope=chosen)
    chosen = dataclasses.replace(wire, axes=("x", "y", "z"))  # hysteretic vertically too (choice: lateral only)
    out["wire rope hysteretic along x, y and z"] = dataclasses.replace(section, wire_rope=chosen)
    out["wire rope exponent 2 (a sharper loop)"] = dataclasses.replace(
        section, wire_rope=dataclasses.replace(wire, exponent=2.0)
    )
    for factor, label in ((0.5, "/ 2"), (2.0, "x 2")):  # the masses: choices (the gains are designed for each)
        out[f"camera mass {label} ({g.camera_mass * factor:g} kg)"] = gimbal(camera_mass=g.camera_mass * factor)
        plate = dataclasses.replace(six, plate_mass=six.plate_mass * factor)
        out[f"plate mass {label} ({six.plate_mass * factor:g} kg)"] = dataclasses.replace(section, six_axis=plate)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("configs", nargs="*", default=["config/config.yaml"])
    parser.add_argument("--cases", default="reports/excitation/cases.nc")
    parser.add_argument("--rest", action="store_true", help="the baseline and the later half of the variants only")
    parser.add_argument("--only", action="append", default=[], help="the baseline and the variants naming this")
    args = parser.parse_args()
    config = merged(args.configs)
    platform = parse(PlatformParams, view(config["platform"], PlatformParams), "platform")
    base = parse(payload.PayloadSection, config["payload"], "payload").with_camera(platform.structure)
    base = dataclasses.replace(base, payloads=("gimbal",))
    camera = parse(CameraModel, config["camera"], "camera")
    sources = {n: parse(StatedSource, config["sources"][n], f"sources.{n}") for n in base.sources}
    cases = io.open_dataset(args.cases)
    found = payload.inputs(cases, sources, base)
    mounts = [m for m in base.mounts if m != "rigid"]
    law_mounts = [m for m in mounts if m in payload.SIX_AXIS_MOUNTS]
    head = ["variant", "input", "rigid", *[f"{m} (best C)" for m in mounts]]
    head += [f"{m} {law}" for m in law_mounts for law in ("skyhook (best c_on)", "scheduled (mean C)")] + ["s"]
    print("| " + " | ".join(head) + " |\n|" + "---|" * len(head))
    chosen = variants(base, args.rest)
    if args.only:
        chosen = {k: v for k, v in chosen.items() if k.startswith("baseline") or any(o in k for o in args.only)}
    for name, section in chosen.items():
        start = time.perf_counter()
        table = payload_table.table_dataset(section)  # the variant's own: the scheduled law reads it
        ds = payload.compare_inputs(found, section, platform, camera, table)
        took = time.perf_counter() - start
        for i in ds.input.values:
            los = ds.los_std.sel(input=i, payload="gimbal") * URAD
            cells = [f"{float(los.sel(mount='rigid').isel(damping=0)):.0f}"] if "rigid" in base.mounts else []
            for m in mounts:
                best = float(ds.best_damping.sel(input=i, payload="gimbal", mount=m))
                cells.append(f"{float(los.sel(mount=m, damping=best)):.0f} ({best:g})")
            for m in law_mounts if "law_los_std" in ds else ():
                sky = ds.law.str.startswith("skyhook_").values
                law = ds.law_los_std.sel(input=i, mount=m).values[sky] * URAD
                c_on = ds.law_c_on.sel(input=i).values[sky]
                best = int(np.argmin(law))
                cells.append(f"{law[best]:.0f} ({c_on[best]:g})")
                scheduled = ds.sel(input=i, law="scheduled", mount=m)
                cells.append(f"{float(scheduled.law_los_std) * URAD:.0f} ({float(scheduled.law_damping_mean):.2g})")
            print(f"| {name} | {i} | " + " | ".join(cells) + f" | {took:.0f} |")


if __name__ == "__main__":
    main()
