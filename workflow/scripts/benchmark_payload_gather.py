"""Snakemake script: the benchmark on the payload gathered -> criteria.nc, its table and figure."""

from uavdamp import integrity, io, workflow
from uavdamp.benchmark import payload as bench
from uavdamp.plots import benchmark_payload as plots
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
p = snakemake.params
options = parse(bench.PayloadBenchmark, {"criterion": p.criterion}, "benchmark.payload")
config = {"split": p.split, "criterion": p.criterion}
runs = [io.open_dataset(path) for path in snakemake.input.runs]
ds = bench.gather(runs, dict(p.split), options.criterion)
table = bench.markdown_table(ds)
workflow.log_info(table)
with job.writing():  # under the outputs' lock; a later run's outputs are never replaced
    io.write_text(table, snakemake.output.table)
    io.save_figure(plots.criteria_figure(ds), snakemake.output.figure)
    io.write_netcdf(
        ds, snakemake.output.criteria, config, section="benchmark", command=workflow.snakemake_command(snakemake)
    )
