digest(
    "reference_table_chunk",
    {"grid": REFERENCE_GRID, "camera": CAMERA_OPTICS, "platform": PLATFORM_MODEL},
)


rule reference_table_chunk:
    output:
        f"{OUT}/reference_table/chunks/{{scatteritem}}.nc",
    log:
        f"{OUT}/logs/reference_table/{{scatteritem}}.log",
    benchmark:
        f"{OUT}/benchmarks/reference_table/{{scatteritem}}.tsv"
    priority: 2  # the study's longest chains first: docs/getting-started.md
    conda:
        ENV
    threads: config["reference_table"]["threads"]
    params:
        digest=DIGESTS["reference_table_chunk"],
        grid=REFERENCE_GRID,
        camera=CAMERA_OPTICS,
        platform=PLATFORM_MODEL,
    script:
        "../scripts/reference_table_chunk.py"


digest(
    "reference_table",
    {
        "grid": REFERENCE_GRID,
        "camera": CAMERA_OPTICS,
        "target": REFERENCE_TARGET,
        "platform": PLATFORM_MODEL,
        "verify": canonical(config["reference_table"]["verify"]),
        "flat_tolerance": config["reference_table"]["flat_tolerance"],
    },
    "reference_table_chunk",
)


rule reference_table:
    input:
        chunks=gather.reference_table(
            f"{OUT}/reference_table/chunks/{{scatteritem}}.nc"
        ),
    output:
        grid=f"{OUT}/reference_table/grid.nc",
        table=f"{OUT}/reference_table/table.nc",
        figure=report(
            f"{OUT}/figures/reference_table.png",
            caption="../report/reference_table.rst",
            category="Reference table",
            subcategory="Table",
            labels={
                "figure": "optimal damping, flat band, scheduling gain and spread"
            },
        ),
        criteria=report(
            f"{OUT}/figures/reference_table_criteria.png",
            caption="../report/reference_table_criteria.rst",
            category="Reference table",
            subcategory="Table",
            labels={"figure": "optimal C per criterion and window"},
        ),
    log:
        f"{OUT}/logs/reference_table/gather.log",
    benchmark:
        f"{OUT}/benchmarks/reference_table/gather.tsv"
    priority: 2  # the study's longest chains first: docs/getting-started.md
    conda:
        ENV
    threads: config["reference_table"]["threads"]
    params:
        digest=DIGESTS["reference_table"],
        expects=expects(
            {
                path: "reference_table_chunk"
                for path in gather.reference_table(
                    f"{OUT}/reference_table/chunks/{{scatteritem}}.nc"
                )
            }
        ),
        grid=REFERENCE_GRID,
        camera=CAMERA_OPTICS,
        target=REFERENCE_TARGET,
        platform=PLATFORM_MODEL,
        verify=canonical(config["reference_table"]["verify"]),
        flat_tolerance=config["reference_table"]["flat_tolerance"],
    script:
        "../scripts/reference_table.py"


# the stroke budget of the table's optimum (apart, so that a budget edit reruns this and the study, not the ANFIS)
digest(
    "reference_table_stroke",
    {
        "platform": PLATFORM_MODEL,
        "stroke": canonical(config["platform"]["stroke"]),
        "amplitude": config["reference_table"]["amplitude_m"],
    },
    "reference_table",
)


rule reference_table_stroke:
    input:
        table=rules.reference_table.output.table,
    output:
        f"{OUT}/reference_table/stroke.nc",
    log:
        f"{OUT}/logs/reference_table/stroke.log",
    conda:
        ENV
    params:
        digest=DIGESTS["reference_table_stroke"],
        expects=expects({f"{OUT}/reference_table/table.nc": "reference_table"}),
        platform=PLATFORM_MODEL,
        stroke=canonical(config["platform"]["stroke"]),
        amplitude=config["reference_table"]["amplitude_m"],
    script:
        "../scripts/reference_table_stroke.py"
