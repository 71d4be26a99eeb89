"""Snakemake script: one helicopter run (balanced, imbalanced or both rotors) -> NetCDF."""

from uavdamp import helicopter, integrity, io, workflow
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
cfg = snakemake.params.helicopter
heli = parse(helicopter.HelicopterRun, cfg, "helicopter")
if snakemake.wildcards.rotor == "balanced":
    heli = heli.balanced()
elif snakemake.wildcards.rotor == "both_rotors":
    heli = heli.with_tail_rotor_speed(heli.tail_rotor.omega_running_rad_s)
ds = helicopter.run(heli, heli.solver, progress=f"helicopter {snakemake.wildcards.rotor}")
workflow.log_info(f"{snakemake.wildcards.rotor}: {ds.attrs}")
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.write_netcdf(ds, snakemake.output[0], cfg, section="helicopter", command=workflow.snakemake_command(snakemake))
