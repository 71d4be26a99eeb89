"""Snakemake script: the benchmark's MR damper (Spencer et al. 1997, scaled to the platform) -> mr_damper.nc."""

from uavdamp import integrity, io, workflow
from uavdamp.benchmark.loop import MROptions
from uavdamp.damping import actuation
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
options = parse(MROptions, snakemake.params.mr, "benchmark.mr")
config = {"mr": snakemake.params.mr}


def make() -> None:
    spec = actuation.MRSpec.build(options.damping_range, options.max_substep)
    ds = actuation.mr_dataset(spec)
    workflow.log_info(f"MR damper: {spec.params}\ncommand table:\n{ds.equivalent_damping.to_dataframe().to_string()}")
    job.check_outputs()  # under the lock: a later run's output is never replaced
    io.write_netcdf(ds, snakemake.output[0], config, section="benchmark", command=workflow.snakemake_command(snakemake))


# one writer: a job that finds another run's job writing this output waits, then keeps what it finished
if not io.write_once(snakemake.output[0], make, config, section="benchmark"):
    workflow.log_info(f"{snakemake.output[0]}: finished by the process that held its lock; kept, not recomputed")
