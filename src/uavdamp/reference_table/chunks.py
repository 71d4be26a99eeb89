"""The grid in chunks: each chunk's criteria (joblib over its (K, C) blocks), one writer per chunk, every chunk
checked before the gather merges them.

Two plants (config `platform.backend`): "linear" (default; `uavdamp.platform.LinearPlant`, every (f_y, f_z) of
one (K, C) at once from one discretisation, `uavdamp.reference_table.sine_batch`) or "exudyn" (time stepping,
point by point). A block or point that fails gives NaN and `failed = 1`; it never stops the chunk.

`exclusive(path)` (`uavdamp.io.exclusive`) holds an OS file lock beside a chunk while a job computes and writes it,
so a surviving job of a killed run and a restarted run cannot write the same chunk at the same time: the second
one waits for the first and keeps the chunk it finished (`finished_chunk`). `load_chunk` opens a chunk and checks
what the gather relies on; any problem is a ValueError naming the file, what is wrong, and how to rebuild it.
"""

from __future__ import annotations

import json
import time
from functools import partial

import numpy as np
import xarray as xr
from joblib import Parallel, delayed, parallel_config
from threadpoolctl import threadpool_limits

from uavdamp import io
from uavdamp.contract import SolverFailed
from uavdamp.damping.laws import Constant
from uavdamp.io import exclusive, open_dataset  # noqa: F401  (exclusive: the chunk job's lock, io's)
from uavdamp.platform import ExudynPlant, LinearPlant, PlatformParams
from uavdamp.progress import each
from uavdamp.reference_table import criteria as crit
from uavdamp.reference_table.grid import (
    DIMS,
    FAILED_ATTRS,
    POINT_LABEL,
    GridSpec,
    block_points,
    chunk_blocks,
    criterion_variables,
)
from uavdamp.reference_table.sine_batch import sine_criteria
from uavdamp.sources.excitation import sine_input


def rebuild_command(path) -> str:
    return io.rebuild_command(path)


def load_chunk(path, *, points: np.ndarray, config: dict) -> xr.Dataset:
    """The chunk at `path`, checked: readable, over the `points` it should hold, made with `config` (the rule's
    reference_table and platform views), every criterion finite and positive where the point did not fail."""

    def bad(what: str) -> ValueError:
        return ValueError(f"reference-table chunk {path}: {what}; rebuild it: {rebuild_command(path)}")

    try:
        ds = open_dataset(path)
    except io.CorruptOutput as error:  # truncated, not NetCDF, a failed checksum, unreadable metadata
        raise bad(f"cannot be read ({error.reason})") from None
    except OSError as error:
        raise bad(f"cannot be read ({type(error).__name__}: {error})") from None
    try:
        return _checked(ds, points, config, bad)
    except (AttributeError, KeyError, TypeError, IndexError, json.JSONDecodeError) as error:  # damaged metadata
        raise bad(f"has damaged metadata ({type(error).__name__}: {error})") from None


def _checked(ds: xr.Dataset, points: np.ndarray, config: dict, bad) -> xr.Dataset:
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
    for key in ("window",):
        if key not in ds.coords:
            raise bad(f"has no {key} coordinate")
    json.loads(ds.attrs.get("errors", "[]"))  # the gather merges them
    return ds


def finished_chunk(path, *, points: np.ndarray, config: dict) -> bool:
    """True if `path` holds a valid finished chunk of these points and config (`load_chunk` passes)."""
    try:
        load_chunk(path, points=points, config=config)
    except (ValueError, FileNotFoundError):
        return False
    return True


_PLANTS: dict[PlatformParams, dict] = {}  # one built model per worker process and platform


def plant_for(platform: PlatformParams, backend: str) -> tuple[ExudynPlant | LinearPlant, float]:
    """The worker's cached plant for this platform and backend, and the build time it cost now (s)."""
    if platform not in _PLANTS:
        _PLANTS.clear()
        _PLANTS[platform] = {}
    cached = _PLANTS[platform]
    if backend in cached:
        return cached[backend], 0.0
    t0 = time.perf_counter()
    if "exudyn" not in cached:
        cached["exudyn"] = ExudynPlant(platform, mount="isolated")
    if backend == "linear":
        cached["linear"] = LinearPlant(cached["exudyn"].model)
    return cached[backend], time.perf_counter() - t0


