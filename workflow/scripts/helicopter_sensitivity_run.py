"""Snakemake script: one sensitivity run of the imbalanced helicopter (wildcard `run`) -> its motion."""

from dataclasses import replace

from uavdamp import helicopter, integrity, io, workflow
from uavdamp.helicopter import sensitivity
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
cfg, flight = snakemake.params.helicopter, snakemake.params.flight
heli = parse(helicopter.HelicopterRun if flight == "vacuum" else helicopter.FlightRun, cfg, "helicopter")
options = replace(heli.solver, duration=snakemake.params.duration_s)
ds = sensitivity.run(heli, snakemake.wildcards.run, options, flight)
workflow.log_info(f"{snakemake.wildcards.run} ({flight}): done")
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.write_netcdf(
        ds,
        snakemake.output[0],
        {**cfg, "sensitivity_duration_s": snakemake.params.duration_s, "sensitivity_flight": flight},
        section="helicopter",
        command=workflow.snakemake_command(snakemake),
    )
