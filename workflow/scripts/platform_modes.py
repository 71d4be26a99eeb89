"""Snakemake script: platform modes (reports/platform/modes.nc) and the rigid-vs-isolated response figure."""

from uavdamp import integrity, io, workflow
from uavdamp.damping.laws import Constant
from uavdamp.platform import ExudynPlant, PlatformParams, modes_dataset
from uavdamp.platform.params import Response
from uavdamp.plots.platform import response_figure
from uavdamp.settings import parse
from uavdamp.sources.excitation import sine_input

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
cfg = snakemake.params.platform
params = parse(PlatformParams, {k: v for k, v in cfg.items() if k != "response"}, "platform")
response = parse(Response, cfg["response"], "platform.response")
modes = modes_dataset(params)
for f, target in zip(modes.natural_frequency.values, modes.target_frequency.values, strict=True):
    workflow.log_info(f"mode {f:.4f} Hz (target {target:.2f} Hz, {100 * (f / target - 1):+.3f} %)")

time, motion = sine_input(
    response.freq_y_hz, response.freq_z_hz, response.amplitude, response.duration, params.time_step
)
runs = {}
for kind in ("rigid", "isolated"):
    plant = ExudynPlant(params, mount=kind)
    runs[kind] = plant.run(time, motion, law=Constant(response.damping))
    peak = abs(runs[kind].camera_displacement).max("time").values
    workflow.log_info(
        f"{kind} mount: build {plant.build_time:.4f} s, solve {plant.solve_time:.3f} s, "
        f"{plant.newton_iterations} Newton iterations, peak camera |y|, |z| = {peak} m"
    )
label = f"y {response.freq_y_hz:g} Hz, z {response.freq_z_hz:g} Hz, {response.amplitude * 1e3:g} mm"
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.save_figure(response_figure(runs["rigid"], runs["isolated"], modes, input_label=label), snakemake.output.figure)
    io.write_netcdf(
        modes, snakemake.output.modes, cfg, section="platform", command=workflow.snakemake_command(snakemake)
    )
