HELICOPTER_SENSITIVITY = config["helicopter"]["sensitivity"]
# one run per value: "baseline" and "<parameter>=<value>" (uavdamp.sensitivity.parse_run_name reads them)
SENSITIVITY_RUNS = ["baseline"] + [
    f"{parameter}={float(value):g}"
    for parameter, values in HELICOPTER_SENSITIVITY["parameters"].items()
    for value in values
]


rule helicopter_run:
    output:
        f"{OUT}/helicopter/runs/{{rotor}}.nc",
    log:
        f"{OUT}/logs/helicopter_run_{{rotor}}.log",
    benchmark:
        f"{OUT}/benchmarks/helicopter_run_{{rotor}}.tsv"
    wildcard_constraints:
        rotor="|".join(VACUUM_RUNS),
    conda:
        ENV
    params:
        helicopter=HELICOPTER_RUN,
    script:
        "../scripts/helicopter_run.py"


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
    conda:
        ENV
    params:
        helicopter=FLIGHT_RUN,
    script:
        "../scripts/helicopter_flight.py"


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
        helicopter=FLIGHT_RUN,
        flights=FLIGHT_RUNS,
    script:
        "../scripts/helicopter_trim.py"


rule helicopter_vibration:
    input:
        runs=expand(f"{OUT}/helicopter/runs/{{rotor}}.nc", rotor=ROTORS),
    output:
        vibration=f"{OUT}/helicopter/vibration.nc",
        figure=report(
            f"{OUT}/figures/fuselage_vibration.png",
            caption="../report/fuselage_vibration.rst",
            category="Helicopter",
        ),
    log:
        f"{OUT}/logs/helicopter_vibration.log",
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
        campbell=f"{OUT}/helicopter/campbell.nc",
        figure=report(
            f"{OUT}/figures/helicopter_campbell.png",
            caption="../report/helicopter_campbell.rst",
            category="Helicopter",
        ),
    log:
        f"{OUT}/logs/helicopter_campbell.log",
    benchmark:
        f"{OUT}/benchmarks/helicopter_campbell.tsv"
    conda:
        ENV
    params:
        helicopter=HELICOPTER_RUN,
        campbell=canonical(config["helicopter"]["campbell"]),
    script:
        "../scripts/helicopter_campbell.py"


rule helicopter_sensitivity_run:
    output:
        f"{OUT}/helicopter/sensitivity/{{run}}.nc",
    log:
        f"{OUT}/logs/helicopter_sensitivity/{{run}}.log",
    benchmark:
        f"{OUT}/benchmarks/helicopter_sensitivity/{{run}}.tsv"
    wildcard_constraints:
        run="baseline|[a-z_]+=[-+.0-9e]+",
    conda:
        ENV
    params:
        helicopter=(
            HELICOPTER_RUN
            if HELICOPTER_SENSITIVITY["flight"] == "vacuum"
            else FLIGHT_RUN
        ),
        duration_s=HELICOPTER_SENSITIVITY["duration_s"],
        flight=HELICOPTER_SENSITIVITY["flight"],
    script:
        "../scripts/helicopter_sensitivity_run.py"


rule helicopter_sensitivity:
    input:
        runs=expand(f"{OUT}/helicopter/sensitivity/{{run}}.nc", run=SENSITIVITY_RUNS),
    output:
        sensitivity=f"{OUT}/helicopter/sensitivity.nc",
        figure=report(
            f"{OUT}/figures/helicopter_sensitivity.png",
            caption="../report/helicopter_sensitivity.rst",
            category="Helicopter",
        ),
    log:
        f"{OUT}/logs/helicopter_sensitivity.log",
    conda:
        ENV
    params:
        sensitivity=canonical(HELICOPTER_SENSITIVITY),
        spectrum=canonical(config["helicopter"]["spectrum"]),
        helicopter=HELICOPTER_RUN,
    script:
        "../scripts/helicopter_sensitivity.py"
