HELICOPTER_SENSITIVITY = config["helicopter"]["sensitivity"]
# one run per value: "baseline" and "<parameter>=<value>" (uavdamp.helicopter.sensitivity.parse_run_name reads them),
# sorted by parameter and value: the one job's params list them, and the config's key order must not rerun it
SENSITIVITY_RUNS = ["baseline"] + [
    f"{parameter}={value:g}"
    for parameter, value in sorted(
        (p, float(v))
        for p, values in HELICOPTER_SENSITIVITY["parameters"].items()
        for v in values
    )
]


digest("helicopter_run", {"helicopter": HELICOPTER_RUN})


rule helicopter_run:
    output:
        f"{OUT}/helicopter/runs/{{rotor}}.nc",
    log:
        f"{OUT}/logs/helicopter_run_{{rotor}}.log",
    benchmark:
        f"{OUT}/benchmarks/helicopter_run_{{rotor}}.tsv"
    wildcard_constraints:
        rotor="|".join(VACUUM_RUNS),
    priority: 3  # the study's longest chains first: docs/getting-started.md
    conda:
        ENV
    params:
        digest=DIGESTS["helicopter_run"],
        helicopter=HELICOPTER_RUN,
    script:
        "../scripts/helicopter_run.py"


digest("helicopter_flight", {"helicopter": FLIGHT_RUN})


rule helicopter_flight:
    output:
        run=f"{OUT}/helicopter/runs/{{flight}}.nc",
        trim=f"{OUT}/helicopter/trims/{{flight}}.nc",
    log:
        f"{OUT}/logs/helicopter_flight_{{flight}}.log",
    benchmark:
        f"{OUT}/benchmarks/helicopter_flight_{{flight}}.tsv"
    wildcard_constraints:
        flight="hover|forward",
    priority: 3  # the study's longest chains first: docs/getting-started.md
    conda:
        ENV
    params:
        digest=DIGESTS["helicopter_flight"],
        helicopter=FLIGHT_RUN,
    script:
        "../scripts/helicopter_flight.py"


digest(
    "helicopter_trim",
    {"helicopter": FLIGHT_RUN, "flights": FLIGHT_RUNS},
    "helicopter_flight",
)


rule helicopter_trim:
    input:
        trims=expand(f"{OUT}/helicopter/trims/{{flight}}.nc", flight=FLIGHT_RUNS),
    output:
        f"{OUT}/helicopter/trim.nc",
    log:
        f"{OUT}/logs/helicopter_trim.log",
    conda:
        ENV
    params:
        digest=DIGESTS["helicopter_trim"],
        expects=expects(
            {
                f"{OUT}/helicopter/trims/{f}.nc": "helicopter_flight"
                for f in FLIGHT_RUNS
            }
        ),
        helicopter=FLIGHT_RUN,
        flights=FLIGHT_RUNS,
    script:
        "../scripts/helicopter_trim.py"


digest(
    "helicopter_vibration",
    {
        "helicopter": HELICOPTER_RUN,
        "spectrum": canonical(config["helicopter"]["spectrum"]),
        "rotors": ROTORS,
    },
    *{RUN_RULE[r] for r in ROTORS},
)


rule helicopter_vibration:
    input:
        runs=expand(f"{OUT}/helicopter/runs/{{rotor}}.nc", rotor=ROTORS),
    output:
        vibration=f"{OUT}/helicopter/vibration.nc",
        figure=report(
            f"{OUT}/figures/fuselage_vibration.png",
            caption="../report/fuselage_vibration.rst",
            category="Helicopter",
            subcategory="Vibration",
            labels={
                "figure": "the fuselage's motion at the mount and its spectra (the paper's Fig. 3)"
            },
        ),
    log:
        f"{OUT}/logs/helicopter_vibration.log",
    conda:
        ENV
    params:
        digest=DIGESTS["helicopter_vibration"],
        expects=expects({f"{OUT}/helicopter/runs/{r}.nc": RUN_RULE[r] for r in ROTORS}),
        helicopter=HELICOPTER_RUN,
        spectrum=canonical(config["helicopter"]["spectrum"]),
        rotors=ROTORS,
    script:
        "../scripts/helicopter_vibration.py"


