"""Progress bars for long jobs on the console (tqdm), quiet when the console is not a terminal.

Snakemake's job scripts send their stderr to the job's log (`uavdamp.workflow.start_log`); the bars write to the
process's original stderr (`sys.__stderr__`), the terminal Snakemake runs in, so the console shows them and the
log keeps the detail. tqdm's `disable=None` turns a bar off when that stream is not a terminal (CI, cluster jobs).
"""

from __future__ import annotations

import sys

from tqdm import tqdm

# on the terminal Snakemake runs in, off where that is not a terminal, not in the job's log
_ON_CONSOLE = {"file": sys.__stderr__, "disable": None, "mininterval": 1.0, "leave": False, "dynamic_ncols": True}


def bar(total: float, desc: str, unit: str) -> tqdm:
    """A bar of `total` units; call .update(n) and .close()."""
    return tqdm(total=total, desc=desc, unit=unit, **_ON_CONSOLE)


def each(iterable, total: int, desc: str, unit: str = "run"):
    """`iterable` with a bar."""
    return tqdm(iterable, total=total, desc=desc, unit=unit, **_ON_CONSOLE)
