"""Snakemake script: gather the chunks into the grid, derive the reference table, draw the heatmaps."""

from uavdamp import criterion, grid, io, workflow
from uavdamp.plots.reference_table import reference_table_figure

workflow.start_log(snakemake.log[0])
spec = grid.GridSpec.from_config(snakemake.params.grid)
full = grid.merge_chunks(spec, [io.open_dataset(path) for path in snakemake.input.chunks])
table = criterion.reference_table(full, snakemake.params.flat_tolerance)
workflow.log_info(f"{full.attrs['n_points']} points, {full.attrs['n_failed']} failed; solver {full.attrs['solver_time_s']:.1f} s, "
            f"build {full.attrs['build_time_s']:.2f} s, workers {full.attrs['worker_time_s']:.1f} s")
workflow.log_info(f"optimal damping spread per stiffness: {table.damping_opt_spread.values.round(2).tolist()}")
workflow.log_info(f"scheduling gain per stiffness: {table.scheduling_gain.values.round(3).tolist()}")
config = {"reference_table": snakemake.params.grid, "flat_tolerance": snakemake.params.flat_tolerance}
command = workflow.snakemake_command(snakemake)
io.save_figure(reference_table_figure(table), snakemake.output.figure)
io.write_netcdf(full, snakemake.output.grid, config, section="reference_table", command=command)
io.write_netcdf(table, snakemake.output.table, config, section="reference_table", command=command)
