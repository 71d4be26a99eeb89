digest("anfis", {"anfis": ANFIS, "target": REFERENCE_TARGET}, "reference_table")


rule anfis:
    input:
        table=f"{OUT}/reference_table/table.nc",
        grid=f"{OUT}/reference_table/grid.nc",
    output:
        model=f"{OUT}/anfis/model.nc",
        fis=f"{OUT}/anfis/model.fis",
        training=f"{OUT}/anfis/training.nc",
        rules=f"{OUT}/anfis/rules.txt",
        table=report(
            f"{OUT}/anfis/rules.md",
            caption="../report/anfis_rules.rst",
            category="ANFIS",
            subcategory="Model",
            labels={"figure": "the rule base as a table"},
        ),
        membership=report(
            f"{OUT}/figures/anfis_membership.png",
            caption="../report/anfis_membership.rst",
            category="ANFIS",
            subcategory="Model",
            labels={"figure": "membership functions, trained and initial"},
        ),
        errors=report(
            f"{OUT}/figures/anfis_training.png",
            caption="../report/anfis_training.rst",
            category="ANFIS",
            subcategory="Training",
            labels={
                "figure": "training and checking error per epoch; predicted against optimal C"
            },
        ),
        selection=report(
            f"{OUT}/figures/anfis_selection.png",
            caption="../report/anfis_selection.rst",
            category="ANFIS",
            subcategory="Training",
            labels={
                "figure": "structure chosen by cross-validation; against the baselines"
            },
        ),
    log:
        f"{OUT}/logs/anfis.log",
    benchmark:
        f"{OUT}/benchmarks/anfis.tsv"
    priority: 2  # the study's longest chains first: docs/getting-started.md
    conda:
        ENV
    threads: config["anfis"]["threads"]
    params:
        digest=DIGESTS["anfis"],
        expects=expects(
            {
                f"{OUT}/reference_table/table.nc": "reference_table",
                f"{OUT}/reference_table/grid.nc": "reference_table",
            }
        ),
        anfis=ANFIS,
        target=REFERENCE_TARGET,
    script:
        "../scripts/anfis_train.py"
