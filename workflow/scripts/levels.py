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
logs = {name: io.open_dataset(path) for name, path in zip(p.logs, snakemake.input.logs, strict=True)}
source_records = {name: survey.source_record(s, options.source_duration_s) for name, s in sources.items()}
log_records = {name: survey.log_record(log, p.log_descriptions[name]) for name, log in logs.items()}
records = {}
for name, path in zip(p.runs, snakemake.input.runs, strict=True):
    records[f"run {name}"] = survey.run_record(io.open_dataset(path), name, options.settle_s, heli)
cases = io.open_dataset(snakemake.input.cases)
for case, use in p.cases.items():  # a case is read at the lines of what it takes its motion from
    if "run" in use:
        lines = heli
    else:
        lines = (source_records[use["source"]] if "source" in use else log_records[use["flight_log"]]).lines_hz
    records[f"case {case}"] = survey.case_record(cases, case, lines)
records |= {f"source {n}": r for n, r in source_records.items()} | {f"log {n}": r for n, r in log_records.items()}
ds = survey.survey(records)
ds.attrs["rotor_blades"] = rotor["blades"]
workflow.log_info(f"levels:\n{survey.summary_table(ds)}")
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.save_figure(levels_figure(ds), snakemake.output.figure)
    config = {"levels": p.levels, "rotor": rotor, "sources": p.sources, "cases": p.cases}
    io.write_netcdf(
        ds, snakemake.output.levels, config, section="levels", command=workflow.snakemake_command(snakemake)
    )
