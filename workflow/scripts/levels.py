"""Snakemake script: helicopter runs, the study's cases, stated sources and flight logs -> each input's vibration
levels at the mount in the field's units (g, in/s, VIBE) and their figure."""

import math

from uavdamp import integrity, io, workflow
from uavdamp.plots.levels import levels_figure
from uavdamp.settings import parse
from uavdamp.sources import levels_survey as survey
from uavdamp.sources.stated import StatedSource

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
p = snakemake.params
options = parse(survey.LevelsSection, p.levels, "levels")
rotor = p.rotor
heli = survey.helicopter_lines(
    rotor["omega_rad_s"] / (2 * math.pi),
    options.orders,
    rotor["tail_omega_rad_s"] / (2 * math.pi),
    rotor["tail_blades"],
)
sources = {name: parse(StatedSource, spec, f"sources.{name}") for name, spec in p.sources.items()}
logs = {n: (io.open_dataset(path), p.log_descriptions[n]) for n, path in zip(p.logs, snakemake.input.logs, strict=True)}
runs = {name: io.open_dataset(path) for name, path in zip(p.runs, snakemake.input.runs, strict=True)}
cases = io.open_dataset(snakemake.input.cases)
records = survey.collect(runs, cases, p.cases, sources, logs, options, heli)
ds = survey.survey(records)
ds.attrs["rotor_blades"] = rotor["blades"]
workflow.log_info(f"levels:\n{survey.summary_table(ds)}")
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.save_figure(levels_figure(ds), snakemake.output.figure)
    config = {"levels": p.levels, "rotor": rotor, "sources": p.sources, "cases": p.cases}
    io.write_netcdf(
        ds, snakemake.output.levels, config, section="levels", command=workflow.snakemake_command(snakemake)
    )
