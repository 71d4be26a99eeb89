"""Snakemake script: the benchmark controllers' parameters at one stiffness (wildcard), tuned on the tuning scenarios
only -> tuned/K<stiffness>.nc."""

import dataclasses
from pathlib import Path

from uavdamp import integrity, io, workflow
from uavdamp.benchmark import loop as benchmark
from uavdamp.config.load import benchmark_options
from uavdamp.damping import actuation
from uavdamp.platform import PlatformParams
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
workflow.load_plugins(snakemake)  # before any strategy is named
p = snakemake.params
options = benchmark_options(p.runs, p.tracking, p.camera)
options = dataclasses.replace(options, stiffness=(float(snakemake.wildcards.stiffness),))
config = {"runs": p.runs, "tracking": p.tracking, "camera": p.camera, "platform": p.platform}


def make() -> None:
    inputs = {Path(path).stem: io.open_dataset(path) for path in snakemake.input.scenarios}
    mr = actuation.MRSpec.from_dataset(io.open_dataset(snakemake.input.mr[0])) if snakemake.input.mr else None
    tuned = benchmark.tune(inputs, parse(PlatformParams, p.platform, "platform"), options, mr=mr)
    workflow.log_info(f"tuned on {sorted(inputs)}:\n{tuned.to_dataframe().to_string()}")
    job.check_outputs()  # under the lock: a later run's output is never replaced
    command = workflow.snakemake_command(snakemake)
    io.write_netcdf(tuned, snakemake.output[0], config, section="benchmark", command=command)


# one writer: a job that finds another run's job writing this output waits, then keeps what it finished
if not io.write_once(snakemake.output[0], make, config, section="benchmark"):
    workflow.log_info(f"{snakemake.output[0]}: finished by the process that held its lock; kept, not recomputed")
