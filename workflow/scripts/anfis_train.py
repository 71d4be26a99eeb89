"""Snakemake script: train the ANFIS on the reference table -> model, training record, rules, figures."""

from uavdamp import io, learning, workflow
from uavdamp.plots.anfis import membership_figure, training_figure

workflow.start_log(snakemake.log[0])
options = snakemake.params.anfis
table, grid = io.open_dataset(snakemake.input.table), io.open_dataset(snakemake.input.grid)
model, record = learning.train(table, grid, options)
a = record.attrs
workflow.log_info(f"{a['n_samples']} samples ({a['n_training']} training, {a['n_dropped_nan']} NaN cells dropped), "
            f"{a['n_rules']} rules, best epoch {a['best_epoch']}: C RMSE training {a['train_rmse_final']:.4g}, "
            f"checking {a['check_rmse_final']:.4g} N s/m; checking median relative error "
            f"{a['check_median_relative_error']:.3f}; checking regret mean {a['check_regret_mean']:.4f}, "
            f"max {a['check_regret_max']:.4f}")
rules = model.rules_text()
workflow.log_info("rules:\n" + rules)
command = workflow.snakemake_command(snakemake)
io.save_figure(membership_figure(model.anfis), snakemake.output.membership)
io.save_figure(training_figure(record), snakemake.output.errors)
io.write_text(rules + "\n", snakemake.output.rules)
io.write_netcdf(record, snakemake.output.training, options, section="anfis", command=command)
io.write_netcdf(model.to_dataset(), snakemake.output.model, options, section="anfis", command=command)
