"""Snakemake script: one measured flight -> the mount's motion (flight_logs/NAME.nc) and its PSD figure."""

from uavdamp import integrity, io, workflow
from uavdamp.plots.flight_log import psd_figure
from uavdamp.settings import parse
from uavdamp.sources.flight_log import FlightLogSource, read_flight_log

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
name = snakemake.wildcards.name
source = parse(FlightLogSource, snakemake.params.source, f"flight_logs.{name}")
ds = read_flight_log(snakemake.input.log, **source.reader_options())
a = ds.attrs
if a["log_sha256"] != snakemake.params.log_sha256:
    raise RuntimeError(f"{snakemake.input.log}: changed while the workflow ran (SHA-256 {a['log_sha256']})")
workflow.log_info(
    f"{a['log_file']} ({a['log_format']}, {a['acc_stream']} at {a['acc_rate_hz']:.1f} Hz, {a['gyro_stream']} at "
    f"{a['gyro_rate_hz']:.1f} Hz): airborne {a['airborne_s_in_window']:.2f} s of the window "
    f"({a['airborne_intervals']}); "
    f"aliasing: {a['problems_aliasing']}; on the ground: {a['problems_on_ground']}; bad samples: "
    f"{a['bad_sample_count']}; VIBE {a['vibe_m_s2'].round(2).tolist()} m/s2; "
    f"{a['sample_rate_hz']:.2f} Hz, window "
    f"{a['log_window_s'][0]:.3f}-{a['log_window_s'][1]:.3f} s, interval jitter std {a['interval_jitter_std']:.3g} "
    f"max {a['interval_jitter_max']:.3g}; peak |displacement| per axis, m: "
    f"{abs(ds.mount_displacement).max('time').values.round(7).tolist()}; peak |rotation|, rad: "
    f"{abs(ds.mount_rotation).max('time').values.round(6).tolist()}"
)
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.save_figure(psd_figure(ds), snakemake.output.figure)
    config = {name: snakemake.params.source}
    command = workflow.snakemake_command(snakemake)
    io.write_netcdf(ds, snakemake.output.motion, config, section="flight_logs", command=command)
