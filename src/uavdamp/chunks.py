"""Guarded reference-table chunks: one writer per chunk, and every chunk checked before the gather uses it.

`exclusive(path)` holds an OS file lock (filelock, fcntl: released when the holder dies, even by SIGKILL) beside a
chunk while a job computes and writes it, so a surviving job of a killed run and a restarted run cannot write the
same chunk at the same time: the second one stops at once, naming the file. `load_chunk` opens a chunk and checks
what the gather relies on; any problem is a ValueError naming the file, what is wrong, and how to rebuild it.
"""

from __future__ import annotations

import contextlib
import json
from pathlib import Path

import numpy as np
import xarray as xr
from filelock import FileLock, Timeout

from uavdamp.io import open_dataset


@contextlib.contextmanager
def exclusive(path):
    """Hold the lock of output `path` (a hidden `.NAME.lock` beside it) for the block; ValueError if it is held."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    lock = FileLock(path.parent / f".{path.name}.lock")
    try:
        lock.acquire(timeout=0)
    except Timeout:
        raise ValueError(
            f"{path}: another process is writing this chunk (lock {lock.lock_file} is held): a job of "
            "an earlier, killed run is still running; stop it (README, 'A killed run') or let it finish, "
            "then run Snakemake again"
        ) from None
    try:
        yield
    finally:
        lock.release()


def rebuild_command(path) -> str:
    return f"rm {path} && snakemake -j2 all (with the same --configfile options)"


def load_chunk(path, *, points: np.ndarray, config: dict) -> xr.Dataset:
    """The chunk at `path`, checked: readable, over the `points` it should hold, made with `config` (the rule's
    reference_table and platform views), every criterion finite and positive where the point did not fail."""

    def bad(what: str) -> ValueError:
        return ValueError(f"reference-table chunk {path}: {what}; rebuild it: {rebuild_command(path)}")

    try:
        ds = open_dataset(path)
    except (OSError, ValueError, RuntimeError) as error:  # truncated or not NetCDF: netCDF4/HDF5 errors
        raise bad(f"cannot be read ({type(error).__name__}: {error})") from None
    if "point" not in ds.dims or "failed" not in ds or not any(v.startswith("criterion") for v in ds.data_vars):
        raise bad(f"has no point dimension, failed flag or criterion (variables {sorted(ds.data_vars)})")
    if not np.array_equal(ds.point.values, np.sort(np.asarray(points))):
        raise bad(
            f"holds points {ds.point.values[:5].tolist()}... , not this chunk's {np.sort(points)[:5].tolist()}..."
        )
    stored = {key: json.loads(value) for key, value in ds.attrs.items() if key == "config_reference_table"}
    if stored.get("config_reference_table") != json.loads(json.dumps(config, sort_keys=True)):
        raise bad("was made with another config than the current one")
    ok = ds.failed.values == 0
    for name in (v for v in ds.data_vars if v.startswith("criterion")):
        values = ds[name].values
        if not np.all(np.isfinite(values[..., ok]) & (values[..., ok] > 0)):
            raise bad(f"{name} is not finite and positive at every point not flagged as failed")
    return ds
