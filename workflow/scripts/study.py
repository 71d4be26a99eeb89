"""Snakemake script: the closed-loop study -> comparison.nc and the paper-style figures."""

from pathlib import Path

from uavdamp import integrity, io, workflow
from uavdamp.anfis import DampingPredictor
from uavdamp.config.load import study_options
from uavdamp.platform import PlatformParams
from uavdamp.platform.params import StrokeBudget
from uavdamp.plots import study as plots
from uavdamp.settings import parse
from uavdamp.study import comparison as study

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
workflow.load_plugins(snakemake)  # before any strategy is named
p = snakemake.params
cfg, fig = p.study, p.figures
options = study_options(cfg, p.camera)
platform = parse(PlatformParams, p.platform, "platform")
budget = parse(StrokeBudget, p.stroke, "platform.stroke")
cases = io.open_dataset(snakemake.input.cases)
model = DampingPredictor.from_dataset(io.open_dataset(snakemake.input.model))
ds = study.run_study(cases, platform, model, options, progress=True, budget=budget)
if p.extrapolation:  # allowed by study.allow_extrapolation (uavdamp.config.checks.extrapolation)
    ds.attrs["extrapolation_warning"] = "; ".join(p.extrapolation)
    workflow.log_info(f"warning: {ds.attrs['extrapolation_warning']}")
if ds.attrs.get("band_edge_warning"):  # uavdamp.study.comparison.band_edge_warning
    workflow.log_info(f"warning: {ds.attrs['band_edge_warning']}")
scalars = [
    v for v in ds.data_vars if "strategy" in ds[v].dims and set(ds[v].dims) <= {"case", "stiffness", "strategy", "axis"}
]
for name in scalars:
    workflow.log_info(f"{name} ({ds[name].attrs['units']}):\n{ds[name].to_dataframe().to_string()}")
k_paper = float(ds.stiffness[0])
early = {"early_s": options.early_s}
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.save_figure(plots.rigid_mount_figure(ds, fig["case_1"], "y", **early), snakemake.output.fig10)
    io.save_figure(plots.passive_vs_anfis_figure(ds, fig["case_1"], "y", k_paper, **early), snakemake.output.fig11)
    io.save_figure(plots.tracked_frequency_figure(ds, fig["case_2"], "z"), snakemake.output.fig12)
    io.save_figure(plots.passive_vs_anfis_figure(ds, fig["case_2"], "z", k_paper, **early), snakemake.output.fig13)
    io.save_figure(plots.blur_distribution_figure(ds), snakemake.output.blur)
    io.save_figure(plots.sharp_fraction_figure(ds), snakemake.output.sharp)
    figures = {Path(path).stem: path for path in snakemake.output.strategies}  # one named output per case
    assert sorted(figures) == sorted(map(str, ds.case.values)), (sorted(figures), ds.case.values)
    for case, path in figures.items():
        io.save_figure(plots.strategies_figure(ds, case, **early), path)
    config = {"study": {**cfg, "camera": p.camera}, "platform": {**p.platform, "stroke": p.stroke}}
    io.write_netcdf(
        ds, snakemake.output.comparison, config, section="study", command=workflow.snakemake_command(snakemake)
    )
