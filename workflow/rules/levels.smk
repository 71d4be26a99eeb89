# Each input's vibration levels at the mount in the field's units: every helicopter run of the vibration stage,
# the study's cases, every stated source and every flight log, per line in g and in/s, as VIBE, and the lateral
# 1/rev against the track-and-balance limit (src/uavdamp/sources/levels_survey.py, docs/stages/levels.md).
LEVELS = canonical(config["levels"])
LEVELS_ROTOR = canonical(
    {
        "omega_rad_s": config["helicopter"]["main_rotor"]["omega_rad_s"],
        "blades": config["helicopter"]["main_rotor"]["n_blades"],
        "tail_omega_rad_s": config["helicopter"]["tail_rotor"]["omega_running_rad_s"],
        "tail_blades": config["helicopter"]["tail_rotor"]["n_blades"],
    }
)
# what each case takes its motion from: its lines are that input's
LEVELS_CASES = canonical(
    {
        name: {k: case[k] for k in ("run", "flight_log", "source") if case.get(k)}
        for name, case in config["study"]["cases"].items()
    }
)
LEVELS_LOG_DESCRIPTIONS = canonical(
    {n: config["flight_logs"][n].get("description", n) for n in FLIGHT_LOGS}
)
digest(
    "levels",
    {
        "levels": LEVELS,
        "rotor": LEVELS_ROTOR,
        "sources": canonical(config["sources"]),
        "cases": LEVELS_CASES,
        "logs": LEVELS_LOG_DESCRIPTIONS,
    },
    *{RUN_RULE[r] for r in ROTORS},
    "excitation",
    *[f"flight_log:{n}" for n in FLIGHT_LOGS],
)


rule levels:
    input:
        runs=expand(f"{OUT}/helicopter/runs/{{rotor}}.nc", rotor=ROTORS),
        cases=f"{OUT}/excitation/cases.nc",
        logs=expand(f"{OUT}/flight_logs/{{name}}.nc", name=FLIGHT_LOGS),
    output:
        levels=f"{OUT}/levels/levels.nc",
        figure=report(
            f"{OUT}/figures/levels.png",
            caption="../report/levels.rst",
            category="Inputs",
            labels={
                "figure": "vibration levels per input: lines, track and balance, VIBE"
            },
        ),
    log:
        f"{OUT}/logs/levels.log",
    benchmark:
        f"{OUT}/benchmarks/levels.tsv"
    conda:
        ENV
    params:
        digest=DIGESTS["levels"],
        expects=expects(
            {
                **{f"{OUT}/helicopter/runs/{r}.nc": RUN_RULE[r] for r in ROTORS},
                f"{OUT}/excitation/cases.nc": "excitation",
                **{
                    f"{OUT}/flight_logs/{n}.nc": f"flight_log:{n}" for n in FLIGHT_LOGS
                },
            }
        ),
        levels=LEVELS,
        rotor=LEVELS_ROTOR,
        sources=canonical(config["sources"]),
        cases=LEVELS_CASES,
        runs=ROTORS,
        logs=FLIGHT_LOGS,
        log_descriptions=LEVELS_LOG_DESCRIPTIONS,
    script:
        "../scripts/levels.py"
