# `snakemake -j1 verify`: read every NetCDF under the output folder whole (Fletcher-32 checksums), list the corrupt
# or truncated ones with their rebuild command and the stale temporary files of interrupted writes; fails if any
# file is corrupt. Heal: delete each listed file and rerun `all` (or `benchmark`). Logic: src/uavdamp/results/verify.py.
from uavdamp.results import verify as output_check


# stale temporary files of this output folder only, and only those whose writer is gone (uavdamp.results.verify.is_stale)
onstart:
    for path in output_check.clean_stale(OUT):
        print(f"removed a stale temporary file: {path}", file=sys.stderr)


rule verify:
    log:
        f"{OUT}/logs/verify.log",
    conda:
        ENV
    params:
        out=OUT,
    script:
        "../scripts/verify.py"
