"""Snakemake script: select and train the ANFIS, fit the baselines -> model (.nc, .fis), record, rules, figures."""

import numpy as np

from uavdamp import anfis, integrity, io, workflow
from uavdamp.anfis.fis import to_fis
from uavdamp.anfis.rules import rules_markdown
from uavdamp.anfis.training import INPUTS
from uavdamp.plots.anfis import membership_figure, selection_figure, training_figure
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
config = snakemake.params.anfis
options = parse(anfis.AnfisOptions, config, "anfis")
table, grid = io.open_dataset(snakemake.input.table), io.open_dataset(snakemake.input.grid)
criterion, window = snakemake.params.target  # the reference table's criterion and window the ANFIS learns
model, record, seconds = anfis.train(table, grid, options, (criterion, window), n_jobs=snakemake.threads)
workflow.log_info(f"target: optimal C of the {criterion} criterion, {window} window; workers: {snakemake.threads}")
a = record.attrs
rows = [
    f"{str(r.candidate_label.values):<24} {float(r.n_rules):6.1f} {float(r.cv_rmse_mean):.4f} +- "
    f"{float(r.cv_rmse_se):.4f} {float(r.cv_regret_mean):.5f} {float(r.cv_regret_max):.4f}"
    for r in (record.isel(candidate=k) for k in range(record.sizes["candidate"]))
]
workflow.log_info(
    f"{a['cv_folds']}-fold cross-validation on the training rows (candidate, rules, RMSE of "
    f"{model.anfis.output_name} +- standard error, regret mean and max):\n"
    + "\n".join(rows)
    + f"\nselected ({a['selection_rule']}): {a['selected_candidate']}; lowest CV RMSE: {a['best_cv_candidate']}"
)
workflow.log_info(
    f"{a['n_samples']} samples ({a['n_training']} training, {a['n_dropped_nan']} NaN cells dropped), "
    f"{a['n_rules']} rules, best epoch {a['best_epoch']} (epoch selection: {a['epoch_selection']}): "
    f"C RMSE training {a['train_rmse_final']:.4g}, checking {a['check_rmse_final']:.4g} N s/m; checking "
    f"median relative error {a['check_median_relative_error']:.3f}; checking regret mean "
    f"{a['check_regret_mean']:.4f}, max {a['check_regret_max']:.4f}"
)
for name in record.model.values:
    s = record.sel(model=name)
    workflow.log_info(
        f"{name:>6}: checking RMSE {float(s.check_rmse_target):.4g} ({s.check_rmse_target.attrs['units']}), "
        f"{float(s.check_rmse_damping):.4g} N s/m, median relative error "
        f"{float(s.check_median_relative_error):.3f}, regret mean {float(s.check_regret_mean):.4f} "
        f"max {float(s.check_regret_max):.4f}; fit {seconds[name]:.3f} s"
    )
workflow.log_info("fit times (s): " + ", ".join(f"{k} {v:.3f}" for k, v in seconds.items()))
rules = model.rules_text()
workflow.log_info("rules:\n" + rules)
cells = np.column_stack([record[name].values for name in INPUTS])
command = workflow.snakemake_command(snakemake)
with job.writing():  # under the output's lock; a later run's output is never replaced
    io.save_figure(membership_figure(model), snakemake.output.membership)
    io.save_figure(training_figure(record), snakemake.output.errors)
    io.save_figure(selection_figure(record), snakemake.output.selection)
    io.write_text(rules + "\n", snakemake.output.rules)
    title = f"ANFIS rule base: optimal C, {criterion} criterion, {window} window"
    io.write_text(rules_markdown(model, cells, title), snakemake.output.table)
    io.write_text(to_fis(model), snakemake.output.fis)
    io.write_netcdf(record, snakemake.output.training, config, section="anfis", command=command)
    io.write_netcdf(model.to_dataset(), snakemake.output.model, config, section="anfis", command=command)
