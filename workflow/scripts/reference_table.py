"""Snakemake script: gather the chunks into the grid, check a sample against Exudyn, derive the table, draw it."""

import os

os.environ.setdefault("EXUDYN_MODULE", "fast")  # as the chunk jobs: the verification's Exudyn runs

from uavdamp import chunks, criterion, grid, io, workflow  # noqa: E402
from uavdamp.plots.reference_table import criteria_figure, reference_table_figure  # noqa: E402

workflow.start_log(snakemake.log[0])
spec = grid.GridSpec.from_config(snakemake.params.grid, snakemake.params.camera)
target = snakemake.params.target
platform = snakemake.params.platform
parts = []
for path in snakemake.input.chunks:  # "i-of-N.nc": each one checked before it is used
    chunk, n_chunks = (int(v) for v in os.path.basename(path).removesuffix(".nc").split("-of-"))
    points = grid.chunk_points(spec, n_chunks, chunk - 1)
    made_with = {"reference_table": snakemake.params.grid, "camera": snakemake.params.camera, "platform": platform}
    parts.append(chunks.load_chunk(path, points=points, config=made_with))
full = grid.merge_chunks(spec, parts)
workflow.log_info(
    f"{full.attrs['n_points']} points ({full.attrs['plant']} plant), {full.attrs['n_failed']} failed; "
    f"plant {full.attrs['solver_time_s']:.1f} s, build {full.attrs['build_time_s']:.2f} s, "
    f"workers {full.attrs['worker_time_s']:.1f} s"
)
check = grid.VerifySpec.from_config(snakemake.params.verify)
checked = grid.verify(platform, spec, full, check, n_jobs=snakemake.threads)
full = full.assign(checked.data_vars)
full.attrs.update(checked.attrs)
largest = checked.verify_relative_difference.max(["verify", "window"])
workflow.log_info(
    f"verification: {check.n_points} points, largest relative difference linear vs Exudyn per "
    f"criterion {dict(zip(largest.criterion.values, largest.values.round(5).tolist(), strict=True))} "
    f"(tolerance {check.tolerance})"
)
grid.check_verification(spec, checked, check.tolerance)  # raises VerificationFailed naming the worst point
table = criterion.reference_table(full, snakemake.params.flat_tolerance)
chosen = criterion.select_table(table, target["criterion"], target["window"])
table.attrs.update(plant=full.attrs["plant"], criterion=target["criterion"], window=target["window"])
for name in table.criterion.values:
    for window in table.window.values:
        part = table.sel(criterion=name, window=window)
        workflow.log_info(
            f"{name}, {window}: optimal damping spread per stiffness "
            f"{part.damping_opt_spread.values.round(2).tolist()}; scheduling gain per stiffness "
            f"{part.scheduling_gain.values.round(3).tolist()}"
        )
workflow.log_info(f"the ANFIS learns: {target['criterion']}, {target['window']} window")
config = {
    "reference_table": {**snakemake.params.grid, **target},
    "flat_tolerance": snakemake.params.flat_tolerance,
    "verify": snakemake.params.verify,
    "camera": snakemake.params.camera,
    "platform": platform,
}
command = workflow.snakemake_command(snakemake)
io.save_figure(reference_table_figure(chosen), snakemake.output.figure)
io.save_figure(criteria_figure(table), snakemake.output.criteria)
io.write_netcdf(full, snakemake.output.grid, config, section="reference_table", command=command)
io.write_netcdf(table, snakemake.output.table, config, section="reference_table", command=command)
