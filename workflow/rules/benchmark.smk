# The controller benchmark: one job per scenario input, tuning on the tuning set only (one job per stiffness),
# one job per scenario running every controller, then a gather. Logic in src/uavdamp/{scenarios,benchmark}.py.
from uavdamp.benchmark.loop import BenchmarkOptions
from uavdamp.benchmark.scenarios import ScenarioOptions, flight_log_of, scenario_specs
from uavdamp.benchmark.scenarios import split as benchmark_split

BENCHMARK = config["benchmark"]
BENCHMARK_SCENARIOS = sorted(scenario_specs(TYPED.benchmark))
BENCHMARK_SPLIT = benchmark_split(
    BENCHMARK_SCENARIOS,
    BENCHMARK["split"]["tuning_fraction"],
    BENCHMARK["split"]["seed"],
)
BENCHMARK_TUNING = [n for n in BENCHMARK_SCENARIOS if BENCHMARK_SPLIT[n] == "tuning"]
BENCHMARK_INPUTS = canonical(view(BENCHMARK, ScenarioOptions))
BENCHMARK_RUNS = canonical(view(BENCHMARK, BenchmarkOptions))
BENCHMARK_STIFFNESS = [
    f"{float(k):g}" for k in BENCHMARK["stiffness_n_m"]
]  # one tuning job each
BENCHMARK_TUNED = expand(
    f"{OUT}/benchmark/tuned/K{{stiffness}}.nc", stiffness=BENCHMARK_STIFFNESS
)
BENCHMARK_TRACKING = canonical(config["study"]["tracking"])
# the MR damper, built once (uavdamp.damping.actuation.MRSpec): an input of the jobs that run it
BENCHMARK_MR = [f"{OUT}/benchmark/mr_damper.nc"] if "mr" in BENCHMARK["dampers"] else []
BENCHMARK_CHECKED = list(BENCHMARK["step_check"]["scenarios"])


digest("benchmark_mr_damper", {"mr": canonical(BENCHMARK["mr"])})


rule benchmark_mr_damper:
    output:
        f"{OUT}/benchmark/mr_damper.nc",
    log:
        f"{OUT}/logs/benchmark_mr_damper.log",
    benchmark:
        f"{OUT}/benchmarks/benchmark_mr_damper.tsv"
    conda:
        ENV
    params:
        digest=DIGESTS["benchmark_mr_damper"],
        mr=canonical(BENCHMARK["mr"]),
    script:
        "../scripts/benchmark_mr_damper.py"


for _s in BENCHMARK_SCENARIOS:
    _log = flight_log_of(TYPED.benchmark, _s)
    digest(
        f"benchmark_scenario:{_s}",
        {
            "inputs": BENCHMARK_INPUTS,
            "helicopter": FLIGHT_RUN,
            "platform": PLATFORM_MODEL,
            "source": canonical(
                config["sources"].get(_s, {})
                if _s in BENCHMARK.get("sources", [])
                else {}
            ),
        },
        *([f"flight_log:{_log}"] if _log else []),
    )


rule benchmark_scenario:
    input:
        log=lambda wc: [
            f"{OUT}/flight_logs/{name}.nc"
            for name in [flight_log_of(TYPED.benchmark, wc.scenario)]
            if name
        ],
    output:
        f"{OUT}/benchmark/scenarios/{{scenario}}.nc",
    log:
        f"{OUT}/logs/benchmark_scenario_{{scenario}}.log",
    benchmark:
        f"{OUT}/benchmarks/benchmark_scenario_{{scenario}}.tsv"
    wildcard_constraints:
        scenario="|".join(BENCHMARK_SCENARIOS),
    conda:
        ENV
    params:
        digest=lambda wc: DIGESTS[f"benchmark_scenario:{wc.scenario}"],
        expects=lambda wc: expects(
            {
                f"{OUT}/flight_logs/{name}.nc": f"flight_log:{name}"
                for name in [flight_log_of(TYPED.benchmark, wc.scenario)]
                if name
            }
        ),
        inputs=BENCHMARK_INPUTS,
        helicopter=FLIGHT_RUN,
        platform=PLATFORM_MODEL,
        # a stated source's own keys (sources.NAME) for a source scenario, {} for the others
        source=lambda wc: canonical(
            config["sources"][wc.scenario]
            if wc.scenario in BENCHMARK.get("sources", [])
            else {}
        ),
    script:
        "../scripts/benchmark_scenario.py"


