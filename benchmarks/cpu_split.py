"""Benchmark: where a run's CPU goes, from a py-spy profile of it and of every process it starts.

Usage:
  python benchmarks/cpu_split.py record PROFILE.raw [--rate HZ] [--top N] -- COMMAND ...
  python benchmarks/cpu_split.py report PROFILE.raw [--rate HZ] [--top N]

`record` runs COMMAND under `py-spy record --subprocesses --format raw` (py-spy: `pip install py-spy`; it needs
ptrace, so root or a permissive `kernel.yama.ptrace_scope`) and then reports. `report` splits the samples by process
(a Snakemake job by its script, the Snakemake processes, pytest's main process and its xdist workers, any other
command) and by what the process was doing:

import    inside Python's import machinery (a module imported at run time counts too)
figure    drawing or saving a figure (matplotlib's savefig, uavdamp.plots); `layout` is the part of it in matplotlib's
          constrained layout
waiting   a thread blocked on a lock, an event, a condition, a select or a child process (py-spy's idle detection
          misses some of these)
compute   everything else

Seconds are samples / --rate (record writes the rate beside the profile, PROFILE.raw.rate): the time each process
spent on a core while sampled, which py-spy's own sampling slows a little.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from collections import Counter
from pathlib import Path

PROCESS = re.compile(r'process (\d+):"(.*?)"(?:;|$)')  # py-spy's process frames lead a sample's stack
SCRIPT = re.compile(r"\.snakemake/scripts/tmp\w+\.(\w+)\.py")  # Snakemake's copy of a rule's script
# the innermost function of a blocked thread (its name after the last dot): Condition.wait, EpollSelector.select, ...
WAITS = {"wait", "select", "poll", "acquire", "sleep", "_try_wait", "_wait_for_tstate_lock"}
KINDS = ("import", "figure", "layout", "waiting", "compute")


def process_name(command: str) -> str:
    """The process a sample belongs to, from its command line."""
    script = SCRIPT.search(command)
    if script:
        return f"job {script.group(1)}.py"
    if not command:  # py-spy names the process it started by no command line
        return "the command"
    if "exec(eval(sys.stdin.readline()))" in command:  # execnet's bootstrap: a pytest-xdist worker
        return "pytest worker"
    if "joblib" in command or "multiprocessing" in command:
        return "joblib or multiprocessing worker"
    if "snakemake" in command.split(" -", 1)[0] or " -m snakemake" in command:
        return "snakemake"
    if "pytest" in command:
        return "pytest"
    return command.split()[0].rsplit("/", 1)[-1] if command.strip() else "?"


def kind(frames: list[str]) -> str:
    """What a sample's Python frames (outermost first) were doing: one of KINDS but "layout" (see `split`)."""
    if any(f.startswith("_find_and_load") for f in frames):
        return "import"
    if any("savefig" in f or "uavdamp/plots/" in f for f in frames):
        return "figure"
    if frames and frames[-1].split(" (", 1)[0].rsplit(".", 1)[-1] in WAITS:
        return "waiting"
    return "compute"


def parse(line: str) -> tuple[str, list[str], int] | None:
    """(process name, Python frames outermost first, samples) of one line of a raw profile; None for a blank or
    malformed line."""
    stack, _, count = line.rstrip("\n").rpartition(" ")
    if not stack or not count.isdigit():
        return None
    command, position = "", 0
    while match := PROCESS.match(stack, position):
        command, position = match.group(2), match.end()
    frames = [f for f in stack[position:].split(";") if f]
    return process_name(command), frames, int(count)


def split(lines) -> dict[str, Counter]:
    """{process name: Counter of samples per kind (KINDS, "layout" also counted in "figure")}."""
    out: dict[str, Counter] = {}
    for line in lines:
        parsed = parse(line)
        if parsed is None:
            continue
        name, frames, count = parsed
        what = kind(frames)
        counts = out.setdefault(name, Counter())
        counts[what] += count
        if what == "figure" and any("_constrained_layout" in f or "ConstrainedLayoutEngine" in f for f in frames):
            counts["layout"] += count
    return out


def report(by_process: dict[str, Counter], rate: float, top: int) -> str:
    """The split as a table: each process name's seconds per kind, the largest first, and the whole run's."""
    total = Counter()
    for counts in by_process.values():
        total.update(counts)
    width = max([len(name) for name in by_process] + [10])
    rows = [f"{'process':<{width}} {'total s':>8} " + " ".join(f"{k + ' s':>9}" for k in KINDS)]

    def row(name: str, counts: Counter) -> str:
        busy = sum(counts[k] for k in KINDS if k != "layout")
        return f"{name:<{width}} {busy / rate:8.1f} " + " ".join(f"{counts[k] / rate:9.1f}" for k in KINDS)

    order = sorted(by_process, key=lambda n: -sum(by_process[n][k] for k in KINDS if k != "layout"))
    rows.append(row("all", total))
    rows += [row(name, by_process[name]) for name in order[:top]]
    busy = sum(total[k] for k in KINDS if k != "layout") or 1
    shares = ", ".join(f"{k} {100 * total[k] / busy:.0f} %" for k in KINDS)
    return "\n".join([f"samples at {rate:g} Hz; shares of all: {shares} (layout is part of figure)", *rows])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mode", choices=["record", "report"])
    parser.add_argument("profile", type=Path)
    parser.add_argument("--rate", type=float, help="samples per second (default: the recorded one, else 25)")
    parser.add_argument("--top", type=int, default=30, help="processes listed (default 30)")
    argv = sys.argv[1:]
    cut = argv.index("--") if "--" in argv else len(argv)
    args, command = parser.parse_args(argv[:cut]), argv[cut + 1 :]
    rate_file = args.profile.with_name(args.profile.name + ".rate")
    if args.mode == "record":
        if not command:
            sys.exit("record: give the command to profile after --")
        rate = args.rate or 25.0
        spy = ["py-spy", "record", "--subprocesses", "--format", "raw", "-r", f"{rate:g}", "-o", str(args.profile)]
        try:
            subprocess.run([*spy, "--", *command], check=True)
        except FileNotFoundError:
            sys.exit("record: py-spy is not installed (pip install py-spy)")
        rate_file.write_text(f"{rate:g}\n")
    if not args.profile.is_file():
        sys.exit(f"{args.profile}: no such profile")
    rate = args.rate or (float(rate_file.read_text()) if rate_file.is_file() else 25.0)
    with args.profile.open() as lines:
        print(report(split(lines), rate, args.top))


if __name__ == "__main__":
    main()
