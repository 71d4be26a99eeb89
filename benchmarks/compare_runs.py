"""Compare two runs' NetCDF outputs variable by variable: did a restructuring change any result?

Usage: python benchmarks/compare_runs.py BEFORE_DIR AFTER_DIR [--rename OLD=NEW ...]

For every `*.nc` under both output directories (same relative path), every variable and coordinate: the largest
absolute difference and the largest relative difference |a - b| / max(|a|, |b|) (NaN where both are NaN counts as
equal; a NaN on one side only is reported), changed `units` or `long_name`, and the variables found on one side only
(`--rename old=new` pairs a variable renamed on purpose where old is only before and new only after). Provenance
attributes (commit, command, times, digests) differ by design and are not compared. Prints one line per file and per
differing variable, then the largest relative difference overall; exit status 1 if a file or variable is missing on
one side.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import xarray as xr


def difference(a: xr.DataArray, b: xr.DataArray) -> tuple[float, float, str]:
    """(largest absolute, largest relative difference, note) of two variables' values."""
    if a.shape != b.shape:
        return np.inf, np.inf, f"shape {a.shape} against {b.shape}"
    if a.dtype.kind not in "fciub" or b.dtype.kind not in "fciub":
        same = np.array_equal(np.asarray(a.values, dtype=str), np.asarray(b.values, dtype=str))
        return (0.0, 0.0, "") if same else (np.inf, np.inf, "text differs")
    x, y = np.asarray(a.values, dtype=float), np.asarray(b.values, dtype=float)
    one_nan = np.isnan(x) != np.isnan(y)
    both = ~np.isnan(x) & ~np.isnan(y)
    if not both.any():
        return 0.0, 0.0, "NaN on one side only" if one_nan.any() else ""
    diff = np.abs(x[both] - y[both])
    scale = np.maximum(np.abs(x[both]), np.abs(y[both]))
    rel = np.where(scale > 0, diff / np.where(scale > 0, scale, 1.0), 0.0)
    return float(diff.max()), float(rel.max()), f"{int(one_nan.sum())} NaN on one side only" if one_nan.any() else ""


def compare_file(before: Path, after: Path, renames: dict[str, str]) -> tuple[list[str], float, bool]:
    """(report lines, largest relative difference, something missing) of one file."""
    lines, worst, missing = [], 0.0, False
    with xr.open_dataset(before, decode_times=False) as a, xr.open_dataset(after, decode_times=False) as b:
        names_a = set(a.variables)
        renames = {o: n for o, n in renames.items() if o in a.variables and n in b.variables and n not in a.variables}
        names_b = {next((o for o, n in renames.items() if n == v), v) for v in b.variables}
        for name in sorted(names_a ^ names_b):
            lines.append(f"  {name}: only {'before' if name in names_a else 'after'}")
            missing = True
        for name in sorted(names_a & names_b):
            va, vb = a[name], b[renames.get(name, name)]
            absolute, relative, note = difference(va, vb)
            attrs = [k for k in ("units", "long_name") if va.attrs.get(k) != vb.attrs.get(k)]
            worst = max(worst, relative)
            if relative > 0 or note or attrs:
                changed = f"; {', '.join(attrs)} changed" if attrs else ""
                lines.append(f"  {name}: max abs {absolute:.3g}, max rel {relative:.3g} {note}{changed}".rstrip())
    return lines, worst, missing


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--rename", action="append", default=[], help="OLD=NEW: a variable renamed on purpose")
    args = parser.parse_args()
    renames = dict(pair.split("=", 1) for pair in args.rename)
    files_a = {p.relative_to(args.before) for p in args.before.rglob("*.nc")}
    files_b = {p.relative_to(args.after) for p in args.after.rglob("*.nc")}
    worst, missing = 0.0, bool(files_a ^ files_b)
    for rel in sorted(files_a ^ files_b):
        print(f"{rel}: only {'before' if rel in files_a else 'after'}")
    for rel in sorted(files_a & files_b):
        lines, file_worst, file_missing = compare_file(args.before / rel, args.after / rel, renames)
        worst, missing = max(worst, file_worst), missing or file_missing
        print(f"{rel}: {'identical values' if not lines else f'max rel {file_worst:.3g}'}")
        if lines:
            print("\n".join(lines))
    print(f"largest relative difference over {len(files_a & files_b)} files: {worst:.3g}")
    sys.exit(1 if missing else 0)


if __name__ == "__main__":
    main()
