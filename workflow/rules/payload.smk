# What the six-axis isolator's best damping depends on for the gimbal: the reference table's construct on the
# payload, in closed form, per mount DOF, frequency, element stiffness and damping (src/uavdamp/study/payload_table.py).
PAYLOAD_TABLE = canonical(
    {k: config["payload"][k] for k in ("gimbal", "six_axis", "table")}
)
PAYLOAD_CAMERA = canonical(
    {k: config["platform"]["structure"][k] for k in ("camera_mass_kg", "camera_size_m")}
)  # the one camera every payload carries: the rest of the structure is the paper's head
digest("payload_table", {"payload": PAYLOAD_TABLE, "camera": PAYLOAD_CAMERA})


rule payload_table:
    output:
        table=f"{OUT}/payload/table.nc",
        figure=report(
            f"{OUT}/figures/payload_table.png",
            caption="../report/payload_table.rst",
            category="Payload",
            labels={"figure": "the six-axis isolator's best damping for the gimbal"},
        ),
    log:
        f"{OUT}/logs/payload_table.log",
    benchmark:
        f"{OUT}/benchmarks/payload_table.tsv"
    priority: 3  # the study's longest chains first: docs/getting-started.md
    conda:
        ENV
    params:
        digest=DIGESTS["payload_table"],
        payload=PAYLOAD_TABLE,
        camera=PAYLOAD_CAMERA,
    script:
        "../scripts/payload_table.py"


# The paper's ANFIS on the payload: [f_a, f_b, K] -> C learnt from the payload table with the anfis section's options
# (src/uavdamp/study/payload_anfis.py); the payload stage runs it as the law `anfis`.
PAYLOAD_ANFIS = canonical(
    {
        "anfis": config["payload"]["anfis"],
        "max_decay_time_s": config["payload"]["schedule"]["max_decay_time_s"],
    }
)
digest("payload_anfis", {"payload": PAYLOAD_ANFIS, "anfis": ANFIS}, "payload_table")


rule payload_anfis:
    input:
        table=f"{OUT}/payload/table.nc",
    output:
        model=f"{OUT}/payload/anfis_model.nc",
        training=f"{OUT}/payload/anfis_training.nc",
        rules=f"{OUT}/payload/anfis_rules.txt",
        figure=report(
            f"{OUT}/figures/payload_anfis_training.png",
            caption="../report/payload_anfis.rst",
            category="Payload",
            labels={
                "figure": "the payload ANFIS: training and checking error, predicted against best C"
            },
        ),
    log:
        f"{OUT}/logs/payload_anfis.log",
    benchmark:
        f"{OUT}/benchmarks/payload_anfis.tsv"
    priority: 2  # the study's longest chains first: docs/getting-started.md
    conda:
        ENV
    threads: config["anfis"]["threads"]
    params:
        digest=DIGESTS["payload_anfis"],
        expects=expects({f"{OUT}/payload/table.nc": "payload_table"}),
        payload=PAYLOAD_ANFIS,
        anfis=ANFIS,
    script:
        "../scripts/payload_anfis.py"


# Which payload and isolator keep the camera sharp: the paper's head, the same head balanced and a gyro-stabilised
# gimbal, each on a rigid, the paper's Y-Z and a six-axis isolator, at constant damping candidates, on the study's
# cases and the stated sources payload.sources names (src/uavdamp/study/payload.py).
PAYLOAD = canonical(
    {k: v for k, v in config["payload"].items() if k != "threads"}
)  # its threads change no number: not a parameter
PAYLOAD_SOURCES = canonical(
    {n: config["sources"][n] for n in config["payload"]["sources"]}
)
digest(
    "payload",
    {
        "payload": PAYLOAD,
        "sources": PAYLOAD_SOURCES,
        "camera": CAMERA,
        "platform": PLATFORM_MODEL,
    },
    "excitation",
    "payload_table",
    "payload_anfis",
)


rule payload:
    input:
        cases=f"{OUT}/excitation/cases.nc",
        table=f"{OUT}/payload/table.nc",
        model=f"{OUT}/payload/anfis_model.nc",
    output:
        comparison=f"{OUT}/payload/comparison.nc",
        design=f"{OUT}/payload/design.nc",
        figure=report(
            f"{OUT}/figures/payload_line_of_sight.png",
            caption="../report/payload.rst",
            category="Payload",
            labels={"figure": "line of sight per payload, mount and damping"},
        ),
        transmissibility=report(
            f"{OUT}/figures/payload_transmissibility.png",
            caption="../report/payload_transmissibility.rst",
            category="Payload",
            labels={
                "figure": "mount motion to line of sight per mount, fixed camera or gimbal"
            },
        ),
    log:
        f"{OUT}/logs/payload.log",
    benchmark:
        f"{OUT}/benchmarks/payload.tsv"
    priority: 3  # the study's longest chains first: docs/getting-started.md
    conda:
        ENV
    threads: config["payload"]["threads"]
    params:
        digest=DIGESTS["payload"],
        expects=expects(
            {
                f"{OUT}/excitation/cases.nc": "excitation",
                f"{OUT}/payload/table.nc": "payload_table",
                f"{OUT}/payload/anfis_model.nc": "payload_anfis",
            }
        ),
        payload=PAYLOAD,
        sources=PAYLOAD_SOURCES,
        camera=CAMERA,
        platform=PLATFORM_MODEL,
    script:
        "../scripts/payload.py"
