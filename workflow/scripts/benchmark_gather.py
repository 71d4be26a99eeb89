"""Snakemake script: the benchmark's scenarios gathered -> criteria.nc, the README table and the figures."""

from pathlib import Path

from uavdamp import integrity, io, workflow
from uavdamp.benchmark import loop as benchmark
from uavdamp.plots import benchmark as plots

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
workflow.load_plugins(snakemake)  # before any strategy is named
config = {"split": snakemake.params.split, "runs": snakemake.params.runs}


def make() -> None:
    runs = [io.open_dataset(path) for path in snakemake.input.runs]
    tuned = benchmark.merge_tuned([io.open_dataset(path) for path in snakemake.input.tuned])
    ds = benchmark.gather(runs, dict(snakemake.params.split), tuned)
    if snakemake.params.extrapolation:  # allowed by benchmark.allow_extrapolation (uavdamp.config.checks.extrapolation)
        ds.attrs["extrapolation_warning"] = "; ".join(snakemake.params.extrapolation)
        workflow.log_info(f"warning: {ds.attrs['extrapolation_warning']}")
    table = "\n".join(plots.markdown_table(ds, damper=str(d)) for d in ds.damper.values)
    workflow.log_info(table)
    job.check_outputs()  # under the lock: a later run's output is never replaced
    io.write_text(table, snakemake.output.table)
    io.save_figure(plots.criteria_figure(ds), snakemake.output.figure)
    io.save_figure(plots.boxplot_figure(ds), snakemake.output.boxplots)
    io.write_netcdf(
        ds, snakemake.output.criteria, config, section="benchmark", command=workflow.snakemake_command(snakemake)
    )


def finished(path) -> bool:
    """The holder of the lock left every output, criteria.nc (written last) whole and of this config."""
    return all(Path(o).is_file() for o in snakemake.output) and io.kept_output(path, config, section="benchmark")


# one writer: a job that finds another run's job writing these outputs waits, then keeps what it finished
if not io.write_guarded(snakemake.output.criteria, make, finished=finished):
    workflow.log_info(f"{snakemake.output.criteria}: finished by the process that held its lock; kept, not recomputed")
