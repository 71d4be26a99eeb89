"""Snakemake script: the flight runs' trims -> reports/helicopter/trim.nc (one row per flight condition)."""

import xarray as xr

from uavdamp import integrity, io, workflow

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
flights = snakemake.params.flights
trims = [io.open_dataset(path) for path in snakemake.input.trims]
histories = {f"trim_history_{f}": t.attrs.get("trim_history", "[]") for f, t in zip(flights, trims, strict=True)}
ds = xr.concat(trims, dim=xr.DataArray(flights, dims="flight"), combine_attrs="override")
ds["flight"].attrs = {"units": "1", "long_name": "flight condition"}
ds.attrs = histories
workflow.log_info(f"trim:\n{ds.to_dataframe().T}")
command = workflow.snakemake_command(snakemake)
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.write_netcdf(ds, snakemake.output[0], snakemake.params.helicopter, section="helicopter", command=command)
