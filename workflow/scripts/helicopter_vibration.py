"""Snakemake script: balanced and imbalanced runs -> spectra, dominant frequencies, Fig. 3 analogue."""

from uavdamp import helicopter, io, workflow
from uavdamp.plots.helicopter import fuselage_vibration_figure

workflow.start_log(snakemake.log[0])
cfg = snakemake.params.helicopter
runs = {rotor: io.open_dataset(path) for rotor, path in zip(snakemake.params.rotors, snakemake.input.runs, strict=True)}
ds = helicopter.vibration(helicopter.Helicopter.from_config(cfg), runs, **cfg["spectrum"])
workflow.log_info(f"dominant omega, rad/s:\n{ds.dominant_omega.to_pandas()}")
fig = fuselage_vibration_figure(ds)
io.save_figure(fig, snakemake.output.figure)
io.write_netcdf(
    ds, snakemake.output.vibration, cfg, section="helicopter", command=workflow.snakemake_command(snakemake)
)
