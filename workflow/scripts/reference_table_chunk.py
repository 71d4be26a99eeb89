"""Snakemake script: one chunk of the reference-table grid, joblib over its (K, C) blocks -> NetCDF."""

import os

# Exudyn's AVX2 module without range checks (falls back when the CPU lacks AVX2); set in the environment so
# that joblib's worker processes load the same module and give bit-identical numbers.
os.environ.setdefault("EXUDYN_MODULE", "fast")

from uavdamp import chunks, grid, io, workflow  # noqa: E402

workflow.start_log(snakemake.log[0])
item = snakemake.wildcards.scatteritem  # "i-of-N"
chunk, n_chunks = (int(v) for v in item.split("-of-"))
spec = grid.GridSpec.from_config(snakemake.params.grid, snakemake.params.camera)
platform = snakemake.params.platform
backend, model = grid.split_platform(platform)
spec.check_damper_bounds(grid.PlatformParams.from_config(model))
workflow.log_info(
    f"chunk {item}: {len(grid.chunk_points(spec, n_chunks, chunk - 1))} of {spec.size} points, "
    f"plant {backend}, {snakemake.threads} workers, SLURM job {os.environ.get('SLURM_JOB_ID', 'none')}"
)
with chunks.exclusive(snakemake.output[0]):  # one writer per chunk, even with a killed run's job still alive
    ds = grid.run_chunk(platform, spec, n_chunks=n_chunks, chunk=chunk - 1, n_jobs=snakemake.threads, progress=True)
    workflow.log_info(
        f"chunk {item}: {ds.attrs['n_failed']} failed; build {ds.attrs['build_time_s']:.2f} s, "
        f"plant {ds.attrs['solver_time_s']:.2f} s, workers {ds.attrs['worker_time_s']:.2f} s, "
        f"wall {ds.attrs['wall_time_s']:.2f} s"
    )
    config = {"reference_table": snakemake.params.grid, "camera": snakemake.params.camera, "platform": platform}
    io.write_netcdf(
        ds, snakemake.output[0], config, section="reference_table", command=workflow.snakemake_command(snakemake)
    )
