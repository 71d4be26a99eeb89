digest("platform_modes", {"platform": PLATFORM})


rule platform_modes:
    output:
        modes=f"{OUT}/platform/modes.nc",
        figure=report(
            f"{OUT}/figures/platform_response.png",
            caption="../report/platform_response.rst",
            category="Platform",
            subcategory="Response",
            labels={"figure": "the platform's response to a sine input"},
        ),
    log:
        f"{OUT}/logs/platform_modes.log",
    benchmark:
        f"{OUT}/benchmarks/platform_modes.tsv"
    conda:
        ENV
    params:
        digest=DIGESTS["platform_modes"],
        platform=PLATFORM,
    script:
        "../scripts/platform_modes.py"
