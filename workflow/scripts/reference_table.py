"""Snakemake script: gather the chunks into the grid, check a sample against Exudyn, derive the table, draw it."""

import os

from uavdamp import integrity, io, workflow
from uavdamp.camera.optics import CameraOptics
from uavdamp.platform import PlatformParams
from uavdamp.plots.reference_table import criteria_figure, reference_table_figure
from uavdamp.reference_table import GridSpec, ReferenceGrid, VerifyOptions, chunks, criteria, grid, verify
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
p = snakemake.params
spec = GridSpec.of(parse(ReferenceGrid, p.grid, "reference_table"), parse(CameraOptics, p.camera, "camera"))
platform = parse(PlatformParams, p.platform, "platform")
check = parse(VerifyOptions, p.verify, "reference_table.verify")
criterion, window = p.target
parts = []
for path in snakemake.input.chunks:  # "i-of-N.nc": each one checked before it is used
    chunk, n_chunks = (int(v) for v in os.path.basename(path).removesuffix(".nc").split("-of-"))
    points = grid.chunk_points(spec, n_chunks, chunk - 1)
    made_with = {"reference_table": p.grid, "camera": p.camera, "platform": p.platform}
    parts.append(chunks.load_chunk(path, points=points, config=made_with))
full = chunks.merge_chunks(spec, parts)
workflow.log_info(
    f"{full.attrs['n_points']} points ({full.attrs['plant']} plant), {full.attrs['n_failed']} failed; "
    f"plant {full.attrs['solver_time_s']:.1f} s, build {full.attrs['build_time_s']:.2f} s, "
    f"workers {full.attrs['worker_time_s']:.1f} s"
)
checked = verify.verify(platform, spec, full, check, n_jobs=snakemake.threads)
full = full.assign(checked.data_vars)
full.attrs.update(checked.attrs)
largest = checked.verify_relative_difference.max(["verify", "window"])
workflow.log_info(
    f"verification: {checked.sizes['verify']} points, largest relative difference linear vs Exudyn per "
    f"criterion {dict(zip(largest.criterion.values, largest.values.round(5).tolist(), strict=True))} "
    f"(tolerance {check.tolerance})"
)
verify.check_verification(spec, checked, check.tolerance)  # raises VerificationFailed naming the worst point
table = criteria.reference_table(full, p.flat_tolerance, (platform.damping_min, platform.damping_max))
chosen = criteria.select_table(table, criterion, window)
share = float(chosen.grid_edge_share)  # the ANFIS refuses a table whose learnt optimum sits on a grid edge
table.attrs.update(plant=full.attrs["plant"], criterion=criterion, window=window, grid_edge_share=share)
for name in table.criterion.values:
    for w in table.window.values:
        part = table.sel(criterion=name, window=w)
        workflow.log_info(
            f"{name}, {w}: optimal damping spread per stiffness "
            f"{part.damping_opt_spread.values.round(2).tolist()}; scheduling gain per stiffness "
            f"{part.scheduling_gain.values.round(3).tolist()}"
        )
workflow.log_info(
    f"the ANFIS learns: {criterion}, {window} window; optimum on an edge of the C grid inside the damper's range: "
    f"{share:.2%} of the cells, at the damper's bound: {float((chosen.optimum_at_grid_edge == 3).mean()):.2%}"
)
config = {
    "reference_table": {**p.grid, "criterion": criterion, "window": window},
    "flat_tolerance": p.flat_tolerance,
    "verify": p.verify,
    "camera": p.camera,
    "platform": p.platform,
}
command = workflow.snakemake_command(snakemake)
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.save_figure(reference_table_figure(chosen), snakemake.output.figure)
    io.save_figure(criteria_figure(table), snakemake.output.criteria)
    io.write_netcdf(full, snakemake.output.grid, config, section="reference_table", command=command)
    io.write_netcdf(table, snakemake.output.table, config, section="reference_table", command=command)
