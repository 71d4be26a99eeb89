"""Snakemake script: one benchmark scenario's mount input (wildcard `scenario`) -> NetCDF."""

import os

os.environ.setdefault("EXUDYN_MODULE", "fast")  # as helicopter_run.py: the same Exudyn module everywhere

from uavdamp import io, scenarios, workflow  # noqa: E402
from uavdamp.platform import PlatformParams  # noqa: E402

workflow.start_log(snakemake.log[0])
cfg = snakemake.params.inputs
params = PlatformParams.from_config(snakemake.params.platform)
ds = scenarios.scenario_input(snakemake.wildcards.scenario, cfg, snakemake.params.helicopter, params.time_step)
workflow.log_info(f"{snakemake.wildcards.scenario}: {ds.attrs}")
config = {"inputs": cfg, "helicopter": snakemake.params.helicopter, "platform": snakemake.params.platform}
io.write_netcdf(ds, snakemake.output[0], config, section="benchmark", command=workflow.snakemake_command(snakemake))
