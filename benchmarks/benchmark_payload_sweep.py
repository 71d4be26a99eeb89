"""The controller benchmark on the payload swept over the choices its ranking depends on: the criterion
(``benchmark.payload.criterion``), the group of scenarios it is read on, the split's seed (``benchmark.split.seed``),
the gimbal's attitude estimator (``payload.gimbal.estimator_crossover_hz``), skyhook's off damping
(``payload.skyhook_c_off_n_s_m``) and its damper's lag (``payload.skyhook_lag_s``).

    python benchmarks/benchmark_payload_sweep.py [RUN_DIR] [--configs config/config.yaml ...] [--seeds 1 2 ...]
                                                 [--estimator-hz 0.159 ...] [--c-off 0.3 3 ...] [--lag-s 0.01 ...]

Reads the runs a `snakemake -j2 benchmark` wrote (RUN_DIR/benchmark/payload/runs/*.nc, default reports) and gathers
them again (`uavdamp.benchmark.payload.gather`, the split of the config) for every criterion of
`uavdamp.benchmark.payload.CRITERIA`; then per group (the helicopter flights, the synthetic inputs at the paper's
amplitude, the stated sources at flyable levels) the mean J over its evaluation scenarios. With --seeds, gathers the
same runs on the split of each seed (line of sight alone). With --estimator-hz, --c-off or --lag-s, runs every
scenario again with that value (the config's others; joblib over 2 workers: about 1.5 min each on 2 cores) and
prints the same.
Prints Markdown tables of the mean J over the evaluation set per controller and the tuned settings; the numbers in
docs/stages/benchmark.md come from it.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np
from payload_sweep import merged

from uavdamp import io, parallel
from uavdamp.anfis.damping import DampingModel
from uavdamp.benchmark import payload as bench
from uavdamp.benchmark import scenarios
from uavdamp.benchmark.runner import case_of
from uavdamp.camera.optics import CameraModel
from uavdamp.config.load import load
from uavdamp.platform import PlatformParams
from uavdamp.settings import parse, view
from uavdamp.sources.stated import StatedSource, motion
from uavdamp.study.payload import PayloadSection


def group_of(name: str, sources) -> str:
    """The scenario's group: helicopter flights, synthetic inputs at the paper's amplitude, stated sources."""
    return "sources" if name in sources else "helicopter" if name.startswith("heli_") else "synthetic"


def split_of(b, seed: int) -> dict[str, str]:
    """The benchmark on the payload's split of the benchmark section `b`'s scenarios and sources, with `seed`."""
    base = scenarios.split(scenarios.scenario_specs(b), b.split.tuning_fraction, seed)
    return bench.split(base, b.payload.sources, b.split.tuning_fraction, seed)


def table(runs, split: dict, sources, label: str) -> None:
    """Mean J over the evaluation set per controller for every criterion, overall and per group, beside the rigid
    gimbal's mean criterion (µrad for an angle) (Markdown)."""
    names = [str(r.input.values[0]) for r in runs]
    groups = sorted({group_of(n, sources) for n in names})
    first = bench.gather(runs, split, bench.CRITERIA[0])
    columns = [str(c) for c in first.controller.values]
    print(f"\n### {label}\n\n| criterion | scenarios | rigid | tuned C / c_on | " + " | ".join(columns) + " |")
    print("|---|---|---:|---|" + "---:|" * len(columns))
    for criterion in bench.CRITERIA:
        ds = bench.gather(runs, split, criterion).sel(mount="six_axis")
        tuned = f"{float(ds.tuned_damping):g} / {float(ds.tuned_c_on):g}"
        evaluation = ds.set == "evaluation"
        for group in ["all", *groups]:
            where = evaluation & (np.array([group in ("all", group_of(n, sources)) for n in names]))
            n = int(where.sum())
            mean = ds.J.where(where).mean("scenario")
            cells = [f"{float(mean.sel(controller=c)):.3g}" for c in columns]
            rigid = ds[criterion].sel(controller="rigid").where(where).mean("scenario")
            scale, unit = (1e6, " µrad") if ds[criterion].attrs.get("units") == "rad" else (1.0, "")
            cells = [f"{float(rigid) * scale:.3g}{unit}", tuned, *cells]
            print(f"| {criterion} | {group} ({n}) | " + " | ".join(cells) + " |")


