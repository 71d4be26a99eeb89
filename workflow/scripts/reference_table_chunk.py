"""Snakemake script: one chunk of the reference-table grid, joblib over its (K, C) blocks -> NetCDF."""

import os
from functools import partial

from uavdamp import integrity, io, workflow
from uavdamp.camera.optics import CameraOptics
from uavdamp.platform import PlatformParams
from uavdamp.reference_table import GridSpec, ReferenceGrid, chunks, grid
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
p = snakemake.params
item = snakemake.wildcards.scatteritem  # "i-of-N"
chunk, n_chunks = (int(v) for v in item.split("-of-"))
spec = GridSpec.of(parse(ReferenceGrid, p.grid, "reference_table"), parse(CameraOptics, p.camera, "camera"))
platform = parse(PlatformParams, p.platform, "platform")
workflow.log_info(
    f"chunk {item}: {len(grid.chunk_points(spec, n_chunks, chunk - 1))} of {spec.size} points, "
    f"plant {platform.backend}, {snakemake.threads} workers, SLURM job {os.environ.get('SLURM_JOB_ID', 'none')}"
)
config = {"reference_table": p.grid, "camera": p.camera, "platform": p.platform}
points = grid.chunk_points(spec, n_chunks, chunk - 1)


def make() -> None:
    ds = chunks.run_chunk(platform, spec, n_chunks=n_chunks, chunk=chunk - 1, n_jobs=snakemake.threads, progress=True)
    workflow.log_info(
        f"chunk {item}: {ds.attrs['n_failed']} failed; build {ds.attrs['build_time_s']:.2f} s, "
        f"plant {ds.attrs['solver_time_s']:.2f} s, workers {ds.attrs['worker_time_s']:.2f} s, "
        f"wall {ds.attrs['wall_time_s']:.2f} s"
    )
    job.check_outputs()  # under the lock: a later run's output is never replaced
    command = workflow.snakemake_command(snakemake)
    io.write_netcdf(ds, snakemake.output[0], config, section="reference_table", command=command)


# one writer per chunk: a job that finds another run's job writing it waits, then keeps what that job finished
finished = partial(chunks.finished_chunk, points=points, config=config)
if not io.write_guarded(snakemake.output[0], make, finished=finished):
    workflow.log_info(f"chunk {item}: finished by the process that held its lock; kept, not recomputed")
