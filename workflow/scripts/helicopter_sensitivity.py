"""Snakemake script: gather the sensitivity runs -> reports/helicopter/sensitivity.nc and its figure."""

from uavdamp import io, sensitivity, workflow
from uavdamp.plots.helicopter import sensitivity_figure

workflow.start_log(snakemake.log[0])
ds = sensitivity.combine(
    [io.open_dataset(path) for path in snakemake.input.runs],
    rotor_omega_rad_s=snakemake.params.rotor_omega_rad_s,
    **snakemake.params.spectrum,
)
workflow.log_info(f"dominant lines:\n{ds[['dominant_omega', 'dominant_amplitude']].to_dataframe()}")
io.save_figure(sensitivity_figure(ds), snakemake.output.figure)
config = {**snakemake.params.sensitivity, "spectrum": snakemake.params.spectrum}
io.write_netcdf(
    ds,
    snakemake.output.sensitivity,
    config,
    section="helicopter_sensitivity",
    command=workflow.snakemake_command(snakemake),
)
