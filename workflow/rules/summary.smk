# The results page from the run's NetCDF outputs: tables and headline numbers, generated, never typed.
rule summary:
    input:
        vibration=f"{OUT}/helicopter/vibration.nc",
        modes=f"{OUT}/platform/modes.nc",
        table=f"{OUT}/reference_table/table.nc",
        stroke=f"{OUT}/reference_table/stroke.nc",
        training=f"{OUT}/anfis/training.nc",
        comparison=f"{OUT}/study/comparison.nc",
    output:
        markdown=f"{OUT}/summary.md",
        html=report(
            f"{OUT}/summary.html",
            caption="../report/summary.rst",
            category="0 Summary",
        ),
    log:
        f"{OUT}/logs/summary.log",
    conda:
        ENV
    script:
        "../scripts/summary.py"