digest(
    "benchmark_tune",
    {
        "runs": BENCHMARK_RUNS,
        "tracking": BENCHMARK_TRACKING,
        "camera": CAMERA,
        "platform": PLATFORM_MODEL,
        "plugins": PLUGINS,
    },
    *[f"benchmark_scenario:{s}" for s in BENCHMARK_TUNING],
    *(["benchmark_mr_damper"] if BENCHMARK_MR else []),
)


rule benchmark_tune:
    input:
        scenarios=expand(
            f"{OUT}/benchmark/scenarios/{{scenario}}.nc", scenario=BENCHMARK_TUNING
        ),
        plugins=PLUGINS,
        plugin_data=PLUGIN_DATA,
        mr=BENCHMARK_MR,
    output:
        f"{OUT}/benchmark/tuned/K{{stiffness}}.nc",
    log:
        f"{OUT}/logs/benchmark_tune_K{{stiffness}}.log",
    benchmark:
        f"{OUT}/benchmarks/benchmark_tune_K{{stiffness}}.tsv"
    wildcard_constraints:
        stiffness="|".join(BENCHMARK_STIFFNESS),
    conda:
        ENV
    params:
        digest=DIGESTS["benchmark_tune"],
        expects=expects(
            {
                **{
                    f"{OUT}/benchmark/scenarios/{s}.nc": f"benchmark_scenario:{s}"
                    for s in BENCHMARK_TUNING
                },
                **{path: "benchmark_mr_damper" for path in BENCHMARK_MR},
            }
        ),
        runs=BENCHMARK_RUNS,
        tracking=BENCHMARK_TRACKING,
        camera=CAMERA,
        platform=PLATFORM_MODEL,
    script:
        "../scripts/benchmark_tune.py"


for _s in BENCHMARK_SCENARIOS:
    digest(
        f"benchmark_run:{_s}",
        {
            "runs": BENCHMARK_RUNS,
            "tracking": BENCHMARK_TRACKING,
            "camera": CAMERA,
            "platform": PLATFORM_MODEL,
            "step_check": _s in BENCHMARK_CHECKED,
            "plugins": PLUGINS,
        },
        f"benchmark_scenario:{_s}",
        "benchmark_tune",
        "anfis",
        "reference_table",
        *(["benchmark_mr_damper"] if BENCHMARK_MR else []),
    )


rule benchmark_run:
    input:
        scenario=f"{OUT}/benchmark/scenarios/{{scenario}}.nc",
        tuned=BENCHMARK_TUNED,
        model=f"{OUT}/anfis/model.nc",
        table=f"{OUT}/reference_table/table.nc",
        plugins=PLUGINS,
        plugin_data=PLUGIN_DATA,
        mr=BENCHMARK_MR,
    output:
        f"{OUT}/benchmark/runs/{{scenario}}.nc",
    log:
        f"{OUT}/logs/benchmark_run_{{scenario}}.log",
    benchmark:
        f"{OUT}/benchmarks/benchmark_run_{{scenario}}.tsv"
    wildcard_constraints:
        scenario="|".join(BENCHMARK_SCENARIOS),
    conda:
        ENV
    params:
        digest=lambda wc: DIGESTS[f"benchmark_run:{wc.scenario}"],
        expects=lambda wc: expects(
            {
                f"{OUT}/benchmark/scenarios/{wc.scenario}.nc": f"benchmark_scenario:{wc.scenario}",
                **{path: "benchmark_tune" for path in BENCHMARK_TUNED},
                f"{OUT}/anfis/model.nc": "anfis",
                f"{OUT}/reference_table/table.nc": "reference_table",
                **{path: "benchmark_mr_damper" for path in BENCHMARK_MR},
            }
        ),
        runs=BENCHMARK_RUNS,
        tracking=BENCHMARK_TRACKING,
        camera=CAMERA,
        platform=PLATFORM_MODEL,
        step_check=lambda wc: wc.scenario in BENCHMARK_CHECKED,
    script:
        "../scripts/benchmark_run.py"


