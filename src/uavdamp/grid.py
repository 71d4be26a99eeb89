"""Reference-table grid search: the camera criterion over (f_y, f_z, K, C), in chunks, with joblib.

Each grid point drives the isolated platform with y = A sin(2 pi f_y t), z = A sin(2 pi f_z t)
at stiffness K and constant damping C; the criterion is sqrt(sigma_y^2 + sigma_z^2), the
standard deviations (1/N, the paper's Eq. 1) of the camera displacement over a window.

Points are numbered in C order over (freq_y, freq_z, stiffness, damping); chunk i of N takes
points i, i + N, i + 2N, ... so that every chunk sees the whole range of inputs. A point whose
solver fails gives NaN and `failed = 1`; it never stops the chunk.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass

import numpy as np
import xarray as xr

from uavdamp import criterion as crit
from uavdamp.contract import SolverFailed
from uavdamp.excitation import sine_input
from uavdamp.platform import ExudynPlant, PlatformParams

DIMS = ("freq_y", "freq_z", "stiffness", "damping")
COORD_ATTRS = {
    "freq_y": {"units": "Hz", "long_name": "fuselage input frequency, y (lateral) axis"},
    "freq_z": {"units": "Hz", "long_name": "fuselage input frequency, z (vertical) axis"},
    "stiffness": {"units": "N m-1", "long_name": "isolator stiffness K"},
    "damping": {"units": "N s m-1", "long_name": "isolator damping C (constant)"},
}
FAILED_ATTRS = {"units": "1", "long_name": "1 where the solver failed (criterion NaN)"}


def axis_values(spec: dict, key: str) -> np.ndarray:
    """Grid axis from {"values": [...]} or {"start", "stop", "num", "spacing": "linear" | "log"}."""
    if "values" in spec:
        values = np.asarray(spec["values"], dtype=float)
    else:
        start, stop, num = float(spec["start"]), float(spec["stop"]), int(spec["num"])
        if spec.get("spacing", "linear") == "log":
            if start <= 0:
                raise ValueError(f"reference_table.{key}.start: log spacing needs a positive start, got {start}")
            values = np.geomspace(start, stop, num)
        else:
            values = np.linspace(start, stop, num)
    if values.ndim != 1 or values.size == 0 or not np.all(np.isfinite(values)):
        raise ValueError(f"reference_table.{key}: need a non-empty list of finite numbers")
    if np.any(np.diff(values) <= 0):
        raise ValueError(f"reference_table.{key}: values must be strictly increasing")
    return values


@dataclass(frozen=True)
class GridSpec:
    """The grid and the run each point gets (config section `reference_table`)."""

    freq_y: np.ndarray  # Hz
    freq_z: np.ndarray  # Hz
    stiffness: np.ndarray  # N m-1
    damping: np.ndarray  # N s m-1
    amplitude: float  # m
    duration: float  # s
    window: tuple[float, float]  # s, criterion window [start, end]

    @classmethod
    def from_config(cls, cfg: dict) -> "GridSpec":
        spec = cls(
            freq_y=axis_values(cfg["freq_y_hz"], "freq_y_hz"),
            freq_z=axis_values(cfg["freq_z_hz"], "freq_z_hz"),
            stiffness=axis_values(cfg["stiffness"], "stiffness"),
            damping=axis_values(cfg["damping"], "damping"),
            amplitude=float(cfg["amplitude"]),
            duration=float(cfg["duration"]),
            window=(float(cfg["window"][0]), float(cfg["window"][1])),
        )
        spec.validate()
        return spec

    def validate(self) -> None:
        for key, values in (("freq_y_hz", self.freq_y), ("freq_z_hz", self.freq_z), ("stiffness", self.stiffness),
                            ("damping", self.damping)):
            if values.min() <= 0:
                raise ValueError(f"reference_table.{key}: values must be positive")
        if not self.amplitude > 0:
            raise ValueError(f"reference_table.amplitude: must be positive, got {self.amplitude}")
        start, end = self.window
        if not 0 <= start < end <= self.duration:
            raise ValueError(f"reference_table.window: need 0 <= start < end <= duration ({self.duration} s), "
                             f"got {list(self.window)}")

    def check_damper_bounds(self, params: PlatformParams) -> None:
        """The damping axis must lie within the platform's damper bounds (else C would be clipped)."""
        if self.damping.min() < params.damping_min or self.damping.max() > params.damping_max:
            raise ValueError(f"reference_table.damping: [{self.damping.min()}, {self.damping.max()}] N s/m lies "
                             f"outside the damper bounds platform.isolator.damping_min/max "
                             f"[{params.damping_min}, {params.damping_max}]")

    @property
    def shape(self) -> tuple[int, int, int, int]:
        return (self.freq_y.size, self.freq_z.size, self.stiffness.size, self.damping.size)

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def point(self, index: int) -> tuple[float, float, float, float]:
        """(f_y Hz, f_z Hz, K N/m, C N s/m) of a flat point index."""
        iy, iz, ik, ic = np.unravel_index(index, self.shape)
        return (float(self.freq_y[iy]), float(self.freq_z[iz]), float(self.stiffness[ik]), float(self.damping[ic]))

    def coords(self) -> dict:
        return {name: (name, values, COORD_ATTRS[name])
                for name, values in zip(DIMS, (self.freq_y, self.freq_z, self.stiffness, self.damping))}


