"""Snakemake script: one measured flight -> the mount's motion (flight_logs/NAME.nc) and its PSD figure."""

from uavdamp import io, workflow
from uavdamp.flight_log import FlightLogSource, read_flight_log
from uavdamp.plots.flight_log import psd_figure
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
name = snakemake.wildcards.name
source = parse(FlightLogSource, snakemake.params.source, f"flight_logs.{name}")
ds = read_flight_log(
    snakemake.input.log,
    band_hz=source.band_hz,
    window_s=source.window_s,
    imu_to_mount_m=source.imu_to_mount_m,
    upsample=source.upsample,
)
a = ds.attrs
workflow.log_info(
    f"{a['log_file']} ({a['log_format']}, {a['log_messages']}): {a['sample_rate_hz']:.2f} Hz, window "
    f"{a['log_window_s'][0]:.3f}-{a['log_window_s'][1]:.3f} s, interval jitter std {a['interval_jitter_std']:.3g} "
    f"max {a['interval_jitter_max']:.3g}; peak |displacement| per axis, m: "
    f"{abs(ds.mount_displacement).max('time').values.round(7).tolist()}; peak |rotation|, rad: "
    f"{abs(ds.mount_rotation).max('time').values.round(6).tolist()}"
)
io.save_figure(psd_figure(ds), snakemake.output.figure)
config = {name: snakemake.params.source}
command = workflow.snakemake_command(snakemake)
io.write_netcdf(ds, snakemake.output.motion, config, section="flight_logs", command=command)