digest(
    "benchmark_gather",
    {
        "split": BENCHMARK_SPLIT,
        "runs": BENCHMARK_RUNS,
        "extrapolation": EXTRAPOLATION["benchmark"],
    },
    *[f"benchmark_run:{s}" for s in BENCHMARK_SCENARIOS],
    "benchmark_tune",
)


rule benchmark_gather:
    input:
        runs=expand(
            f"{OUT}/benchmark/runs/{{scenario}}.nc", scenario=BENCHMARK_SCENARIOS
        ),
        tuned=BENCHMARK_TUNED,
        plugins=PLUGINS,
        plugin_data=PLUGIN_DATA,
    output:
        criteria=f"{OUT}/benchmark/criteria.nc",
        table=f"{OUT}/benchmark/table.md",
        figure=report(
            f"{OUT}/figures/benchmark_criteria.png",
            caption="../report/benchmark_criteria.rst",
            category="Benchmark",
            subcategory="Criteria",
            labels={"figure": "mean and worst J per controller and criterion"},
        ),
        boxplots=report(
            f"{OUT}/figures/benchmark_boxplots.png",
            caption="../report/benchmark_boxplots.rst",
            category="Benchmark",
            subcategory="Criteria",
            labels={"figure": "J over the evaluation scenarios per controller"},
        ),
    log:
        f"{OUT}/logs/benchmark_gather.log",
    benchmark:
        f"{OUT}/benchmarks/benchmark_gather.tsv"
    conda:
        ENV
    params:
        digest=DIGESTS["benchmark_gather"],
        expects=expects(
            {
                **{
                    f"{OUT}/benchmark/runs/{s}.nc": f"benchmark_run:{s}"
                    for s in BENCHMARK_SCENARIOS
                },
                **{path: "benchmark_tune" for path in BENCHMARK_TUNED},
            }
        ),
        split=BENCHMARK_SPLIT,
        runs=BENCHMARK_RUNS,
        extrapolation=EXTRAPOLATION["benchmark"],
    script:
        "../scripts/benchmark_gather.py"


# The benchmark on the payload: the gimbal on the payload section's six-axis isolators under every scenario and the
# stated sources benchmark.payload.sources names, the payload laws tuned on the tuning set and scored on the
# evaluation set (src/uavdamp/benchmark/payload.py). The payload section's view leaves out what the benchmark
# replaces (its payloads, mounts, inputs and duration) and its threads.
from uavdamp.benchmark import payload as benchmark_payload

BENCHMARK_PAYLOAD_MOUNTS = list(
    BENCHMARK["payload"]["mounts"]
)  # the runs'; the criterion is the gather's
BENCHMARK_PAYLOAD_SOURCES = list(BENCHMARK["payload"]["sources"])
BENCHMARK_PAYLOAD_SCENARIOS = BENCHMARK_SCENARIOS + BENCHMARK_PAYLOAD_SOURCES
BENCHMARK_PAYLOAD_SPLIT = benchmark_payload.split(
    BENCHMARK_SPLIT,
    BENCHMARK_PAYLOAD_SOURCES,
    BENCHMARK["split"]["tuning_fraction"],
    BENCHMARK["split"]["seed"],
)
BENCHMARK_PAYLOAD_SECTION = canonical(
    {
        k: v
        for k, v in config["payload"].items()
        if k not in ("payloads", "mounts", "sources", "duration_s", "threads")
    }
)
BENCHMARK_PAYLOAD_RUNS = (
    expand(
        f"{OUT}/benchmark/payload/runs/{{scenario}}.nc",
        scenario=BENCHMARK_PAYLOAD_SCENARIOS,
    )
    if BENCHMARK["payload"]["enabled"]
    else []
)