def evaluate(sim: ExudynPlant, spec: GridSpec, point: tuple[float, float, float, float]) -> np.ndarray:
    """Criteria (criteria, windows) of one grid point with the Exudyn plant (raises SolverFailed if it stops)."""
    freq_y, freq_z, stiffness, damping = point
    t, mount = sine_input(freq_y, freq_z, spec.amplitude, spec.duration, sim.params.time_step)
    ds = sim.run(t, mount, stiffness=stiffness, law=Constant(damping))
    if spec.camera is None:
        return np.array(
            [
                [crit.camera_criterion(ds.camera_displacement, w) for w in spec.windows.values()],
                [crit.line_of_sight_criterion(ds, w) for w in spec.windows.values()],
            ]
        )
    return crit.response_criteria(ds, spec.windows, spec.camera)


def evaluate_block(plant: LinearPlant, spec: GridSpec, block: int) -> np.ndarray:
    """Criteria of every (f_y, f_z) of one (K, C) block with the linear plant: (f_y x f_z in C order, criteria,
    windows)."""
    ik, ic = divmod(int(block), spec.damping.size)
    values = sine_criteria(
        plant,
        spec.stiffness[ik],
        spec.damping[ic],
        spec.freq_y,
        spec.freq_z,
        spec.amplitude,
        spec.duration,
        spec.windows,
        spec.camera,
    )
    stacked = np.stack([values[name] for name in spec.criteria])  # (criteria, windows, f_y, f_z)
    return stacked.reshape(*spec.n_values, -1).transpose(2, 0, 1)


def evaluate_batch(platform: PlatformParams, spec: GridSpec, blocks: np.ndarray) -> dict:
    """Criteria of every point of `blocks`; failures become NaN with a flag and the error text.

    Returns arrays over the blocks' points (criterion: (points, criteria, windows)) and the time spent
    building, in the plant and in total (s).
    """
    t0 = time.perf_counter()
    backend = platform.backend
    plant, build_time = plant_for(platform, backend)
    indices = np.concatenate([block_points(spec, b) for b in blocks])
    values = np.full((indices.size, *spec.n_values), np.nan)
    failed = np.zeros(indices.size, dtype=np.int8)
    errors: list[str] = []
    solve_time = 0.0
    per_block = spec.freq_y.size * spec.freq_z.size
    with threadpool_limits(limits=1):  # small matrices: BLAS threads only contend
        for b, block in enumerate(blocks):
            part = slice(b * per_block, (b + 1) * per_block)
            if backend == "linear":
                t1 = time.perf_counter()
                try:
                    values[part] = evaluate_block(plant, spec, block)
                except (np.linalg.LinAlgError, FloatingPointError) as error:
                    failed[part] = 1
                    errors.append(f"block {int(block)} (K, C) = {spec.point(int(indices[part][0]))[2:]}: {error}")
                solve_time += time.perf_counter() - t1
                continue
            for k in range(part.start, part.stop):
                index = int(indices[k])
                try:
                    values[k] = evaluate(plant, spec, spec.point(index))
                except (SolverFailed, FloatingPointError) as error:
                    failed[k] = 1
                    errors.append(f"point {index} {spec.point(index)}: {error}")
                solve_time += plant.solve_time
    failed[np.isnan(values).any(axis=(1, 2))] = 1
    values[failed == 1] = np.nan
    return {
        "indices": indices,
        "criterion": values,
        "failed": failed,
        "errors": errors,
        "build_time": build_time,
        "solve_time": solve_time,
        "wall_time": time.perf_counter() - t0,
    }


def fan_out(function, batches: list, n_jobs: int, progress: bool) -> list:
    """function(batch) for every batch, in-process (n_jobs 1) or on n_jobs loky workers, one BLAS thread each."""
    if n_jobs == 1:
        return list(_progress((function(b) for b in batches), len(batches), progress))
    with parallel_config(backend="loky", inner_max_num_threads=1):
        results = Parallel(n_jobs=n_jobs, return_as="generator")(delayed(function)(b) for b in batches)
        return list(_progress(results, len(batches), progress))


