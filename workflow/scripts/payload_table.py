"""Snakemake script: the payload table -> payload/table.nc and its figure (src/uavdamp/study/payload_table.py)."""

from types import SimpleNamespace

from uavdamp import integrity, io, workflow
from uavdamp.plots.payload_table import table_figure
from uavdamp.settings import parse
from uavdamp.study import payload, payload_table

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)
p = snakemake.params
camera = SimpleNamespace(camera_mass=p.camera["camera_mass_kg"], camera_size=tuple(p.camera["camera_size_m"]))
section = parse(payload.PayloadSection, p.payload, "payload").with_camera(camera)
table = payload_table.table_dataset(section)
gain = table.scheduling_gain.to_dataframe().dropna()
workflow.log_info(f"scheduling gain (1: none) per DOF, element stiffness and band:\n{gain.to_string()}")
config = {"payload": p.payload, "platform": {"structure": p.camera}}
command = workflow.snakemake_command(snakemake)
with job.writing():
    io.save_figure(table_figure(table, section.six_axis.stiffness[2]), snakemake.output.figure)
    io.write_netcdf(table, snakemake.output.table, config, section="payload_table", command=command)
