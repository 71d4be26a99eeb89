"""The payload stage's stated sources run longer than the study's 5 s: does the start-up transient of the six-axis
isolator's rocking modes set which damping wins?

    python benchmarks/payload_long_runs.py [CONFIG ...] [--duration 20] [--settle 10]

The gimbal on the six-axis isolator under each of ``payload.sources`` for `--duration` s, scored from `--settle` s
(the stage: 5 s from 1 s), at the constant damping candidates, under skyhook and under the scheduled law with the
config's payload table: line-of-sight rms and detrended rms (µrad) per input as a Markdown table, the 5 s run's
beside it, and the gimbal's rms on a still mount over the same window (its sensor-noise floor). The cases
of the study are 5 s long and cannot be run longer here.
"""

from __future__ import annotations

import argparse
import dataclasses

from payload_sweep import merged

from uavdamp.camera.optics import CameraModel
from uavdamp.platform import PlatformParams
from uavdamp.settings import parse, view
from uavdamp.sources.stated import StatedSource, motion
from uavdamp.study import payload, payload_table

URAD = 1e6


def row(section, platform, camera, table, name, source) -> list[str]:
    """The cells of one input, rms / detrended (µrad): each constant C, the best skyhook (by rms), the scheduled
    law (its mean C)."""
    t, moved, _ = motion(source, section.duration_s)
    ds = payload.compare_payloads(t, moved, section, platform, camera, table)
    own = ds.sel(payload="gimbal", mount="six_axis")
    cells = [
        f"{a * URAD:.0f} / {b * URAD:.0f}"
        for a, b in zip(own.los_std.values, own.los_detrended_std.values, strict=True)
    ]
    sky = [k for k, n in enumerate(ds.law.values) if str(n) != "scheduled"]
    k = min(sky, key=lambda j: float(ds.law_los_std.values[j]))
    rms, flat = float(ds.law_los_std.values[k]) * URAD, float(ds.law_los_detrended_std.values[k]) * URAD
    cells.append(f"{rms:.0f} / {flat:.0f} ({float(ds.law_c_on.values[k]):g})")
    s = ds.sel(law="scheduled")
    rms, flat = float(s.law_los_std) * URAD, float(s.law_los_detrended_std) * URAD
    cells.append(f"{rms:.0f} / {flat:.0f} ({float(s.law_damping_mean):.2g})")
    floor = float(ds.floor_los_std.sel(payload="gimbal")) * URAD
    return [*cells, f"{floor:.0f}"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("configs", nargs="*", default=["config/config.yaml"])
    parser.add_argument("--duration", type=float, default=20.0, help="s, of each run")
    parser.add_argument("--settle", type=float, default=10.0, help="s, the metrics from here")
    args = parser.parse_args()
    config = merged(args.configs)
    platform = parse(PlatformParams, view(config["platform"], PlatformParams), "platform")
    base = parse(payload.PayloadSection, config["payload"], "payload").with_camera(platform.structure)
    base = dataclasses.replace(base, payloads=("gimbal",), mounts=("six_axis",))
    camera = parse(CameraModel, config["camera"], "camera")
    table = payload_table.table_dataset(base)
    long = dataclasses.replace(base, duration_s=args.duration, settle_s=args.settle)
    head = ["input", "run", *[f"C {c:g}" for c in base.damping], "best skyhook (c_on)", "scheduled (mean C)"]
    head += ["still mount (rms)"]
    print("| " + " | ".join(head) + " |\n|" + "---|" * len(head))
    for name in base.sources:
        source = parse(StatedSource, config["sources"][name], f"sources.{name}")
        for label, section in ((f"{base.duration_s:g} s from {base.settle_s:g} s", base),
                               (f"{args.duration:g} s from {args.settle:g} s", long)):  # fmt: skip
            cells = row(section, platform, camera, table, name, source)
            print(f"| {name} | {label} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
