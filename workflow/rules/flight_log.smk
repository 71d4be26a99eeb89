# A measured flight -> the mount's motion (NetCDF) and its PSD figure; a study case or benchmark scenario names it.
rule flight_log:
    input:
        log=lambda wc: config["flight_logs"][wc.name]["path"],
    output:
        motion=f"{OUT}/flight_logs/{{name}}.nc",
        figure=report(
            f"{OUT}/figures/flight_logs/{{name}}.png",
            caption="../report/flight_log.rst",
            category="Flight logs",
        ),
    log:
        f"{OUT}/logs/flight_logs/{{name}}.log",
    benchmark:
        f"{OUT}/benchmarks/flight_logs/{{name}}.tsv"
    conda:
        ENV
    params:
        source=lambda wc: canonical(config["flight_logs"][wc.name]),
    script:
        "../scripts/flight_log.py"
