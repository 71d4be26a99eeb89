rule platform_modes:
    output:
        modes="reports/platform/modes.nc",
        figure=report(
            "reports/figures/platform_response.png",
            caption="../report/platform_response.rst",
            category="Platform",
        ),
    log:
        "reports/logs/platform_modes.log",
    benchmark:
        "reports/benchmarks/platform_modes.tsv"
    conda:
        ENV
    params:
        platform=PLATFORM,
    script:
        "../scripts/platform_modes.py"
