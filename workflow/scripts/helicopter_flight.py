"""Snakemake script: one flight run (hover or forward: trim, release, pilot) -> its motion and its trim (NetCDF)."""

from uavdamp import helicopter, integrity, io, workflow
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
cfg = snakemake.params.helicopter
heli = parse(helicopter.FlightRun, cfg, "helicopter")
run, trim = helicopter.flight_run(heli, snakemake.wildcards.flight)
workflow.log_info(f"{snakemake.wildcards.flight}: {run.attrs}\ntrim:\n{trim}")
command = workflow.snakemake_command(snakemake)
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.write_netcdf(run, snakemake.output.run, cfg, section="helicopter", command=command)
    io.write_netcdf(trim, snakemake.output.trim, cfg, section="helicopter", command=command)
