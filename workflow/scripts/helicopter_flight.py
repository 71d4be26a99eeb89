"""Snakemake script: one flight run (hover or forward: trim, release, pilot) -> its motion and its trim (NetCDF)."""

from uavdamp import helicopter, io, workflow
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
cfg = snakemake.params.helicopter
heli = parse(helicopter.FlightRun, cfg, "helicopter")
run, trim = helicopter.flight_run(heli, snakemake.wildcards.flight)
workflow.log_info(f"{snakemake.wildcards.flight}: {run.attrs}\ntrim:\n{trim}")
command = workflow.snakemake_command(snakemake)
io.write_netcdf(run, snakemake.output.run, cfg, section="helicopter", command=command)
io.write_netcdf(trim, snakemake.output.trim, cfg, section="helicopter", command=command)
