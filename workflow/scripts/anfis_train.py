"""Snakemake script: select and train the ANFIS, fit the baselines -> model, training record, rules, figures."""

from uavdamp import anfis, io, workflow
from uavdamp.plots.anfis import membership_figure, selection_figure, training_figure
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
config = snakemake.params.anfis
options = parse(anfis.AnfisOptions, config, "anfis")
table, grid = io.open_dataset(snakemake.input.table), io.open_dataset(snakemake.input.grid)
criterion, window = snakemake.params.target  # the reference table's criterion and window the ANFIS learns
model, record, seconds = anfis.train(table, grid, options, (criterion, window))
workflow.log_info(f"target: optimal C of the {criterion} criterion, {window} window")
a = record.attrs
cv = "; ".join(
    f"{lab}: {m:.4g} +- {s:.2g}"
    for lab, m, s in zip(
        record.candidate_label.values, record.cv_rmse_mean.values, record.cv_rmse_std.values, strict=True
    )
)
workflow.log_info(
    f"{a['cv_folds']}-fold cross-validated RMSE of {model.anfis.output_name} on the training rows: {cv}; "
    f"selected {a['selected_candidate']}"
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
command = workflow.snakemake_command(snakemake)
io.save_figure(membership_figure(model.anfis), snakemake.output.membership)
io.save_figure(training_figure(record), snakemake.output.errors)
io.save_figure(selection_figure(record), snakemake.output.selection)
io.write_text(rules + "\n", snakemake.output.rules)
io.write_netcdf(record, snakemake.output.training, config, section="anfis", command=command)
io.write_netcdf(model.to_dataset(), snakemake.output.model, config, section="anfis", command=command)
