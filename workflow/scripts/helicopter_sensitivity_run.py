"""Snakemake script: one sensitivity run of the imbalanced helicopter (wildcard `run`) -> its motion."""

from dataclasses import replace

from uavdamp import helicopter, io, workflow
from uavdamp.helicopter import sensitivity
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
cfg = snakemake.params.helicopter
heli = parse(helicopter.HelicopterRun, cfg, "helicopter")
ds = sensitivity.run(heli, snakemake.wildcards.run, replace(heli.solver, duration=snakemake.params.duration_s))
workflow.log_info(f"{snakemake.wildcards.run}: done")
io.write_netcdf(
    ds,
    snakemake.output[0],
    {**cfg, "sensitivity_duration_s": snakemake.params.duration_s},
    section="helicopter",
    command=workflow.snakemake_command(snakemake),
)
