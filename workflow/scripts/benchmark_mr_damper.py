"""Snakemake script: the benchmark's MR damper (Spencer et al. 1997, scaled to the platform) -> mr_damper.nc."""

from uavdamp import actuation, io, workflow
from uavdamp.benchmark import MROptions
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
options = parse(MROptions, snakemake.params.mr, "benchmark.mr")
spec = actuation.MRSpec.build(options.damping_range, options.max_substep)
ds = actuation.mr_dataset(spec)
workflow.log_info(f"MR damper: {spec.params}\ncommand table:\n{ds.equivalent_damping.to_dataframe().to_string()}")
config = {"mr": snakemake.params.mr}
io.write_netcdf(ds, snakemake.output[0], config, section="benchmark", command=workflow.snakemake_command(snakemake))