def chunk_points(size: int, n_chunks: int, chunk: int) -> np.ndarray:
    """Flat point indices of chunk `chunk` (0-based) of `n_chunks`: chunk, chunk + n_chunks, ..."""
    if not 0 <= chunk < n_chunks:
        raise ValueError(f"chunk {chunk} outside 0..{n_chunks - 1}")
    return np.arange(chunk, size, n_chunks)


# ------------------------------------------------------------------------------------------ workers

_SIMULATORS: dict[str, ExudynPlant] = {}  # one built model per worker process and platform config


def _simulator(platform: dict) -> tuple[ExudynPlant, float]:
    """The worker's cached simulator for this platform config, and the build time it cost now (s)."""
    key = json.dumps(platform, sort_keys=True)
    if key in _SIMULATORS:
        return _SIMULATORS[key], 0.0
    sim = ExudynPlant(platform, mount="isolated")
    _SIMULATORS.clear()
    _SIMULATORS[key] = sim
    return sim, sim.build_time


def evaluate(sim: ExudynPlant, spec: GridSpec, point: tuple[float, float, float, float]) -> float:
    """Criterion, m, of one grid point (raises SolverFailed if the solver stops)."""
    freq_y, freq_z, stiffness, damping = point
    t, y, z = sine_input(freq_y, freq_z, spec.amplitude, spec.duration, sim.params.time_step)
    ds = sim.run(t, y, z, stiffness=stiffness, law=damping)
    return crit.camera_criterion(ds.camera_displacement, spec.window)


def evaluate_batch(platform: dict, spec: GridSpec, indices: np.ndarray, fail: frozenset = frozenset()) -> dict:
    """Criterion of each point in `indices`; failures become NaN with a flag and the error text.

    `fail` holds point indices forced to fail (tests of the failure path). Returns arrays and the
    time spent building, in the solver, and in total (s).
    """
    t0 = time.perf_counter()
    sim, build_time = _simulator(platform)
    values = np.full(indices.size, np.nan)
    failed = np.zeros(indices.size, dtype=np.int8)
    errors: list[str] = []
    solve_time = 0.0
    for k, index in enumerate(indices):
        try:
            if int(index) in fail:
                raise SolverFailed(f"forced failure of point {int(index)}")
            values[k] = evaluate(sim, spec, spec.point(int(index)))
        except (SolverFailed, FloatingPointError) as error:
            failed[k] = 1
            errors.append(f"point {int(index)} {spec.point(int(index))}: {error}")
        solve_time += sim.solve_time
    return {"indices": indices, "criterion": values, "failed": failed, "errors": errors,
            "build_time": build_time, "solve_time": solve_time, "wall_time": time.perf_counter() - t0}


