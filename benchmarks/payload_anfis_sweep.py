"""The payload ANFIS's result swept over the choices it depends on: the two mount DOFs whose frequencies it reads
(``payload.anfis.dofs``), its reference's frequency resolution (``payload.anfis.freq_hz``) and the dampings its
reference may take (``payload.schedule.max_decay_time_s``, shared with the scheduled law).

    python benchmarks/payload_anfis_sweep.py [CONFIG ...] [--cases reports/excitation/cases.nc]

Reads the merged config files (default config/config.yaml) and the study's cases written by a run of `all`; for
each variant builds the payload table and the ANFIS's reference, trains the ANFIS with the ``anfis`` section's
options (`uavdamp.anfis.training.train`), and runs the gimbal on the six-axis isolator per input. Prints, as a
Markdown table, the checking regret (mean, max) on the reference, and per input the line-of-sight rms (µrad) under
the ANFIS (its mean C), under the scheduled law (its mean C) and at the best constant C (that C).
The numbers in docs/stages/payload.md come from it.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time

from payload_sweep import merged

from uavdamp import anfis, io
from uavdamp.camera.optics import CameraModel
from uavdamp.platform import PlatformParams
from uavdamp.reference_table.params import Axis
from uavdamp.settings import parse, view
from uavdamp.sources.stated import StatedSource
from uavdamp.study import payload, payload_anfis, payload_table

URAD = 1e6


def variants(section: payload.PayloadSection) -> dict[str, payload.PayloadSection]:
    """The config's section and one change of one choice each."""
    a, s = section.anfis, section.schedule
    out = {"baseline (config)": section}
    for dofs in (("x", "ry"), ("x", "rz"), ("ry", "rz")):
        out[f"dofs {' '.join(dofs)}"] = dataclasses.replace(section, anfis=dataclasses.replace(a, dofs=dofs))
    f = a.freq.array()
    coarser = Axis(start=f[0], stop=f[-1], num=(f.size + 1) // 2, spacing="log")
    out[f"reference frequencies {coarser.num}"] = dataclasses.replace(
        section, anfis=dataclasses.replace(a, freq=coarser)
    )
    out["max decay time none"] = dataclasses.replace(section, schedule=dataclasses.replace(s, max_decay_time=math.inf))
    return out


def _row(name: str, ds, record, took: float) -> list[str]:
    """The Markdown rows of one variant: its regret, then per input ANFIS, scheduled, best constant."""
    rows = []
    check = record.sel(model="anfis")
    regret = f"{float(check.check_regret_mean):.3f} / {float(check.check_regret_max):.2f}"
    for i in ds.input.values:
        cells = []
        for law in ("anfis", "scheduled"):
            run = ds.sel(input=i, law=law, mount="six_axis")
            cells.append(f"{float(run.law_los_std) * URAD:.0f} ({float(run.law_damping_mean):.2g})")
        best = float(ds.best_damping.sel(input=i, payload="gimbal", mount="six_axis"))
        los = float(ds.los_std.sel(input=i, payload="gimbal", mount="six_axis", damping=best)) * URAD
        cells.append(f"{los:.0f} ({best:g})")
        rows.append(f"| {name} | {regret} | {i} | " + " | ".join(cells) + f" | {took:.0f} |")
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("configs", nargs="*", default=["config/config.yaml"])
    parser.add_argument("--cases", default="reports/excitation/cases.nc")
    args = parser.parse_args()
    config = merged(args.configs)
    platform = parse(PlatformParams, view(config["platform"], PlatformParams), "platform")
    base = parse(payload.PayloadSection, config["payload"], "payload").with_camera(platform.structure)
    base = dataclasses.replace(
        base, payloads=("gimbal",), mounts=("six_axis",), mr=dataclasses.replace(base.mr, enabled=False)
    )
    options = parse(anfis.AnfisOptions, view(config["anfis"], anfis.AnfisOptions), "anfis")
    camera = parse(CameraModel, config["camera"], "camera")
    sources = {n: parse(StatedSource, config["sources"][n], f"sources.{n}") for n in base.sources}
    found = payload.inputs(io.open_dataset(args.cases), sources, base)
    head = [
        "variant",
        "checking regret mean / max",
        "input",
        "ANFIS (mean C)",
        "scheduled (mean C)",
        "best constant (C)",
    ]
    print("| " + " | ".join(head + ["s"]) + " |\n|" + "---|" * (len(head) + 1))
    for name, section in variants(base).items():
        start = time.perf_counter()
        table = payload_table.table_dataset(section)  # the variant's own
        reference, grid = payload_anfis.reference(table, section.anfis, section.schedule.max_decay_time)
        model, record, _ = anfis.train(reference, grid, options, n_jobs=2, inputs=section.anfis.inputs)
        ds = payload.compare_inputs(found, section, platform, camera, table, model)
        print("\n".join(_row(name, ds, record, time.perf_counter() - start)), flush=True)


if __name__ == "__main__":
    main()