digest(
    "helicopter_campbell",
    {
        "helicopter": HELICOPTER_RUN,
        "campbell": canonical(config["helicopter"]["campbell"]),
    },
)


rule helicopter_campbell:
    output:
        campbell=f"{OUT}/helicopter/campbell.nc",
        figure=report(
            f"{OUT}/figures/helicopter_campbell.png",
            caption="../report/helicopter_campbell.rst",
            category="Helicopter",
            subcategory="Modes",
            labels={"figure": "Campbell diagram of the balanced helicopter"},
        ),
    log:
        f"{OUT}/logs/helicopter_campbell.log",
    benchmark:
        f"{OUT}/benchmarks/helicopter_campbell.tsv"
    conda:
        ENV
    params:
        digest=DIGESTS["helicopter_campbell"],
        helicopter=HELICOPTER_RUN,
        campbell=canonical(config["helicopter"]["campbell"]),
    script:
        "../scripts/helicopter_campbell.py"


digest(
    "helicopter_sensitivity_run",
    {
        "helicopter": (
            HELICOPTER_RUN
            if HELICOPTER_SENSITIVITY["flight"] == "vacuum"
            else FLIGHT_RUN
        ),
        "duration_s": HELICOPTER_SENSITIVITY["duration_s"],
        "flight": HELICOPTER_SENSITIVITY["flight"],
    },
)


# every run in one job (each run as a job of its own paid a process start of about 1.5 s: 15 of them in the study)
rule helicopter_sensitivity_run:
    output:
        expand(f"{OUT}/helicopter/sensitivity/{{run}}.nc", run=SENSITIVITY_RUNS),
    log:
        f"{OUT}/logs/helicopter_sensitivity_run.log",
    benchmark:
        f"{OUT}/benchmarks/helicopter_sensitivity_run.tsv"
    priority: 1  # 39 s: started before the short jobs, not after them (docs/getting-started.md)
    conda:
        ENV
    params:
        digest=DIGESTS["helicopter_sensitivity_run"],
        helicopter=(
            HELICOPTER_RUN
            if HELICOPTER_SENSITIVITY["flight"] == "vacuum"
            else FLIGHT_RUN
        ),
        duration_s=HELICOPTER_SENSITIVITY["duration_s"],
        flight=HELICOPTER_SENSITIVITY["flight"],
        runs=SENSITIVITY_RUNS,
    script:
        "../scripts/helicopter_sensitivity_run.py"


digest(
    "helicopter_sensitivity",
    {
        "sensitivity": canonical(HELICOPTER_SENSITIVITY),
        "spectrum": canonical(config["helicopter"]["spectrum"]),
        "helicopter": HELICOPTER_RUN,
    },
    "helicopter_sensitivity_run",
)


rule helicopter_sensitivity:
    input:
        runs=expand(f"{OUT}/helicopter/sensitivity/{{run}}.nc", run=SENSITIVITY_RUNS),
    output:
        sensitivity=f"{OUT}/helicopter/sensitivity.nc",
        figure=report(
            f"{OUT}/figures/helicopter_sensitivity.png",
            caption="../report/helicopter_sensitivity.rst",
            category="Helicopter",
            subcategory="Sensitivity",
            labels={"figure": "dominant lines against each uncertain parameter"},
        ),
    log:
        f"{OUT}/logs/helicopter_sensitivity.log",
    conda:
        ENV
    params:
        digest=DIGESTS["helicopter_sensitivity"],
        expects=expects(
            {
                f"{OUT}/helicopter/sensitivity/{r}.nc": "helicopter_sensitivity_run"
                for r in SENSITIVITY_RUNS
            }
        ),
        sensitivity=canonical(HELICOPTER_SENSITIVITY),
        spectrum=canonical(config["helicopter"]["spectrum"]),
        helicopter=HELICOPTER_RUN,
    script:
        "../scripts/helicopter_sensitivity.py"
