ROTORS = ["balanced", "imbalanced"]


def helicopter_model_config():
    """The helicopter section less the spectrum options, which do not change a run."""
    return {k: v for k, v in config["helicopter"].items() if k != "spectrum"}


rule helicopter_run:
    output:
        "reports/helicopter/runs/{rotor}.nc",
    params:
        helicopter=helicopter_model_config(),
    log:
        "reports/logs/helicopter_run_{rotor}.log",
    benchmark:
        "reports/benchmarks/helicopter_run_{rotor}.tsv"
    wildcard_constraints:
        rotor="|".join(ROTORS),
    script:
        "../scripts/helicopter_run.py"


rule helicopter_vibration:
    input:
        runs=expand("reports/helicopter/runs/{rotor}.nc", rotor=ROTORS),
    output:
        vibration="reports/helicopter/vibration.nc",
        figure="reports/figures/fuselage_vibration.png",
    params:
        helicopter=config["helicopter"],
        rotors=ROTORS,
    log:
        "reports/logs/helicopter_vibration.log",
    script:
        "../scripts/helicopter_vibration.py"
