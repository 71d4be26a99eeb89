digest(
    "summary",
    {},
    "helicopter_vibration",
    "platform_modes",
    "reference_table",
    "reference_table_stroke",
    "anfis",
    "excitation",
    "study",
    "payload",
)
# The results page from the run's NetCDF outputs and key figures: findings, descriptions and tables, generated,
# never typed. `all` writes the study's page; the benchmark target writes the same page with the benchmark's
# table beside it (`summary_with_benchmark`), so that `all` never waits for, nor reruns, the benchmark.
SUMMARY_FIGURES = {  # role (uavdamp.results.summary.FIGURES): figure under the output folder
    "blur": "figures/study_blur.png",
    "strategies": f"figures/study_strategies/{STUDY_FIGURES['case_1']}.png",  # not the first listed: key order changes nothing
    "fuselage": "figures/fuselage_vibration.png",
    "reference": "figures/reference_table.png",
    "payload": "figures/payload_line_of_sight.png",
}
SUMMARY_EXPECTS = {
    f"{OUT}/helicopter/vibration.nc": "helicopter_vibration",
    f"{OUT}/platform/modes.nc": "platform_modes",
    f"{OUT}/reference_table/table.nc": "reference_table",
    f"{OUT}/reference_table/stroke.nc": "reference_table_stroke",
    f"{OUT}/anfis/training.nc": "anfis",
    f"{OUT}/excitation/cases.nc": "excitation",
    f"{OUT}/study/comparison.nc": "study",
    f"{OUT}/payload/comparison.nc": "payload",
}


rule summary:
    input:
        **{f"figure_{role}": f"{OUT}/{path}" for role, path in SUMMARY_FIGURES.items()},
        vibration=f"{OUT}/helicopter/vibration.nc",
        modes=f"{OUT}/platform/modes.nc",
        table=f"{OUT}/reference_table/table.nc",
        stroke=f"{OUT}/reference_table/stroke.nc",
        training=f"{OUT}/anfis/training.nc",
        cases=f"{OUT}/excitation/cases.nc",
        comparison=f"{OUT}/study/comparison.nc",
        payload=f"{OUT}/payload/comparison.nc",
        # relative to the working directory: a run folder moved elsewhere plans nothing new
        landing=os.path.relpath(
            os.path.join(workflow.current_basedir, "..", "report", "workflow.rst")
        ),
    output:
        markdown=f"{OUT}/summary.md",
        # the report's first page: workflow/report/workflow.rst with the findings (the Snakefile's report:)
        landing=f"{OUT}/report_landing.rst",
        html=report(
            f"{OUT}/summary.html",
            caption="../report/summary.rst",
            category="Summary",
            labels={"page": "results of the run"},
        ),
    log:
        f"{OUT}/logs/summary.log",
    conda:
        ENV
    params:
        digest=DIGESTS["summary"],
        expects=expects(SUMMARY_EXPECTS),
    script:
        "../scripts/summary.py"


# the benchmark on the payload's criteria, when it runs (benchmark.payload.enabled)
BENCHMARK_PAYLOAD_SUMMARY = (
    {
        "benchmark_payload": f"{OUT}/benchmark/payload/criteria.nc",
        "figure_benchmark_payload": f"{OUT}/figures/benchmark_payload.png",
    }
    if BENCHMARK["payload"]["enabled"]
    else {}
)
digest(
    "summary_with_benchmark",
    {},
    "summary",
    "benchmark_gather",
    *(["benchmark_payload_gather"] if BENCHMARK_PAYLOAD_SUMMARY else []),
)


use rule summary as summary_with_benchmark with:
    input:
        **{f"figure_{role}": f"{OUT}/{path}" for role, path in SUMMARY_FIGURES.items()},
        **BENCHMARK_PAYLOAD_SUMMARY,
        figure_benchmark=f"{OUT}/figures/benchmark_criteria.png",
        benchmark=f"{OUT}/benchmark/criteria.nc",
        vibration=f"{OUT}/helicopter/vibration.nc",
        modes=f"{OUT}/platform/modes.nc",
        table=f"{OUT}/reference_table/table.nc",
        stroke=f"{OUT}/reference_table/stroke.nc",
        training=f"{OUT}/anfis/training.nc",
        cases=f"{OUT}/excitation/cases.nc",
        comparison=f"{OUT}/study/comparison.nc",
        payload=f"{OUT}/payload/comparison.nc",
    output:
        markdown=f"{OUT}/benchmark/summary.md",
        html=report(
            f"{OUT}/benchmark/summary.html",
            caption="../report/summary.rst",
            category="Summary",
            labels={"page": "results of the run with the benchmark"},
        ),
    log:
        f"{OUT}/logs/summary_with_benchmark.log",
    params:
        digest=DIGESTS["summary_with_benchmark"],
        expects=expects(
            {
                **SUMMARY_EXPECTS,
                f"{OUT}/benchmark/criteria.nc": "benchmark_gather",
                **{
                    path: "benchmark_payload_gather"
                    for path in BENCHMARK_PAYLOAD_SUMMARY.values()
                    if path.endswith(".nc")
                },
            }
        ),
