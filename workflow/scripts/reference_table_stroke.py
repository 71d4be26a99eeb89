"""Snakemake script: the stroke budget of the reference table's optimum per (f_y, f_z, K) -> stroke.nc."""

from uavdamp import integrity, io, workflow
from uavdamp.platform import LinearPlant, PlatformParams
from uavdamp.platform.params import StrokeBudget
from uavdamp.platform.stroke import table_stroke_budget
from uavdamp.reference_table import criteria
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
p = snakemake.params
platform = parse(PlatformParams, p.platform, "platform")
budget = parse(StrokeBudget, p.stroke, "platform.stroke")
table = io.open_dataset(snakemake.input.table)
chosen = criteria.select_table(table, table.attrs["criterion"], table.attrs["window"])
ds = table_stroke_budget(budget, LinearPlant.from_params(platform), chosen, float(p.amplitude))
ds.attrs.update(criterion=table.attrs["criterion"], window=table.attrs["window"])
share = ds.stroke_feasible.mean(["freq_y", "freq_z"])
workflow.log_info(
    f"stroke budget ({budget.weight_support}, max {budget.max_stroke} m, {budget.manoeuvre_g} g): static sag per "
    f"stiffness {ds.static_sag.values.round(4).tolist()} m, manoeuvre {ds.manoeuvre_stroke.values.round(4).tolist()} "
    f"m; feasible share of the band per stiffness {share.values.round(3).tolist()}"
)
config = {"platform": {**p.platform, "stroke": p.stroke}, "reference_table": {"amplitude_m": p.amplitude}}
command = workflow.snakemake_command(snakemake)
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.write_netcdf(ds, snakemake.output[0], config, section="reference_table", command=command)
