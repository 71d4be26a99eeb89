"""Snakemake script: gather the chunks into the grid, check a sample against Exudyn, derive the table, draw it."""

import os

os.environ.setdefault("EXUDYN_MODULE", "fast")  # as the chunk jobs: the verification's Exudyn runs

from uavdamp import chunks, criterion, grid, io, workflow  # noqa: E402
from uavdamp.plots.reference_table import reference_table_figure  # noqa: E402

workflow.start_log(snakemake.log[0])
spec = grid.GridSpec.from_config(snakemake.params.grid)
platform = snakemake.params.platform
parts = []
for path in snakemake.input.chunks:  # "i-of-N.nc": each one checked before it is used
    chunk, n_chunks = (int(v) for v in os.path.basename(path).removesuffix(".nc").split("-of-"))
    points = grid.chunk_points(spec, n_chunks, chunk - 1)
    parts.append(chunks.load_chunk(path, points=points, config={"reference_table": snakemake.params.grid,
                                                                "platform": platform}))
full = grid.merge_chunks(spec, parts)
workflow.log_info(f"{full.attrs['n_points']} points ({full.attrs['plant']} plant), {full.attrs['n_failed']} failed; "
                  f"plant {full.attrs['solver_time_s']:.1f} s, build {full.attrs['build_time_s']:.2f} s, "
                  f"workers {full.attrs['worker_time_s']:.1f} s")
check = grid.VerifySpec.from_config(snakemake.params.verify)
checked = grid.verify(platform, spec, full, check, n_jobs=snakemake.threads)
full = full.assign(checked.data_vars)
full.attrs.update(checked.attrs)
workflow.log_info(f"verification: {check.n_points} points, largest relative difference linear vs Exudyn "
                  f"{float(checked.verify_max_relative_difference):.3%} (tolerance {check.tolerance:.3%})")
grid.check_verification(spec, checked, check.tolerance)  # raises VerificationFailed naming the worst point
table = criterion.reference_table(full, snakemake.params.flat_tolerance)
table.attrs["plant"] = full.attrs["plant"]
workflow.log_info(f"optimal damping spread per stiffness: {table.damping_opt_spread.values.round(2).tolist()}")
workflow.log_info(f"scheduling gain per stiffness: {table.scheduling_gain.values.round(3).tolist()}")
config = {"reference_table": snakemake.params.grid, "flat_tolerance": snakemake.params.flat_tolerance,
          "verify": snakemake.params.verify, "platform": platform}
command = workflow.snakemake_command(snakemake)
io.save_figure(reference_table_figure(table), snakemake.output.figure)
io.write_netcdf(full, snakemake.output.grid, config, section="reference_table", command=command)
io.write_netcdf(table, snakemake.output.table, config, section="reference_table", command=command)
