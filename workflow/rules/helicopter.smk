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
        helicopter=HELICOPTER_MODEL,
    script:
        "../scripts/helicopter_run.py"


rule helicopter_vibration:
    input:
        runs=expand("reports/helicopter/runs/{rotor}.nc", rotor=ROTORS),
    output:
        vibration="reports/helicopter/vibration.nc",
        figure="reports/figures/fuselage_vibration.png",
    log:
        "reports/logs/helicopter_vibration.log",
    conda:
        ENV
    params:
        helicopter=HELICOPTER,
        rotors=ROTORS,
    script:
        "../scripts/helicopter_vibration.py"
