"""Snakemake script: the results page (summary.md, summary.html) from the run's NetCDF outputs and figures (rules
summary and summary_with_benchmark)."""

import os
from pathlib import Path

from uavdamp import integrity, io, workflow
from uavdamp.results import render as summary_render
from uavdamp.results import summary

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
page_dir = Path(snakemake.output.markdown).parent
outputs, figures = {}, {}
for role, path in snakemake.input.items():
    if role.startswith("figure_"):
        figures[role.removeprefix("figure_")] = os.path.relpath(path, page_dir)
    elif role == "landing":
        continue
    else:
        outputs[role] = io.open_dataset(path)
page = summary.summary_page(outputs, figures)
for sentence in page.findings:
    workflow.log_info(sentence)
images = {fig.path: (page_dir / fig.path).read_bytes() for fig in page.figures}
with job.writing():  # under the outputs' lock; a later run's outputs are never replaced
    io.write_text(summary_render.to_markdown(page), snakemake.output.markdown)
    io.write_text(summary_render.to_html(page, images), snakemake.output.html)
    if "landing" in snakemake.output.keys():  # the study's page is the report's first page; the benchmark's is not
        landing = Path(snakemake.input.landing).read_text()
        text = summary_render.landing_rst(landing, page, Path(snakemake.output.html).name)
        io.write_text(text, snakemake.output.landing)