def seeds(runs, typed, seeds) -> None:
    """The line-of-sight table on the split of each seed (the same runs, the config's tuning fraction)."""
    b = typed.benchmark
    for seed in seeds:
        split = split_of(b, seed)
        ds = bench.gather(runs, split, "los_std").sel(mount="six_axis")
        cells = " | ".join(f"{c}: {float(ds.J_mean.sel(controller=c)):.3g}" for c in ds.controller.values)
        tuned = f"C {float(ds.tuned_damping):g}, c_on {float(ds.tuned_c_on):g}"
        print(
            f"\nseed {seed} (tuning: {', '.join(n for n in sorted(split) if split[n] == 'tuning')}; {tuned}): {cells}"
        )


def rerun(names, config: dict, typed, run_dir: Path, change: dict) -> list:
    """Every scenario run again with the payload section's values `change` (``gimbal`` a dict of its own)."""
    platform = parse(PlatformParams, view(config["platform"], PlatformParams), "platform")
    section = parse(PayloadSection, config["payload"], "payload").with_camera(platform.structure)
    gimbal = dataclasses.replace(section.gimbal, **change.pop("gimbal", {}))
    section = dataclasses.replace(section, gimbal=gimbal, **change)
    section = bench.benchmark_section(section, typed.benchmark.payload, typed.benchmark.duration_s)
    camera = parse(CameraModel, config["camera"], "camera")
    table_ds = io.open_dataset(run_dir / "payload/table.nc")
    model = DampingModel.from_dataset(io.open_dataset(run_dir / "payload/anfis_model.nc"))
    tasks = []
    for name in names:
        if name in typed.benchmark.payload.sources:
            source = parse(StatedSource, config["sources"][name], f"sources.{name}")
            t, moved, _ = motion(source, typed.benchmark.duration_s)
        else:
            t, moved = case_of(io.open_dataset(run_dir / f"benchmark/scenarios/{name}.nc"))
        tasks.append((bench.run_scenario, (name, "", t, moved, section, platform, camera, table_ds, model)))
    return parallel.run(tasks, 2)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run_dir", nargs="?", default="reports")
    parser.add_argument("--configs", nargs="*", default=["config/config.yaml"])
    parser.add_argument("--seeds", nargs="*", type=int, default=[])
    parser.add_argument("--estimator-hz", nargs="*", type=float, default=[])
    parser.add_argument("--c-off", nargs="*", type=float, default=[])
    parser.add_argument("--lag-s", nargs="*", type=float, default=[])
    args = parser.parse_args()
    config = merged(args.configs)
    typed = load(config)
    b = typed.benchmark
    split = split_of(b, b.split.seed)
    run_dir = Path(args.run_dir)
    runs = [io.open_dataset(run_dir / f"benchmark/payload/runs/{n}.nc") for n in sorted(split)]
    crossover = typed.payload.gimbal.estimator_crossover_hz
    table(runs, split, b.payload.sources, f"the run's ({run_dir}): estimator crossover {crossover:g} Hz")
    seeds(runs, typed, args.seeds)
    changes = [
        (f"estimator crossover {hz:g} Hz", {"gimbal": {"estimator_crossover_hz": hz}}) for hz in args.estimator_hz
    ]
    changes += [(f"skyhook c_off {c:g} N s/m", {"skyhook_c_off": c}) for c in args.c_off]
    changes += [(f"skyhook damper lag {lag:g} s", {"skyhook_lag": lag}) for lag in args.lag_s]
    for label, change in changes:
        start = time.perf_counter()
        again = rerun(sorted(split), config, typed, run_dir, change)
        table(again, split, b.payload.sources, f"{label} ({time.perf_counter() - start:.0f} s)")


if __name__ == "__main__":
    main()
