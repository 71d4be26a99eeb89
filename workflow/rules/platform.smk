rule platform_modes:
    output:
        modes="reports/platform/modes.nc",
        figure="reports/figures/platform_response.png",
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
