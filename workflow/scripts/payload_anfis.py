"""Snakemake script: the paper's ANFIS on the payload table -> payload/anfis_model.nc, anfis_training.nc, the rules
in words and the training figure."""

from uavdamp import anfis, integrity, io, workflow
from uavdamp.plots.anfis import training_figure
from uavdamp.settings import parse
from uavdamp.study import payload_anfis

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
p = snakemake.params
options = parse(anfis.AnfisOptions, p.anfis, "anfis")
section = parse(payload_anfis.AnfisPayloadSection, p.payload["anfis"], "payload.anfis")
reference, grid = payload_anfis.reference(
    io.open_dataset(snakemake.input.table), section, p.payload["max_decay_time_s"]
)
model, record, seconds = anfis.train(reference, grid, options, n_jobs=snakemake.threads, inputs=section.inputs)
record.attrs.update(payload_anfis.record_attrs(section, reference, grid))
a = record.attrs
workflow.log_info(
    f"[f_{section.dofs[0]}, f_{section.dofs[1]}, K] -> C: {a['n_samples']} samples ({a['n_training']} training), "
    f"selected {a['selected_candidate']}, {a['n_rules']} rules; best C at the least / largest eligible damping in "
    f"{a['share_at_least_eligible_damping']:.1%} / {a['share_at_largest_eligible_damping']:.1%} of the cells"
)
for name in record.model.values:
    s = record.sel(model=name)
    workflow.log_info(
        f"{name:>6}: checking regret mean {float(s.check_regret_mean):.4f} max {float(s.check_regret_max):.4f}, "
        f"median relative error of C {float(s.check_median_relative_error):.3f}; fit {seconds[name]:.3f} s"
    )
rules = model.rules_text()
workflow.log_info("rules:\n" + rules)
config = {"payload": p.payload, "anfis": p.anfis}
command = workflow.snakemake_command(snakemake)
with job.writing():  # under the outputs' lock; a later run's outputs are never replaced
    io.save_figure(training_figure(record), snakemake.output.figure)
    io.write_text(rules + "\n", snakemake.output.rules)
    io.write_netcdf(record, snakemake.output.training, config, section="payload_anfis", command=command)
    io.write_netcdf(model.to_dataset(), snakemake.output.model, config, section="payload_anfis", command=command)
