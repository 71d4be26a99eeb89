"""Snakemake script: helicopter runs, measured flights and stated sources -> the study's input cases."""

from uavdamp import integrity, io, workflow
from uavdamp.settings import parse
from uavdamp.sources import excitation, stated

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
cfg = snakemake.params.excitation
options = parse(excitation.ExcitationOptions, cfg, "study")
runs = {name: io.open_dataset(path) for name, path in zip(snakemake.params.runs, snakemake.input.runs, strict=True)}
logs = {name: io.open_dataset(path) for name, path in zip(snakemake.params.logs, snakemake.input.logs, strict=True)}
sources = {
    name: stated.generate(parse(stated.StatedSource, spec, f"sources.{name}"), name, options.duration_s)
    for name, spec in snakemake.params.sources.items()
}  # over the cases' duration, as a benchmark scenario over benchmark.duration_s: the same source alike
ds = excitation.cases_dataset(runs, options, logs, sources)
workflow.log_info(
    f"dominant frequency, Hz:\n{ds.dominant_freq.to_pandas()}\nspectral width, Hz:\n{ds.spectral_width.to_pandas()}"
)
config = {**cfg, "sources": snakemake.params.sources} if snakemake.params.sources else cfg
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.write_netcdf(ds, snakemake.output[0], config, section="study", command=workflow.snakemake_command(snakemake))
