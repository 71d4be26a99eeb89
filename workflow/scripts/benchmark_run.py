"""Snakemake script: every benchmark controller on one scenario (wildcard `scenario`) -> its criteria."""

import os

for _name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):  # small matrices: one BLAS thread
    os.environ.setdefault(_name, "1")

from uavdamp import benchmark, io, learning, workflow  # noqa: E402
from uavdamp.platform import PlatformParams  # noqa: E402

workflow.start_log(snakemake.log[0])
p = snakemake.params
options = benchmark.BenchmarkOptions.from_config(p.runs, p.tracking, p.camera)
model = learning.TableModel.from_dataset(io.open_dataset(snakemake.input.model))
tuned = benchmark.merge_tuned([io.open_dataset(path) for path in snakemake.input.tuned])
ds = benchmark.run_scenario(
    io.open_dataset(snakemake.input.scenario),
    tuned,
    PlatformParams.from_config(p.platform),
    options,
    model=model,
    table=io.open_dataset(snakemake.input.table),
)
workflow.log_info(ds.J.sel(damper="ideal").to_dataframe().J.unstack("criterion").to_string())
config = {"runs": p.runs, "tracking": p.tracking, "camera": p.camera, "platform": p.platform}
io.write_netcdf(ds, snakemake.output[0], config, section="benchmark", command=workflow.snakemake_command(snakemake))