def run_chunk(
    platform: PlatformParams,
    spec: GridSpec,
    *,
    n_chunks: int = 1,
    chunk: int = 0,
    n_jobs: int = 1,
    batches_per_job: int = 4,
    progress: bool = False,
) -> xr.Dataset:
    """Evaluate one chunk's points with `n_jobs` joblib workers on the plant `platform.backend` names.

    Returns a dataset over `point` (flat grid index) with `criterion_<name>` (window, point) per criterion
    and `failed`, 1; the plant, timing and failure counts in its attributes.
    """
    t0 = time.perf_counter()
    blocks = chunk_blocks(spec, n_chunks, chunk)
    n_batches = max(1, min(blocks.size, n_jobs * batches_per_job))
    batches = [b for b in np.array_split(blocks, n_batches) if b.size]
    parts = fan_out(partial(evaluate_batch, platform, spec), batches, n_jobs, progress)
    indices = np.concatenate([p["indices"] for p in parts]) if parts else np.empty(0, dtype=int)
    criterion = np.concatenate([p["criterion"] for p in parts]) if parts else np.empty((0, *spec.n_values))
    failed = np.concatenate([p["failed"] for p in parts]) if parts else np.empty(0, dtype=np.int8)
    errors = [e for p in parts for e in p["errors"]]
    order = np.argsort(indices, kind="stable")  # CF: a coordinate is strictly monotonic
    indices, criterion, failed = indices[order], criterion[order], failed[order]
    point_attrs = {"units": "1", "long_name": POINT_LABEL}
    return xr.Dataset(
        {**criterion_variables(spec, criterion, ("point",)), "failed": ("point", failed, FAILED_ATTRS)},
        coords={"point": ("point", indices, point_attrs), **spec.window_coords()},
        attrs={
            "plant": platform.backend,
            "chunk": chunk,
            "n_chunks": n_chunks,
            "n_jobs": n_jobs,
            "n_failed": int(failed.sum()),
            "errors": json.dumps(errors),
            "build_time_s": sum(p["build_time"] for p in parts),
            "solver_time_s": sum(p["solve_time"] for p in parts),
            "worker_time_s": sum(p["wall_time"] for p in parts),
            "wall_time_s": time.perf_counter() - t0,
        },
    )


def _progress(iterable, total: int, show: bool):
    """A console bar over the batches (`uavdamp.progress`: on the terminal, not in the job's log)."""
    return each(iterable, total, "grid chunk", "batch") if show else iterable


def merge_chunks(spec: GridSpec, chunks: list[xr.Dataset]) -> xr.Dataset:
    """The full grid from chunk datasets: `criterion_<name>` over (window, freq_y, freq_z, stiffness, damping)
    per criterion, and `failed` over (freq_y, freq_z, stiffness, damping).

    Raises ValueError if a point is missing or present twice (no point is silently dropped), or if the
    chunks come from different plants.
    """
    criterion = np.full((spec.size, *spec.n_values), np.nan)
    failed = np.zeros(spec.size, dtype=np.int8)
    seen = np.zeros(spec.size, dtype=int)
    for ds in chunks:
        idx = ds.point.values.astype(int)
        missing = [crit.variable(n) for n in spec.criteria if crit.variable(n) not in ds]
        if missing or list(ds.window.values) != list(spec.windows):
            raise ValueError(
                f"a chunk lacks {missing} or has windows {list(ds.window.values)} (the grid: "
                f"{list(spec.windows)}): rerun the chunks"
            )
        criterion[idx] = np.stack(
            [ds[crit.variable(n)].transpose("point", "window").values for n in spec.criteria], axis=1
        )
        failed[idx] = ds.failed.values
        np.add.at(seen, idx, 1)
    if np.any(seen != 1):
        missing, doubled = np.flatnonzero(seen == 0), np.flatnonzero(seen > 1)
        raise ValueError(
            f"chunks do not cover the grid exactly: {missing.size} points missing "
            f"(first {missing[:5].tolist()}), {doubled.size} present twice"
        )
    if np.any(np.isnan(criterion).any(axis=(1, 2)) & (failed == 0)):
        raise ValueError("a point has no criterion but is not flagged as failed")
    plants = sorted({ds.attrs.get("plant", "exudyn") for ds in chunks})
    if len(plants) > 1:
        raise ValueError(f"chunks come from different plants {plants}: rerun the grid with one platform.backend")
    errors = [e for ds in chunks for e in json.loads(ds.attrs.get("errors", "[]"))]
    return xr.Dataset(
        {
            **criterion_variables(spec, criterion.reshape(*spec.shape, *spec.n_values), DIMS),
            "failed": (DIMS, failed.reshape(spec.shape), FAILED_ATTRS),
        },
        coords={**spec.coords(), **spec.window_coords()},
        attrs={
            "plant": plants[0] if plants else "linear",
            "n_points": spec.size,
            "n_failed": int(failed.sum()),
            "errors": json.dumps(errors),
            "amplitude_m": spec.amplitude,
            "duration_s": spec.duration,
            "criteria": list(spec.criteria),
            **(spec.camera.attrs() if spec.camera else {}),
            "solver_time_s": float(sum(ds.attrs.get("solver_time_s", 0.0) for ds in chunks)),
            "build_time_s": float(sum(ds.attrs.get("build_time_s", 0.0) for ds in chunks)),
            "worker_time_s": float(sum(ds.attrs.get("worker_time_s", 0.0) for ds in chunks)),
        },
    )