def run_chunk(platform: dict, spec: GridSpec, *, n_chunks: int = 1, chunk: int = 0, n_jobs: int = 1,
              batches_per_job: int = 4, progress: bool = False, fail: frozenset = frozenset()) -> xr.Dataset:
    """Evaluate one chunk's points with `n_jobs` joblib workers (loky, one BLAS thread each).

    Returns a dataset over `point` (flat grid index) with `criterion`, m, and `failed`, 1; timing
    and failure counts in its attributes.
    """
    from joblib import Parallel, delayed, parallel_config

    t0 = time.perf_counter()
    indices = chunk_points(spec.size, n_chunks, chunk)
    n_batches = max(1, min(indices.size, n_jobs * batches_per_job))
    batches = [b for b in np.array_split(indices, n_batches) if b.size]
    if n_jobs == 1:
        parts = list(_progress((evaluate_batch(platform, spec, b, fail) for b in batches), len(batches), progress))
    else:
        with parallel_config(backend="loky", inner_max_num_threads=1):
            results = Parallel(n_jobs=n_jobs, return_as="generator")(
                delayed(evaluate_batch)(platform, spec, b, fail) for b in batches)
            parts = list(_progress(results, len(batches), progress))
    criterion = np.concatenate([p["criterion"] for p in parts]) if parts else np.empty(0)
    failed = np.concatenate([p["failed"] for p in parts]) if parts else np.empty(0, dtype=np.int8)
    errors = [e for p in parts for e in p["errors"]]
    point_attrs = {"units": "1", "long_name": "flat grid point index, C order over (freq_y, freq_z, stiffness, damping)"}
    return xr.Dataset(
        {"criterion": ("point", criterion, crit.CRITERION_ATTRS),
         "failed": ("point", failed, FAILED_ATTRS)},
        coords={"point": ("point", indices, point_attrs)},
        attrs={"chunk": chunk, "n_chunks": n_chunks, "n_jobs": n_jobs, "n_failed": int(failed.sum()),
               "errors": json.dumps(errors), "build_time_s": sum(p["build_time"] for p in parts),
               "solver_time_s": sum(p["solve_time"] for p in parts),
               "worker_time_s": sum(p["wall_time"] for p in parts), "wall_time_s": time.perf_counter() - t0},
    )


def _progress(iterable, total: int, show: bool):
    if not show:
        return iterable
    from tqdm import tqdm

    return tqdm(iterable, total=total, unit="batch", mininterval=2.0)


def merge_chunks(spec: GridSpec, chunks: list[xr.Dataset]) -> xr.Dataset:
    """The full grid from chunk datasets: `criterion` and `failed` over (freq_y, freq_z, stiffness, damping).

    Raises ValueError if a point is missing or present twice (no point is silently dropped).
    """
    criterion = np.full(spec.size, np.nan)
    failed = np.zeros(spec.size, dtype=np.int8)
    seen = np.zeros(spec.size, dtype=int)
    for ds in chunks:
        idx = ds.point.values.astype(int)
        criterion[idx] = ds.criterion.values
        failed[idx] = ds.failed.values
        np.add.at(seen, idx, 1)
    if np.any(seen != 1):
        missing, doubled = np.flatnonzero(seen == 0), np.flatnonzero(seen > 1)
        raise ValueError(f"chunks do not cover the grid exactly: {missing.size} points missing "
                         f"(first {missing[:5].tolist()}), {doubled.size} present twice")
    if np.any(np.isnan(criterion) & (failed == 0)):
        raise ValueError("a point has no criterion but is not flagged as failed")
    errors = [e for ds in chunks for e in json.loads(ds.attrs.get("errors", "[]"))]
    return xr.Dataset(
        {"criterion": (DIMS, criterion.reshape(spec.shape), crit.CRITERION_ATTRS),
         "failed": (DIMS, failed.reshape(spec.shape), FAILED_ATTRS)},
        coords=spec.coords(),
        attrs={"n_points": spec.size, "n_failed": int(failed.sum()), "errors": json.dumps(errors),
               "amplitude_m": spec.amplitude, "duration_s": spec.duration, "window_s": list(spec.window),
               "solver_time_s": float(sum(ds.attrs.get("solver_time_s", 0.0) for ds in chunks)),
               "build_time_s": float(sum(ds.attrs.get("build_time_s", 0.0) for ds in chunks)),
               "worker_time_s": float(sum(ds.attrs.get("worker_time_s", 0.0) for ds in chunks))},
    )
