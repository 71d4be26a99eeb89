"""Snakemake script: balanced and imbalanced runs -> spectra, dominant frequencies, Fig. 3 analogue."""

from uavdamp import helicopter, integrity, io, workflow
from uavdamp.plots.helicopter import fuselage_vibration_figure
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
p = snakemake.params
heli = parse(helicopter.HelicopterRun, p.helicopter, "helicopter")
options = parse(helicopter.Spectrum, p.spectrum, "helicopter.spectrum")
runs = {rotor: io.open_dataset(path) for rotor, path in zip(p.rotors, snakemake.input.runs, strict=True)}
ds = helicopter.vibration(heli, runs, options)
lines = ds.dominant_omega.to_dataframe()["dominant_omega"].unstack("axis")
workflow.log_info(f"dominant omega, rad/s:\n{lines}")
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.save_figure(fuselage_vibration_figure(ds), snakemake.output.figure)
    config = {**p.helicopter, "spectrum": p.spectrum}
    io.write_netcdf(
        ds, snakemake.output.vibration, config, section="helicopter", command=workflow.snakemake_command(snakemake)
    )
