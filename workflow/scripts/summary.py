"""Snakemake script: the results page (summary.md, summary.html) from the run's NetCDF outputs."""

from pathlib import Path

from uavdamp import io, summary, workflow

workflow.start_log(snakemake.log[0])
outputs = {role: io.open_dataset(path) for role, path in snakemake.input.items()}
sections = summary.summary_tables(outputs)
numbers = summary.headline(outputs["comparison"])
provenance = summary.provenance_of(outputs["comparison"])
workflow.log_info(f"headline numbers: {numbers}")
Path(snakemake.output.markdown).write_text(summary.to_markdown(sections, numbers, provenance))
Path(snakemake.output.html).write_text(summary.to_html(sections, numbers, provenance))
