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
    conda:
        ENV
    params:
        digest=DIGESTS["payload_table"],
        payload=PAYLOAD_TABLE,
        camera=PAYLOAD_CAMERA,
    script:
        "../scripts/payload_table.py"


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
)


rule payload:
    input:
        cases=f"{OUT}/excitation/cases.nc",
        table=f"{OUT}/payload/table.nc",
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
    priority: 1  # the study's longest chains first: docs/getting-started.md
    conda:
        ENV
    threads: config["payload"]["threads"]
    params:
        digest=DIGESTS["payload"],
        expects=expects(
            {
                f"{OUT}/excitation/cases.nc": "excitation",
                f"{OUT}/payload/table.nc": "payload_table",
            }
        ),
        payload=PAYLOAD,
        sources=PAYLOAD_SOURCES,
        camera=CAMERA,
        platform=PLATFORM_MODEL,
    script:
        "../scripts/payload.py"
