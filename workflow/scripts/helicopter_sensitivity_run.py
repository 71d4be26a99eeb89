"""Snakemake script: the sensitivity runs of the imbalanced helicopter (params `runs`, one after the other in this
job) -> each run's motion."""

from dataclasses import replace

from uavdamp import helicopter, integrity, io, workflow
from uavdamp.helicopter import sensitivity
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
cfg, flight = snakemake.params.helicopter, snakemake.params.flight
heli = parse(helicopter.HelicopterRun if flight == "vacuum" else helicopter.FlightRun, cfg, "helicopter")
options = replace(heli.solver, duration=snakemake.params.duration_s)
runs = {}
for name in snakemake.params.runs:
    runs[name] = sensitivity.run(heli, name, options, flight)
    workflow.log_info(f"{name} ({flight}): done")
config = {**cfg, "sensitivity_duration_s": snakemake.params.duration_s, "sensitivity_flight": flight}
command = workflow.snakemake_command(snakemake)
with job.writing():  # under the outputs' lock; a later run's outputs are never replaced
    for ds, path in zip(runs.values(), snakemake.output, strict=True):
        io.write_netcdf(ds, path, config, section="helicopter", command=command)
