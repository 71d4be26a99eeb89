"""Snakemake script: every NetCDF under the output folder read whole (`uavdamp.results.verify`): the report on the
terminal
and in the log; the job fails if a file is corrupt."""

import contextlib
import io
import sys
from pathlib import Path

from uavdamp.results import verify

report = io.StringIO()
with contextlib.redirect_stdout(report):
    code = verify.main([snakemake.params.out])
print(report.getvalue(), end="", file=sys.stderr)
Path(snakemake.log[0]).write_text(report.getvalue())
if code:
    sys.exit(f"verify: corrupt outputs under {snakemake.params.out} (listed above): delete them and rerun all")
