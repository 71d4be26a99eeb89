# A measured flight -> the mount's motion (NetCDF) and its PSD figure; a study case or benchmark scenario names it.
# The log file is an input and its SHA-256 a parameter: a changed file reruns the job by content, whatever its
# modification time (the config check refuses a missing file, naming flight_logs.NAME.path, before any job).
for _name in FLIGHT_LOGS:
    digest(f"flight_log:{_name}", canonical(config["flight_logs"][_name]))


rule flight_log:
    input:
        log=lambda wc: config["flight_logs"][wc.name]["path"],
    output:
        motion=f"{OUT}/flight_logs/{{name}}.nc",
        figure=report(
            f"{OUT}/figures/flight_logs/{{name}}.png",
            caption="../report/flight_log.rst",
            category="Flight logs",
            subcategory="Spectra",
            labels={"figure": "acceleration and rate spectra of the log {name}"},
        ),
    log:
        f"{OUT}/logs/flight_logs/{{name}}.log",
    benchmark:
        f"{OUT}/benchmarks/flight_logs/{{name}}.tsv"
    conda:
        ENV
    params:
        digest=lambda wc: DIGESTS[f"flight_log:{wc.name}"],
        source=lambda wc: canonical(config["flight_logs"][wc.name]),
        log_sha256=lambda wc: integrity.file_sha256(
            config["flight_logs"][wc.name]["path"]
        ),
    script:
        "../scripts/flight_log.py"
