"""Check a run's outputs: every NetCDF read whole, stale temporary files listed (and removed with --clean).

    python -m uavdamp.results.verify [OUTPUT_DIR] [--clean] [--max-age-hours H]

Reads every `*.nc` under OUTPUT_DIR (default `reports`) with `uavdamp.io.open_dataset` (all variables, so every
Fletcher-32 checksum is checked) and lists each corrupt or truncated file with the command that rebuilds it; exit
code 1 if any. Temporary files of interrupted writes (`.NAME~host~pid~XXXX.tmp.SUFFIX`, `uavdamp.io.atomic_write`)
are stale when their writer is gone: written on this host by a pid that no longer runs, or (another host's, or
an older file without the host~pid tag) last modified more than --max-age-hours ago (default 24 h: no write of
the pipeline takes that long). A live writer's file is never touched; pid reuse can only keep a stale file.
"""

from __future__ import annotations

import argparse
import os
import re
import socket
import sys
import time
from pathlib import Path

from uavdamp import io

DEFAULT_MAX_AGE_H = 24.0
_TMP = re.compile(r"^\..+\.tmp(\.[A-Za-z0-9]+)?$")
_TAG = re.compile(r"~([^~/]+)~(\d+)~[^~]*\.tmp(\.[A-Za-z0-9]+)?$")


def temporary_files(folder) -> list[Path]:
    """Every temporary file of `atomic_write` under `folder` (hidden, `.tmp` before the suffix)."""
    return sorted(p for p in Path(folder).rglob(".*") if p.is_file() and _TMP.match(p.name))


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's live process
        return True
    return True


def is_stale(path: Path, *, max_age_h: float = DEFAULT_MAX_AGE_H, now: float | None = None) -> bool:
    """True if the writer of temporary file `path` is gone (see the module's docstring)."""
    tag = _TAG.search(path.name)
    if tag and tag.group(1) == socket.gethostname():
        return not _alive(int(tag.group(2)))
    age_s = (time.time() if now is None else now) - path.stat().st_mtime
    return age_s > max_age_h * 3600.0


def stale_files(folder, *, max_age_h: float = DEFAULT_MAX_AGE_H) -> list[Path]:
    """The stale temporary files under `folder`."""
    return [p for p in temporary_files(folder) if is_stale(p, max_age_h=max_age_h)]


def clean_stale(folder, *, max_age_h: float = DEFAULT_MAX_AGE_H) -> list[Path]:
    """Remove the stale temporary files under `folder` (only there); returns those removed."""
    removed = []
    for path in stale_files(folder, max_age_h=max_age_h):
        path.unlink(missing_ok=True)
        removed.append(path)
    return removed


def corrupt_files(folder) -> list[tuple[Path, str]]:
    """(path, message) of every `*.nc` under `folder` (temporary files aside) that does not read whole."""
    bad = []
    for path in sorted(Path(folder).rglob("*.nc")):
        if path.name.startswith("."):
            continue
        try:
            io.open_dataset(path)
        except io.CorruptOutput as error:
            bad.append((path, str(error)))
    return bad


def main(argv: list[str] | None = None) -> int:
    """The command: report, optionally clean; 0 if every NetCDF reads whole, else 1 (2: no such folder)."""
    parser = argparse.ArgumentParser(prog="python -m uavdamp.results.verify", description=__doc__.split("\n")[0])
    parser.add_argument("output_dir", nargs="?", default="reports", help="the run's output folder")
    parser.add_argument("--clean", action="store_true", help="remove the stale temporary files")
    parser.add_argument("--max-age-hours", type=float, default=DEFAULT_MAX_AGE_H, help="see the module docstring")
    args = parser.parse_args(argv)
    folder = Path(args.output_dir)
    if not folder.is_dir():
        print(f"verify: {folder}: no such folder", file=sys.stderr)
        return 2
    n_files = sum(1 for p in folder.rglob("*.nc") if not p.name.startswith("."))
    bad = corrupt_files(folder)
    for _, message in bad:
        print(f"CORRUPT {message}")
    stale = stale_files(folder, max_age_h=args.max_age_hours)
    for path in stale:
        if args.clean:
            path.unlink(missing_ok=True)
        print(f"STALE {path}: temporary file of an interrupted write{' (removed)' if args.clean else ''}")
    if stale and not args.clean:
        print("remove the stale temporary files: python -m uavdamp.results.verify --clean " + str(folder))
    print(f"verify: {n_files} NetCDF files under {folder}, {len(bad)} corrupt, {len(stale)} stale temporary")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
