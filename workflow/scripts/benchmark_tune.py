"""Snakemake script: the benchmark controllers' parameters at one stiffness (wildcard), tuned on the tuning scenarios
only -> tuned/K<stiffness>.nc."""

import os

for _name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):  # small matrices: one BLAS thread
    os.environ.setdefault(_name, "1")

import dataclasses  # noqa: E402
from pathlib import Path  # noqa: E402

from uavdamp import benchmark, io, workflow  # noqa: E402
from uavdamp.platform import PlatformParams  # noqa: E402

workflow.start_log(snakemake.log[0])
p = snakemake.params
options = benchmark.BenchmarkOptions.from_config(p.runs, p.tracking, p.camera)
options = dataclasses.replace(options, stiffness=(float(snakemake.wildcards.stiffness),))
inputs = {Path(path).stem: io.open_dataset(path) for path in snakemake.input.scenarios}
tuned = benchmark.tune(inputs, PlatformParams.from_config(p.platform), options)
workflow.log_info(f"tuned on {sorted(inputs)}:\n{tuned.to_dataframe().to_string()}")
config = {"runs": p.runs, "tracking": p.tracking, "camera": p.camera, "platform": p.platform}
io.write_netcdf(tuned, snakemake.output[0], config, section="benchmark", command=workflow.snakemake_command(snakemake))
