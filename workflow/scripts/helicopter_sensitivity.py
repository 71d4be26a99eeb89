"""Snakemake script: gather the sensitivity runs -> reports/helicopter/sensitivity.nc and its figure."""

from uavdamp import helicopter, integrity, io, workflow
from uavdamp.helicopter import sensitivity
from uavdamp.plots.helicopter import sensitivity_figure
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
p = snakemake.params
heli = parse(helicopter.HelicopterRun, p.helicopter, "helicopter")
spectrum = parse(helicopter.Spectrum, p.spectrum, "helicopter.spectrum")
ds = sensitivity.combine(
    [io.open_dataset(path) for path in snakemake.input.runs],
    rotor_omega_rad_s=heli.main_rotor.omega_rad_s,
    spectrum=spectrum,
)
workflow.log_info(f"dominant lines:\n{ds[['dominant_omega', 'dominant_amplitude']].to_dataframe()}")
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.save_figure(sensitivity_figure(ds), snakemake.output.figure)
    config = {**p.sensitivity, "spectrum": p.spectrum}
    io.write_netcdf(
        ds,
        snakemake.output.sensitivity,
        config,
        section="helicopter_sensitivity",
        command=workflow.snakemake_command(snakemake),
    )
