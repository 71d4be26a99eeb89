# The controller benchmark: one job per scenario input, tuning on the tuning set only (one job per stiffness),
# one job per scenario running every controller, then a gather. Logic in src/uavdamp/{scenarios,benchmark}.py.
from uavdamp.benchmark import BenchmarkOptions
from uavdamp.scenarios import ScenarioOptions, flight_log_of, scenario_specs
from uavdamp.scenarios import split as benchmark_split

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
# the MR damper, built once (uavdamp.actuation.MRSpec): an input of the jobs that run it
BENCHMARK_MR = [f"{OUT}/benchmark/mr_damper.nc"] if "mr" in BENCHMARK["dampers"] else []
BENCHMARK_CHECKED = list(BENCHMARK["step_check"]["scenarios"])


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
        mr=canonical(BENCHMARK["mr"]),
    script:
        "../scripts/benchmark_mr_damper.py"


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
        inputs=BENCHMARK_INPUTS,
        helicopter=FLIGHT_RUN,
        platform=PLATFORM_MODEL,
    script:
        "../scripts/benchmark_scenario.py"


rule benchmark_tune:
    input:
        scenarios=expand(
            f"{OUT}/benchmark/scenarios/{{scenario}}.nc", scenario=BENCHMARK_TUNING
        ),
        plugins=PLUGINS,
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
        runs=BENCHMARK_RUNS,
        tracking=BENCHMARK_TRACKING,
        camera=CAMERA,
        platform=PLATFORM_MODEL,
    script:
        "../scripts/benchmark_tune.py"


rule benchmark_run:
    input:
        scenario=f"{OUT}/benchmark/scenarios/{{scenario}}.nc",
        tuned=BENCHMARK_TUNED,
        model=f"{OUT}/anfis/model.nc",
        table=f"{OUT}/reference_table/table.nc",
        plugins=PLUGINS,
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
        runs=BENCHMARK_RUNS,
        tracking=BENCHMARK_TRACKING,
        camera=CAMERA,
        platform=PLATFORM_MODEL,
        step_check=lambda wc: wc.scenario in BENCHMARK_CHECKED,
    script:
        "../scripts/benchmark_run.py"


rule benchmark_gather:
    input:
        runs=expand(
            f"{OUT}/benchmark/runs/{{scenario}}.nc", scenario=BENCHMARK_SCENARIOS
        ),
        tuned=BENCHMARK_TUNED,
        plugins=PLUGINS,
    output:
        criteria=f"{OUT}/benchmark/criteria.nc",
        table=f"{OUT}/benchmark/table.md",
        figure=report(
            f"{OUT}/figures/benchmark_criteria.png",
            caption="../report/benchmark_criteria.rst",
            category="Benchmark",
        ),
        boxplots=report(
            f"{OUT}/figures/benchmark_boxplots.png",
            caption="../report/benchmark_boxplots.rst",
            category="Benchmark",
        ),
    log:
        f"{OUT}/logs/benchmark_gather.log",
    benchmark:
        f"{OUT}/benchmarks/benchmark_gather.tsv"
    conda:
        ENV
    params:
        split=BENCHMARK_SPLIT,
        runs=BENCHMARK_RUNS,
        extrapolation=EXTRAPOLATION["benchmark"],
    script:
        "../scripts/benchmark_gather.py"
