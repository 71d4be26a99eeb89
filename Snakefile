# uavdamp: semi-active vibration isolation of a UAV camera platform (after Marichal et al. 2014).
# Thin on purpose: stages live in workflow/rules/*.smk, logic in src/uavdamp.
from snakemake.utils import min_version, validate

import sys

from uavdamp import budget
from uavdamp.checks import check_config
from uavdamp.workflow import export_provenance

min_version("9.0")


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


validate(config, "workflow/schemas/config.schema.yaml")
# values against each other and the cost estimate, before any job
print(budget.summary(check_config(config)), file=sys.stderr)
export_provenance(workflow.configfiles, workflow.basedir)


scattergather:
    reference_table=config["reference_table"]["n_chunks"],


include: "workflow/rules/common.smk"
include: "workflow/rules/helicopter.smk"
include: "workflow/rules/platform.smk"
include: "workflow/rules/reference_table.smk"
include: "workflow/rules/anfis.smk"
include: "workflow/rules/study.smk"
include: "workflow/rules/benchmark.smk"


# every output of every rule of the study, so that any deleted file is rebuilt (tests/test_rebuild.py); the
# controller benchmark is its own target below (about 20 min on 2 cores)
rule all:
    default_target: True
    input:
        expand(rules.helicopter_run.output, rotor=RUNS),
        rules.helicopter_vibration.output,
        rules.helicopter_campbell.output,
        expand(rules.helicopter_sensitivity_run.output, run=SENSITIVITY_RUNS),
        rules.helicopter_sensitivity.output,
        rules.platform_modes.output,
        gather.reference_table(rules.reference_table_chunk.output[0]),
        rules.reference_table.output,
        rules.anfis.output,
        rules.excitation.output,
        rules.study.output,


# the controller benchmark over many scenarios: `snakemake -j2 benchmark`
rule benchmark:
    input:
        expand(rules.benchmark_scenario.output, scenario=BENCHMARK_SCENARIOS),
        BENCHMARK_TUNED,
        expand(rules.benchmark_run.output, scenario=BENCHMARK_SCENARIOS),
        rules.benchmark_gather.output,
