"""Snakemake script: helicopter runs and measured flights -> the study's input cases (high-passed, scaled)."""

from uavdamp import excitation, io, workflow
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
cfg = snakemake.params.excitation
options = parse(excitation.ExcitationOptions, cfg, "study")
runs = {name: io.open_dataset(path) for name, path in zip(snakemake.params.runs, snakemake.input.runs, strict=True)}
logs = {name: io.open_dataset(path) for name, path in zip(snakemake.params.logs, snakemake.input.logs, strict=True)}
ds = excitation.cases_dataset(runs, options, logs)
workflow.log_info(
    f"dominant frequency, Hz:\n{ds.dominant_freq.to_pandas()}\nspectral width, Hz:\n{ds.spectral_width.to_pandas()}"
)
io.write_netcdf(ds, snakemake.output[0], cfg, section="study", command=workflow.snakemake_command(snakemake))
