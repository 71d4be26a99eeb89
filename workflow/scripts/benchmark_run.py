"""Snakemake script: every benchmark controller on one scenario (wildcard `scenario`) -> its criteria."""

from uavdamp import integrity, io, workflow
from uavdamp.anfis import DampingPredictor
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
config = {"runs": p.runs, "tracking": p.tracking, "camera": p.camera, "platform": p.platform}


def make() -> None:
    model = DampingPredictor.from_dataset(io.open_dataset(snakemake.input.model))
    tuned = benchmark.merge_tuned([io.open_dataset(path) for path in snakemake.input.tuned])
    ds = benchmark.run_scenario(
        io.open_dataset(snakemake.input.scenario),
        tuned,
        parse(PlatformParams, p.platform, "platform"),
        options,
        model=model,
        table=io.open_dataset(snakemake.input.table),
        mr=actuation.MRSpec.from_dataset(io.open_dataset(snakemake.input.mr[0])) if snakemake.input.mr else None,
        step_check=bool(p.step_check),
    )
    for damper in ds.damper.values:
        workflow.log_info(f"{damper}:\n" + ds.J.sel(damper=damper).to_dataframe().J.unstack("criterion").to_string())
    job.check_outputs()  # under the lock: a later run's output is never replaced
    io.write_netcdf(ds, snakemake.output[0], config, section="benchmark", command=workflow.snakemake_command(snakemake))


# one writer: a job that finds another run's job writing this output waits, then keeps what it finished
if not io.write_once(snakemake.output[0], make, config, section="benchmark"):
    workflow.log_info(f"{snakemake.output[0]}: finished by the process that held its lock; kept, not recomputed")
