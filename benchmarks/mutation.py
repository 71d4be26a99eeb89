"""Mutation testing of the numeric core with mutmut 3: run it and write the report.

Slow (tens of minutes on 2 cores), so not part of CI. From the repository root:

    .venv/bin/python benchmarks/mutation.py run        # fresh run: deletes mutants/, mutates, tests
    .venv/bin/python benchmarks/mutation.py run --only "uavdamp.study.metrics.*"   # the same for one module's mutants
    .venv/bin/python benchmarks/mutation.py retest     # retest the surviving mutants only (after adding tests)
    .venv/bin/python benchmarks/mutation.py report     # docs/mutation.md's table from mutants/*.meta

The modules and the test selection are pyproject.toml's [tool.mutmut] table. mutmut maps every mutated
function to the tests that call it and runs only those for its mutants. Mutants judged equivalent (no
input can tell them apart) are listed, each with its reason, in tests/mutation_equivalent.txt; the report
counts them apart and gives the kill rate over the others. Run without PYTHONPATH: mutmut puts its mutated
copy of src/ first on sys.path itself. The selection holds no test that starts Snakemake: pyproject's
`-m "not slow"` leaves out every pipeline test (tests/conftest.py marks them), so the mutants' copy needs only
src/ and what the unit tests read (`also_copy`).
"""

from __future__ import annotations

import argparse
import fnmatch
import json
import os
import shutil
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MUTMUT = str(Path(sys.executable).with_name("mutmut"))
EQUIVALENT = ROOT / "tests" / "mutation_equivalent.txt"
REPORT = ROOT / "docs" / "mutation.md"
STATUS = {
    0: "survived",
    33: "no tests",
    34: "skipped",
    36: "timeout",
    -24: "timeout",
    152: "timeout",
    24: "timeout",
    37: "type check",
    1: "killed",
    3: "killed",
    -11: "segfault",
    None: "not checked",
}


def _env() -> dict:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["OMP_NUM_THREADS"] = env["OPENBLAS_NUM_THREADS"] = env["MKL_NUM_THREADS"] = "1"
    return env


def results() -> dict[str, int | None]:
    """{mutant name: mutmut exit code} over every mutated module."""
    out: dict[str, int | None] = {}
    for meta in sorted((ROOT / "mutants").rglob("*.py.meta")):
        out.update(json.loads(meta.read_text())["exit_code_by_key"])
    return out


def equivalent() -> dict[str, str]:
    """{mutant name: why it is equivalent} from tests/mutation_equivalent.txt ("name  reason" per line)."""
    if not EQUIVALENT.exists():
        return {}
    pairs = (line.split(None, 1) for line in EQUIVALENT.read_text().splitlines() if line.strip() and line[0] != "#")
    return {name: reason.strip() for name, reason in pairs}


def module_of(name: str) -> str:
    return name.split(".x\u01c1")[0].split(".x_")[0]


def report(wall_s: float | None, only: str | None = None) -> str:
    """The table over every mutant, or over those whose name matches the pattern `only` (fnmatch)."""
    res, equiv = results(), equivalent()
    if only:
        res = {name: code for name, code in res.items() if fnmatch.fnmatch(name, only)}
    table: dict[str, Counter] = {}
    surviving = []
    for name, code in res.items():
        status = STATUS.get(code, "killed" if code else "survived")
        counts = table.setdefault(module_of(name), Counter())
        counts["generated"] += 1
        if status == "killed" or status == "timeout" or status == "segfault":
            counts["killed"] += 1
        elif name in equiv:
            counts["equivalent"] += 1
        else:
            counts["surviving"] += 1
            surviving.append((name, status))
    lines = [
        "| module | generated | killed | equivalent | surviving | killed % of non-equivalent |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    total = Counter()
    for module in sorted(table):
        c = table[module]
        total.update(c)
        lines.append(_row(module, c))
    lines.append(_row("**total**", total))
    text = "\n".join(lines) + "\n"
    if wall_s is not None:
        text += f"\nWall time of this command: {wall_s / 60:.1f} min on {os.cpu_count()} cores.\n"
    text += "\nSurviving mutants (`mutmut show NAME` prints the diff):\n\n"
    text += "".join(f"- `{n}` ({s})\n" for n, s in sorted(surviving)) or "- none\n"
    return text


def _row(module: str, c: Counter) -> str:
    live = c["generated"] - c["equivalent"]
    pct = 100.0 * c["killed"] / live if live else 100.0
    return f"| {module} | {c['generated']} | {c['killed']} | {c['equivalent']} | {c['surviving']} | {pct:.1f} |"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("command", choices=["run", "retest", "report"])
    parser.add_argument("--max-children", type=int, default=2, help="parallel test workers (default 2)")
    parser.add_argument("--output", type=Path, default=None, help="write the table here (default: print it)")
    parser.add_argument(
        "--only", default=None, help='mutant names to run and report (fnmatch: "uavdamp.study.metrics.*")'
    )
    args = parser.parse_args()
    start = time.monotonic()
    wall = None
    if args.command == "run":
        shutil.rmtree(ROOT / "mutants", ignore_errors=True)
        names = [args.only] if args.only else []
        command = [MUTMUT, "run", "--max-children", str(args.max_children), *names]
        subprocess.run(command, cwd=ROOT, env=_env(), check=False)
        wall = time.monotonic() - start
    elif args.command == "retest":
        names = [n for n, code in results().items() if code in (0, 33) and n not in equivalent()]
        names = [n for n in names if not args.only or fnmatch.fnmatch(n, args.only)]
        if names:
            subprocess.run(
                [MUTMUT, "run", "--max-children", str(args.max_children), *names], cwd=ROOT, env=_env(), check=False
            )
        wall = time.monotonic() - start
    text = report(wall, args.only)
    if args.output:
        args.output.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