# {path: rule digest} of each payload run's scenario file ({} for a stated source: the job generates it)
BENCHMARK_PAYLOAD_INPUTS = {
    s: (
        {}
        if s in BENCHMARK_PAYLOAD_SOURCES
        else {f"{OUT}/benchmark/scenarios/{s}.nc": f"benchmark_scenario:{s}"}
    )
    for s in BENCHMARK_PAYLOAD_SCENARIOS
}

for _s in BENCHMARK_PAYLOAD_SCENARIOS:
    digest(
        f"benchmark_payload_run:{_s}",
        {
            "mounts": BENCHMARK_PAYLOAD_MOUNTS,
            "duration_s": BENCHMARK["duration_s"],
            "payload": BENCHMARK_PAYLOAD_SECTION,
            "camera": CAMERA,
            "platform": PLATFORM_MODEL,
            "source": canonical(
                config["sources"][_s] if _s in BENCHMARK_PAYLOAD_SOURCES else {}
            ),
        },
        *BENCHMARK_PAYLOAD_INPUTS[_s].values(),
        "payload_table",
        "payload_anfis",
    )


rule benchmark_payload_run:
    input:
        scenario=lambda wc: list(BENCHMARK_PAYLOAD_INPUTS[wc.scenario]),
        table=f"{OUT}/payload/table.nc",
        model=f"{OUT}/payload/anfis_model.nc",
    output:
        f"{OUT}/benchmark/payload/runs/{{scenario}}.nc",
    log:
        f"{OUT}/logs/benchmark_payload_run_{{scenario}}.log",
    benchmark:
        f"{OUT}/benchmarks/benchmark_payload_run_{{scenario}}.tsv"
    wildcard_constraints:
        scenario="|".join(BENCHMARK_PAYLOAD_SCENARIOS),
    conda:
        ENV
    params:
        digest=lambda wc: DIGESTS[f"benchmark_payload_run:{wc.scenario}"],
        expects=lambda wc: expects(
            {
                **BENCHMARK_PAYLOAD_INPUTS[wc.scenario],
                f"{OUT}/payload/table.nc": "payload_table",
                f"{OUT}/payload/anfis_model.nc": "payload_anfis",
            }
        ),
        mounts=BENCHMARK_PAYLOAD_MOUNTS,
        duration_s=BENCHMARK["duration_s"],
        payload=BENCHMARK_PAYLOAD_SECTION,
        camera=CAMERA,
        platform=PLATFORM_MODEL,
        # a stated source's own keys (sources.NAME) for a source scenario, {} for the others
        source=lambda wc: canonical(
            config["sources"][wc.scenario]
            if wc.scenario in BENCHMARK_PAYLOAD_SOURCES
            else {}
        ),
    script:
        "../scripts/benchmark_payload_run.py"


digest(
    "benchmark_payload_gather",
    {"split": BENCHMARK_PAYLOAD_SPLIT, "criterion": BENCHMARK["payload"]["criterion"]},
    *[f"benchmark_payload_run:{s}" for s in BENCHMARK_PAYLOAD_SCENARIOS],
)


rule benchmark_payload_gather:
    input:
        runs=BENCHMARK_PAYLOAD_RUNS,
    output:
        criteria=f"{OUT}/benchmark/payload/criteria.nc",
        table=f"{OUT}/benchmark/payload/table.md",
        figure=report(
            f"{OUT}/figures/benchmark_payload.png",
            caption="../report/benchmark_payload.rst",
            category="Benchmark",
            subcategory="Payload",
            labels={"figure": "J per damping law on the gimbal's isolator"},
        ),
    log:
        f"{OUT}/logs/benchmark_payload_gather.log",
    benchmark:
        f"{OUT}/benchmarks/benchmark_payload_gather.tsv"
    conda:
        ENV
    params:
        digest=DIGESTS["benchmark_payload_gather"],
        expects=expects(
            {
                f"{OUT}/benchmark/payload/runs/{s}.nc": f"benchmark_payload_run:{s}"
                for s in BENCHMARK_PAYLOAD_SCENARIOS
            }
        ),
        split=BENCHMARK_PAYLOAD_SPLIT,
        criterion=BENCHMARK["payload"]["criterion"],
    script:
        "../scripts/benchmark_payload_gather.py"
