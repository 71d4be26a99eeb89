rule platform_modes:
    output:
        modes=f"{OUT}/platform/modes.nc",
        figure=report(
            f"{OUT}/figures/platform_response.png",
            caption="../report/platform_response.rst",
            category="Platform",
        ),
    log:
        f"{OUT}/logs/platform_modes.log",
    benchmark:
        f"{OUT}/benchmarks/platform_modes.tsv"
    conda:
        ENV
    params:
        platform=PLATFORM,
    script:
        "../scripts/platform_modes.py"
