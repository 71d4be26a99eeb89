"""Snakemake script: the payload stage -> payload/comparison.nc, payload/design.nc (modes, loops, transmissibility)
and the line-of-sight and transmissibility figures."""

from uavdamp import integrity, io, workflow
from uavdamp.anfis.predictor import DampingPredictor
from uavdamp.camera.optics import CameraModel
from uavdamp.platform import PlatformParams
from uavdamp.plots import payload as plots
from uavdamp.settings import parse
from uavdamp.sources.stated import StatedSource
from uavdamp.study import payload, payload_design

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
p = snakemake.params
platform = parse(PlatformParams, p.platform, "platform")
section = parse(payload.PayloadSection, {**p.payload, "threads": snakemake.threads}, "payload")
section = section.with_camera(platform.structure)  # the one camera every payload carries
camera = parse(CameraModel, p.camera, "camera")
sources = {name: parse(StatedSource, cfg, f"sources.{name}") for name, cfg in p.sources.items()}
cases = io.open_dataset(snakemake.input.cases)
table = io.open_dataset(snakemake.input.table)  # the payload table: the scheduled law's
model = DampingPredictor.from_dataset(io.open_dataset(snakemake.input.model))  # the payload ANFIS: the law anfis's
ds = payload.compare_inputs(payload.inputs(cases, sources, section), section, platform, camera, table, model)
design = payload_design.design_dataset(section)
for name in ("los_std", "best_damping", "law_los_std", "scheduled_damping", "anfis_damping"):
    if name in ds:
        workflow.log_info(f"{name} ({ds[name].attrs['units']}):\n{ds[name].to_dataframe().to_string()}")
config = {"payload": p.payload, "sources": p.sources, "camera": p.camera, "platform": p.platform}
command = workflow.snakemake_command(snakemake)
with job.writing():  # under the outputs' lock; a later run's outputs are never replaced
    io.save_figure(plots.line_of_sight_figure(ds), snakemake.output.figure)
    io.save_figure(plots.transmissibility_figure(design), snakemake.output.transmissibility)
    io.write_netcdf(ds, snakemake.output.comparison, config, section="payload", command=command)
    io.write_netcdf(design, snakemake.output.design, config, section="payload", command=command)
