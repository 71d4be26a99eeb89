"""Snakemake script: one sensitivity run of the imbalanced helicopter (wildcard `run`) -> its motion."""

import os

os.environ.setdefault("EXUDYN_MODULE", "fast")  # as helicopter_run.py: the same Exudyn module everywhere

from uavdamp import helicopter, io, sensitivity, workflow  # noqa: E402

workflow.start_log(snakemake.log[0])
cfg = snakemake.params.helicopter
heli = helicopter.Helicopter.from_config(cfg)
options = helicopter.SolverOptions.from_config({**cfg["solver"], "duration": snakemake.params.duration})
ds = sensitivity.run(heli, snakemake.wildcards.run, options)
workflow.log_info(f"{snakemake.wildcards.run}: done")
io.write_netcdf(
    ds,
    snakemake.output[0],
    {**cfg, "sensitivity_duration": snakemake.params.duration},
    section="helicopter",
    command=workflow.snakemake_command(snakemake),
)
