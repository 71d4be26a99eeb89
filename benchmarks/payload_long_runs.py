"""The payload stage's inputs run longer than the study's 5 s: does the start-up transient of the six-axis
isolator's rocking modes set which damping wins?

    python benchmarks/payload_long_runs.py [CONFIG ...] [--duration 20] [--settle 10] [--runs DIR] [--mount M]
                                           [--input NAME ...]

The gimbal on the six-axis isolator under each study case (rebuilt over `--duration` s from the helicopter runs in
DIR, default reports/helicopter/runs of a run of `all`, as the excitation stage builds it) and each of
``payload.sources``, for `--duration` s scored from `--settle` s (the stage: 5 s from 1 s), at the constant damping
candidates, under skyhook, under the scheduled law with the config's payload table and under the payload ANFIS
(`--anfis`, default reports/payload/anfis_model.nc of a run of `all`): line-of-sight rms and
detrended rms (µrad) per input as a Markdown table, the 5 s run's beside it, and the gimbal's rms on a still mount
over the same window (its sensor-noise floor); on the six-axis isolator also the MR damper's four runs
(`uavdamp.study.payload_mr`). `--mount wire_rope` prints the constant C and the laws on the
wire-rope isolator instead. A case rebuilt over the longer record is scaled on it
(its dominant line read over the whole record): its scale per axis is printed beside the stage's 5 s case's
(`--cases`).
"""

from __future__ import annotations

import argparse
import dataclasses

from payload_sweep import merged

from uavdamp import io
from uavdamp.anfis.damping import DampingModel
from uavdamp.camera.optics import CameraModel
from uavdamp.platform import PlatformParams
from uavdamp.settings import parse, view
from uavdamp.sources import excitation
from uavdamp.sources.excitation import case_motion
from uavdamp.sources.stated import StatedSource, motion
from uavdamp.study import payload, payload_table
from uavdamp.study.payload_mr import MR_LAWS

URAD = 1e6


def cases(config: dict, duration: float, runs_dir: str):
    """The study's helicopter cases over `duration` s, as the excitation stage builds them (no log or source case)."""
    study = config["study"]
    keys = ("cases", "duration_s", "highpass_hz", "tracking")
    options = parse(excitation.ExcitationOptions, {k: study[k] for k in keys} | {"duration_s": duration}, "study")
    names = {c.run for c in options.cases.values() if c.run}
    runs = {name: io.open_dataset(f"{runs_dir}/{name}.nc") for name in names}
    return excitation.cases_dataset(runs, options, {}, {})


def row(section, platform, camera, table, t, moved, mount: str = "six_axis", model=None) -> list[str]:
    """The cells of one input, rms / detrended (µrad): each constant C, the best skyhook (by rms), the scheduled
    law and the payload ANFIS `model` (their mean C), all on `mount`."""
    ds = payload.compare_payloads(t, moved, section, platform, camera, table, model).sel(mount=mount)
    own = ds.sel(payload="gimbal")
    cells = [
        f"{a * URAD:.0f} / {b * URAD:.0f}"
        for a, b in zip(own.los_std.values, own.los_detrended_std.values, strict=True)
    ]
    sky = [k for k, n in enumerate(ds.law.values) if str(n).startswith("skyhook_")]
    k = min(sky, key=lambda j: float(ds.law_los_std.values[j]))
    rms, flat = float(ds.law_los_std.values[k]) * URAD, float(ds.law_los_detrended_std.values[k]) * URAD
    cells.append(f"{rms:.0f} / {flat:.0f} ({float(ds.law_c_on.values[k]):g})")
    for law in ("scheduled", "anfis"):
        s = ds.sel(law=law)
        rms, flat = float(s.law_los_std) * URAD, float(s.law_los_detrended_std) * URAD
        cells.append(f"{rms:.0f} / {flat:.0f} ({float(s.law_damping_mean):.2g})")
    for name in MR_LAWS if "mr_off" in ds.law.values and mount == "six_axis" else ():
        mr = ds.sel(law=name)
        cells.append(f"{float(mr.law_los_std) * URAD:.0f} / {float(mr.law_los_detrended_std) * URAD:.0f}")
    floor = float(ds.floor_los_std.sel(payload="gimbal")) * URAD
    return [*cells, f"{floor:.0f}"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("configs", nargs="*", default=["config/config.yaml"])
    parser.add_argument("--duration", type=float, default=20.0, help="s, of each run")
    parser.add_argument("--settle", type=float, default=10.0, help="s, the metrics from here")
    parser.add_argument("--runs", default="reports/helicopter/runs", help="the helicopter runs of a run of all")
    parser.add_argument("--cases", default="reports/excitation/cases.nc", help="the stage's own 5 s cases")
    parser.add_argument("--mount", default="six_axis", choices=["six_axis", "wire_rope"], help="the constant C's")
    parser.add_argument("--input", action="append", default=[], help="only this input (repeatable; default all)")
    parser.add_argument("--anfis", default="reports/payload/anfis_model.nc", help="the payload ANFIS of a run")
    args = parser.parse_args()
    model = DampingModel.from_dataset(io.open_dataset(args.anfis))
    config = merged(args.configs)
    platform = parse(PlatformParams, view(config["platform"], PlatformParams), "platform")
    base = parse(payload.PayloadSection, config["payload"], "payload").with_camera(platform.structure)
    mounts = ("six_axis",) if args.mount == "six_axis" else ("six_axis", args.mount)
    base = dataclasses.replace(base, payloads=("gimbal",), mounts=mounts)
    camera = parse(CameraModel, config["camera"], "camera")
    table = payload_table.table_dataset(base)
    long = dataclasses.replace(base, duration_s=args.duration, settle_s=args.settle)
    head = ["input", "run", *[f"{args.mount} C {c:g}" for c in base.damping], "best skyhook (c_on)"]
    head += ["scheduled (mean C)", "ANFIS (mean C)"]
    head += [f"MR {n[3:]}" for n in MR_LAWS] if base.mr.enabled and args.mount == "six_axis" else []
    head += ["still mount (rms)"]
    print("| " + " | ".join(head) + " |\n|" + "---|" * len(head))
    runs = [
        (f"{base.duration_s:g} s from {base.settle_s:g} s", base),
        (f"{args.duration:g} s from {args.settle:g} s", long),
    ]
    found, short = cases(config, args.duration, args.runs), io.open_dataset(args.cases)
    names = [str(c) for c in found.case.values] + list(base.sources)
    for name in [n for n in names if not args.input or n in args.input]:
        for label, section in runs:
            if name in found.case.values:  # the stage's case for its own window, the rebuilt one for the long
                own = short if section is base else found
                t, moved = own.time.values, case_motion(own, name)
                scale = ", ".join(f"{v:.3g}" for v in own.scale.sel(case=name).values)
                label = f"{label} (scale y, z: {scale})"
            else:
                source = parse(StatedSource, config["sources"][name], f"sources.{name}")
                t, moved, _ = motion(source, section.duration_s)
            cells = row(section, platform, camera, table, t, moved, args.mount, model)
            print(f"| {name} | {label} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
