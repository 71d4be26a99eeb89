HELICOPTER_SENSITIVITY = config["helicopter"]["sensitivity"]
# one run per value: "baseline" and "<parameter>=<value>" (uavdamp.sensitivity.parse_run_name reads them)
SENSITIVITY_RUNS = ["baseline"] + [
    f"{parameter}={float(value):g}"
    for parameter, values in HELICOPTER_SENSITIVITY["parameters"].items()
    for value in values
]


rule helicopter_run:
    output:
        "reports/helicopter/runs/{rotor}.nc",
    log:
        "reports/logs/helicopter_run_{rotor}.log",
    benchmark:
        "reports/benchmarks/helicopter_run_{rotor}.tsv"
    wildcard_constraints:
        rotor="|".join(RUNS),
    conda:
        ENV
    params:
        helicopter=HELICOPTER_RUN,
    script:
        "../scripts/helicopter_run.py"


rule helicopter_vibration:
    input:
        runs=expand("reports/helicopter/runs/{rotor}.nc", rotor=ROTORS),
    output:
        vibration="reports/helicopter/vibration.nc",
        figure=report(
            "reports/figures/fuselage_vibration.png",
            caption="../report/fuselage_vibration.rst",
            category="Helicopter",
        ),
    log:
        "reports/logs/helicopter_vibration.log",
    conda:
        ENV
    params:
        helicopter=HELICOPTER_RUN,
        spectrum=canonical(config["helicopter"]["spectrum"]),
        rotors=ROTORS,
    script:
        "../scripts/helicopter_vibration.py"


rule helicopter_campbell:
    output:
        campbell="reports/helicopter/campbell.nc",
        figure=report(
            "reports/figures/helicopter_campbell.png",
            caption="../report/helicopter_campbell.rst",
            category="Helicopter",
        ),
    log:
        "reports/logs/helicopter_campbell.log",
    benchmark:
        "reports/benchmarks/helicopter_campbell.tsv"
    conda:
        ENV
    params:
        helicopter=HELICOPTER_RUN,
        campbell=canonical(config["helicopter"]["campbell"]),
    script:
        "../scripts/helicopter_campbell.py"


rule helicopter_sensitivity_run:
    output:
        "reports/helicopter/sensitivity/{run}.nc",
    log:
        "reports/logs/helicopter_sensitivity/{run}.log",
    benchmark:
        "reports/benchmarks/helicopter_sensitivity/{run}.tsv"
    wildcard_constraints:
        run="baseline|[a-z_]+=[-+.0-9e]+",
    conda:
        ENV
    params:
        helicopter=HELICOPTER_RUN,
        duration_s=HELICOPTER_SENSITIVITY["duration_s"],
    script:
        "../scripts/helicopter_sensitivity_run.py"


rule helicopter_sensitivity:
    input:
        runs=expand("reports/helicopter/sensitivity/{run}.nc", run=SENSITIVITY_RUNS),
    output:
        sensitivity="reports/helicopter/sensitivity.nc",
        figure=report(
            "reports/figures/helicopter_sensitivity.png",
            caption="../report/helicopter_sensitivity.rst",
            category="Helicopter",
        ),
    log:
        "reports/logs/helicopter_sensitivity.log",
    conda:
        ENV
    params:
        sensitivity=canonical(HELICOPTER_SENSITIVITY),
        spectrum=canonical(config["helicopter"]["spectrum"]),
        helicopter=HELICOPTER_RUN,
    script:
        "../scripts/helicopter_sensitivity.py"
