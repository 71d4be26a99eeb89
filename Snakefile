# uavdamp: semi-active vibration isolation of a UAV camera platform (after Marichal et al. 2014).
# Thin on purpose: stages live in workflow/rules/*.smk, logic in src/uavdamp.
from snakemake.utils import min_version, validate

from uavdamp.checks import check_config
from uavdamp.workflow import export_provenance

min_version("9.0")


configfile: "config/config.yaml"


validate(config, "workflow/schemas/config.schema.yaml")
check_config(config)  # values against each other, before any job
export_provenance(workflow.configfiles, workflow.basedir)


scattergather:
    reference_table=config["reference_table"]["n_chunks"],


rule all:
    default_target: True
    input:
        "reports/helicopter/vibration.nc",
        "reports/figures/fuselage_vibration.png",
        "reports/helicopter/campbell.nc",
        "reports/figures/helicopter_campbell.png",
        "reports/helicopter/sensitivity.nc",
        "reports/figures/helicopter_sensitivity.png",
        "reports/platform/modes.nc",
        "reports/figures/platform_response.png",
        "reports/reference_table/table.nc",
        "reports/figures/reference_table.png",
        "reports/anfis/model.nc",
        "reports/study/comparison.nc",
        "reports/benchmark/criteria.nc",


include: "workflow/rules/common.smk"
include: "workflow/rules/helicopter.smk"
include: "workflow/rules/platform.smk"
include: "workflow/rules/reference_table.smk"
include: "workflow/rules/anfis.smk"
include: "workflow/rules/study.smk"
include: "workflow/rules/benchmark.smk"
