# The controller benchmark: one job per scenario input, tuning on the tuning set only (one job per stiffness),
# one job per scenario running every controller, then a gather. Logic in src/uavdamp/{scenarios,benchmark}.py.
from uavdamp.benchmark import BenchmarkOptions
from uavdamp.scenarios import ScenarioOptions, scenario_specs
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
    "reports/benchmark/tuned/K{stiffness}.nc", stiffness=BENCHMARK_STIFFNESS
)
BENCHMARK_TRACKING = canonical(config["study"]["tracking"])


rule benchmark_scenario:
    output:
        "reports/benchmark/scenarios/{scenario}.nc",
    log:
        "reports/logs/benchmark_scenario_{scenario}.log",
    benchmark:
        "reports/benchmarks/benchmark_scenario_{scenario}.tsv"
    wildcard_constraints:
        scenario="|".join(BENCHMARK_SCENARIOS),
    conda:
        ENV
    params:
        inputs=BENCHMARK_INPUTS,
        helicopter=HELICOPTER_RUN,
        platform=PLATFORM_MODEL,
    script:
        "../scripts/benchmark_scenario.py"


rule benchmark_tune:
    input:
        scenarios=expand(
            "reports/benchmark/scenarios/{scenario}.nc", scenario=BENCHMARK_TUNING
        ),
    output:
        "reports/benchmark/tuned/K{stiffness}.nc",
    log:
        "reports/logs/benchmark_tune_K{stiffness}.log",
    benchmark:
        "reports/benchmarks/benchmark_tune_K{stiffness}.tsv"
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
        scenario="reports/benchmark/scenarios/{scenario}.nc",
        tuned=BENCHMARK_TUNED,
        model="reports/anfis/model.nc",
        table="reports/reference_table/table.nc",
    output:
        "reports/benchmark/runs/{scenario}.nc",
    log:
        "reports/logs/benchmark_run_{scenario}.log",
    benchmark:
        "reports/benchmarks/benchmark_run_{scenario}.tsv"
    wildcard_constraints:
        scenario="|".join(BENCHMARK_SCENARIOS),
    conda:
        ENV
    params:
        runs=BENCHMARK_RUNS,
        tracking=BENCHMARK_TRACKING,
        camera=CAMERA,
        platform=PLATFORM_MODEL,
    script:
        "../scripts/benchmark_run.py"


rule benchmark_gather:
    input:
        runs=expand(
            "reports/benchmark/runs/{scenario}.nc", scenario=BENCHMARK_SCENARIOS
        ),
        tuned=BENCHMARK_TUNED,
    output:
        criteria="reports/benchmark/criteria.nc",
        table="reports/benchmark/table.md",
        figure=report(
            "reports/figures/benchmark_criteria.png",
            caption="../report/benchmark_criteria.rst",
            category="Benchmark",
        ),
        boxplots=report(
            "reports/figures/benchmark_boxplots.png",
            caption="../report/benchmark_boxplots.rst",
            category="Benchmark",
        ),
    log:
        "reports/logs/benchmark_gather.log",
    benchmark:
        "reports/benchmarks/benchmark_gather.tsv"
    conda:
        ENV
    params:
        split=BENCHMARK_SPLIT,
        runs=BENCHMARK_RUNS,
    script:
        "../scripts/benchmark_gather.py"
