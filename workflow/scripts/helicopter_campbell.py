"""Snakemake script: Campbell diagram of the balanced rotor's coupled modes (multiblade coordinates) -> NetCDF."""

import numpy as np
import xarray as xr

from uavdamp import helicopter, integrity, io, workflow
from uavdamp.helicopter import floquet, modes
from uavdamp.plots.helicopter import campbell_figure
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
cfg, opts = snakemake.params.helicopter, snakemake.params.campbell
imbalanced = parse(helicopter.HelicopterRun, cfg, "helicopter")
campbell = parse(helicopter.Campbell, opts, "helicopter.campbell")
heli = imbalanced.balanced()
speeds = np.linspace(0.0, campbell.max_speed_ratio * heli.main_rotor.omega_rad_s, campbell.n_speeds)
ds = modes.campbell(heli, speeds, check_azimuths_rad=campbell.check_azimuths_rad)
ds = xr.merge([ds, floquet.floquet_dataset(imbalanced, campbell.floquet_steps)], combine_attrs="no_conflicts")
nominal = ds.sel(rotor_speed=heli.main_rotor.omega_rad_s, method="nearest")
table = nominal[["frequency", "damping_ratio"]].to_dataframe()
workflow.log_info(f"modes at {float(nominal.rotor_speed):.2f} rad/s:\n{table}")
workflow.log_info(f"largest periodicity residual: {float(ds.periodicity_residual.max()):.3g}")
workflow.log_info(f"Floquet, imbalanced rotor:\n{ds[['floquet_frequency', 'floquet_decay_rate']].to_dataframe()}")
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.save_figure(campbell_figure(ds), snakemake.output.figure)
    io.write_netcdf(
        ds,
        snakemake.output.campbell,
        {**cfg, "campbell": opts},
        section="helicopter",
        command=workflow.snakemake_command(snakemake),
    )
