"""Reference-table grid search: the camera criterion over (f_y, f_z, K, C), in chunks, with joblib.

Each grid point drives the isolated platform with y = A sin(2 pi f_y t), z = A sin(2 pi f_z t)
at stiffness K and constant damping C for `duration` s; every criterion of `uavdamp.criterion`
(displacement, the paper's; line_of_sight; blur, with a camera) is scored over every named window
(`transient`, `steady`, ...) of that one run. The grid holds one variable per criterion
(`criterion_<name>` over (window, freq_y, freq_z, stiffness, damping)): each has its own units.

Two plants (config `platform.backend`): "linear" (default; `uavdamp.linear_plant`, every (f_y, f_z)
of one (K, C) at once from one discretisation) or "exudyn" (time stepping, point by point).
Points are numbered in C order over (freq_y, freq_z, stiffness, damping); they are grouped in
(K, C) blocks, and chunk i of N takes blocks i, i + N, i + 2N, ... so that every chunk sees the
whole range of K and C. A block or point that fails gives NaN and `failed = 1`; it never stops the
chunk. `verify` reruns a seeded sample of points (the grid's corners included) with the Exudyn
plant and `check_verification` fails, naming the worst point, above a relative tolerance.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass

import numpy as np
import xarray as xr

from uavdamp import criterion as crit
from uavdamp.camera import CameraModel
from uavdamp.contract import SolverFailed
from uavdamp.excitation import sine_input
from uavdamp.linear_plant import LinearPlant, sine_criteria
from uavdamp.platform import ExudynPlant, PlatformParams
from uavdamp.progress import each

DIMS = ("freq_y", "freq_z", "stiffness", "damping")
COORD_ATTRS = {
    "freq_y": {"units": "Hz", "long_name": "fuselage input frequency, y (lateral) axis"},
    "freq_z": {"units": "Hz", "long_name": "fuselage input frequency, z (vertical) axis"},
    "stiffness": {"units": "N m-1", "long_name": "isolator stiffness K"},
    "damping": {"units": "N s m-1", "long_name": "isolator damping C (constant)"},
}
FAILED_ATTRS = {"units": "1", "long_name": "1 where the solver failed (criterion NaN)"}
POINT_LABEL = "flat grid point index, C order over (freq_y, freq_z, stiffness, damping)"


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
    windows: dict  # {name: (start, end)} s, criterion windows
    camera: CameraModel | None = None  # the blur criterion's camera; None: no blur criterion

    @classmethod
    def from_config(cls, cfg: dict, camera: dict | CameraModel | None = None) -> GridSpec:
        """From the `reference_table` section (and the `camera` section); checks `criterion` and `window`
        (the table's choice) where the section holds them."""
        if not isinstance(cfg.get("windows"), dict) or not cfg["windows"]:
            raise ValueError("reference_table.windows: need a mapping {name: [start, end]} s")
        if camera is not None and not isinstance(camera, CameraModel):
            camera = CameraModel.from_config(camera)
        spec = cls(
            freq_y=axis_values(cfg["freq_y_hz"], "freq_y_hz"),
            freq_z=axis_values(cfg["freq_z_hz"], "freq_z_hz"),
            stiffness=axis_values(cfg["stiffness"], "stiffness"),
            damping=axis_values(cfg["damping"], "damping"),
            amplitude=float(cfg["amplitude"]),
            duration=float(cfg["duration"]),
            windows={str(name): (float(w[0]), float(w[1])) for name, w in cfg["windows"].items()},
            camera=camera,
        )
        spec.validate()
        if "criterion" in cfg or "window" in cfg:
            crit.check_choice(cfg.get("criterion"), cfg.get("window"), spec.windows)
        return spec

    def validate(self) -> None:
        for key, values in (
            ("freq_y_hz", self.freq_y),
            ("freq_z_hz", self.freq_z),
            ("stiffness", self.stiffness),
            ("damping", self.damping),
        ):
            if values.min() <= 0:
                raise ValueError(f"reference_table.{key}: values must be positive")
        if not self.amplitude > 0:
            raise ValueError(f"reference_table.amplitude: must be positive, got {self.amplitude}")
        for name, (start, end) in self.windows.items():
            if not 0 <= start < end <= self.duration:
                raise ValueError(
                    f"reference_table.windows.{name}: need 0 <= start < end <= duration "
                    f"({self.duration} s), got {[start, end]}"
                )

    @property
    def criteria(self) -> tuple[str, ...]:
        """The criteria this grid scores (`criterion.CRITERIA` order; blur only with a camera)."""
        return tuple(name for name in crit.CRITERIA if name != "blur" or self.camera is not None)

    @property
    def n_values(self) -> tuple[int, int]:
        """(criteria, windows) per point."""
        return len(self.criteria), len(self.windows)

    def window_coords(self) -> dict:
        """The `window` coordinate (names) with its start and end, s."""
        names = np.array(list(self.windows), dtype=object)
        bounds = np.array(list(self.windows.values()))
        return {
            "window": ("window", names, crit.WINDOW_ATTRS),
            "window_start": ("window", bounds[:, 0], {"units": "s", "long_name": "criterion window start"}),
            "window_end": ("window", bounds[:, 1], {"units": "s", "long_name": "criterion window end"}),
        }

    def check_damper_bounds(self, params: PlatformParams) -> None:
        """The damping axis must lie within the platform's damper bounds (else C would be clipped)."""
        if self.damping.min() < params.damping_min or self.damping.max() > params.damping_max:
            raise ValueError(
                f"reference_table.damping: [{self.damping.min()}, {self.damping.max()}] N s/m lies "
                f"outside the damper bounds platform.isolator.damping_min/max "
                f"[{params.damping_min}, {params.damping_max}]"
            )

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
        return {
            name: (name, values, COORD_ATTRS[name])
            for name, values in zip(DIMS, (self.freq_y, self.freq_z, self.stiffness, self.damping), strict=True)
        }


def chunk_blocks(spec: GridSpec, n_chunks: int, chunk: int) -> np.ndarray:
    """(K, C) blocks (flat index ik * n_damping + ic) of chunk `chunk` (0-based) of `n_chunks`: chunk, chunk + N, ..."""
    if not 0 <= chunk < n_chunks:
        raise ValueError(f"chunk {chunk} outside 0..{n_chunks - 1}")
    return np.arange(chunk, spec.stiffness.size * spec.damping.size, n_chunks)


def block_points(spec: GridSpec, block: int) -> np.ndarray:
    """Flat point indices of one (K, C) block, C order over (freq_y, freq_z)."""
    ik, ic = divmod(int(block), spec.damping.size)
    iy, iz = np.meshgrid(np.arange(spec.freq_y.size), np.arange(spec.freq_z.size), indexing="ij")
    return np.ravel_multi_index((iy.ravel(), iz.ravel(), ik, ic), spec.shape)


def chunk_points(spec: GridSpec, n_chunks: int, chunk: int) -> np.ndarray:
    """Flat point indices of a chunk, block by block."""
    blocks = chunk_blocks(spec, n_chunks, chunk)
    return np.concatenate([block_points(spec, b) for b in blocks]) if blocks.size else np.empty(0, dtype=int)


@dataclass(frozen=True)
class VerifySpec:
    """The pipeline's check of the grid against the Exudyn plant (config `reference_table.verify`)."""

    n_points: int  # points rerun, the grid's corners first
    tolerance: dict  # 1, largest relative difference allowed per criterion (a number in the config: every one)
    seed: int  # of the random points beyond the corners

    @classmethod
    def from_config(cls, cfg: dict) -> VerifySpec:
        unknown = sorted(set(cfg) - {"n_points", "tolerance", "seed"})
        if unknown:
            raise ValueError(f"reference_table.verify: unknown key(s) {unknown}")
        given = cfg["tolerance"]
        tolerance = (
            {str(k): float(v) for k, v in given.items()}
            if isinstance(given, dict)
            else dict.fromkeys(crit.CRITERIA, float(given))
        )
        spec = cls(n_points=int(cfg["n_points"]), tolerance=tolerance, seed=int(cfg["seed"]))
        if spec.n_points < 1:
            raise ValueError(f"reference_table.verify.n_points: must be >= 1, got {spec.n_points}")
        for name, value in tolerance.items():
            if name not in crit.CRITERIA:
                raise ValueError(f"reference_table.verify.tolerance: {name!r} is not one of {list(crit.CRITERIA)}")
            if not value > 0:
                raise ValueError(f"reference_table.verify.tolerance: must be > 0, got {value} ({name})")
        missing = sorted(set(crit.CRITERIA) - set(tolerance))
        if missing:
            raise ValueError(f"reference_table.verify.tolerance: no tolerance for {missing}")
        return spec


def split_platform(platform: dict) -> tuple[str, dict]:
    """(the plant `platform.backend` names, the platform section)."""
    return PlatformParams.from_config(platform).backend, platform


# ------------------------------------------------------------------------------------------ workers

_PLANTS: dict[str, dict] = {}  # one built model per worker process and platform config


def _plant(platform: dict, backend: str) -> tuple[ExudynPlant | LinearPlant, float]:
    """The worker's cached plant for this platform config and backend, and the build time it cost now (s)."""
    key = json.dumps(platform, sort_keys=True)
    if key not in _PLANTS:
        _PLANTS.clear()
        _PLANTS[key] = {}
    cached = _PLANTS[key]
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
    t, y, z = sine_input(freq_y, freq_z, spec.amplitude, spec.duration, sim.params.time_step)
    ds = sim.run(t, y, z, stiffness=stiffness, law=damping)
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


def evaluate_batch(platform: dict, spec: GridSpec, blocks: np.ndarray, backend: str = "linear") -> dict:
    """Criteria of every point of `blocks`; failures become NaN with a flag and the error text.

    Returns arrays over the blocks' points (criterion: (points, criteria, windows)) and the time spent
    building, in the plant and in total (s).
    """
    from threadpoolctl import threadpool_limits

    t0 = time.perf_counter()
    plant, build_time = _plant(platform, backend)
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


def criterion_variables(spec: GridSpec, values: np.ndarray, dims: tuple[str, ...]) -> dict:
    """{criterion_<name>: (("window", *dims), values of that criterion, attrs)} from (..., criteria, windows)."""
    return {
        crit.variable(name): (("window", *dims), np.moveaxis(values[..., j, :], -1, 0), crit.CRITERIA[name])
        for j, name in enumerate(spec.criteria)
    }


def _fan_out(function, batches: list, n_jobs: int, progress: bool) -> list:
    """function(batch) for every batch, in-process (n_jobs 1) or on n_jobs loky workers, one BLAS thread each."""
    from joblib import Parallel, delayed, parallel_config

    if n_jobs == 1:
        return list(_progress((function(b) for b in batches), len(batches), progress))
    with parallel_config(backend="loky", inner_max_num_threads=1):
        results = Parallel(n_jobs=n_jobs, return_as="generator")(delayed(function)(b) for b in batches)
        return list(_progress(results, len(batches), progress))


def run_chunk(
    platform: dict,
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
    from functools import partial

    t0 = time.perf_counter()
    backend, model = split_platform(platform)
    blocks = chunk_blocks(spec, n_chunks, chunk)
    n_batches = max(1, min(blocks.size, n_jobs * batches_per_job))
    batches = [b for b in np.array_split(blocks, n_batches) if b.size]
    parts = _fan_out(partial(evaluate_batch, model, spec, backend=backend), batches, n_jobs, progress)
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
            "plant": backend,
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


# ------------------------------------------------------------------------------------------ verification


class VerificationFailed(RuntimeError):
    """The grid's plant and the Exudyn plant disagree beyond the tolerance at some verification point."""


def verification_points(spec: GridSpec, n_points: int, seed: int) -> np.ndarray:
    """Flat indices: the grid's corners (all of them), then seeded random other points up to n_points."""
    ends = [np.unique([0, n - 1]) for n in spec.shape]
    corners = np.ravel_multi_index(tuple(g.ravel() for g in np.meshgrid(*ends, indexing="ij")), spec.shape)
    if n_points < corners.size:
        raise ValueError(
            f"reference_table.verify.n_points: must be >= the grid's {corners.size} corners, got {n_points}"
        )
    others = np.setdiff1d(np.arange(spec.size), corners)
    rng = np.random.default_rng(seed)
    extra = rng.choice(others, size=min(n_points - corners.size, others.size), replace=False)
    return np.concatenate([corners, np.sort(extra)]).astype(int)


def evaluate_points(platform: dict, spec: GridSpec, indices: np.ndarray, backend: str) -> np.ndarray:
    """Criteria (points, criteria, windows) of single points with one plant (NaN where the Exudyn solver fails)."""
    from threadpoolctl import threadpool_limits

    plant, _ = _plant(platform, backend)
    values = np.full((len(indices), *spec.n_values), np.nan)
    with threadpool_limits(limits=1):
        for k, index in enumerate(indices):
            fy, fz, stiffness, damping = spec.point(int(index))
            if backend == "linear":
                one = sine_criteria(
                    plant, stiffness, damping, [fy], [fz], spec.amplitude, spec.duration, spec.windows, spec.camera
                )
                values[k] = [one[name][:, 0, 0] for name in spec.criteria]
                continue
            try:
                values[k] = evaluate(plant, spec, (fy, fz, stiffness, damping))
            except (SolverFailed, FloatingPointError):
                pass
    return values


def grid_values(spec: GridSpec, full: xr.Dataset) -> np.ndarray:
    """The grid's criteria as (points in flat order, criteria, windows)."""
    return np.stack(
        [full[crit.variable(n)].transpose(*DIMS, "window").values.reshape(spec.size, -1) for n in spec.criteria], axis=1
    )


def verify(platform: dict, spec: GridSpec, full: xr.Dataset, check: VerifySpec, n_jobs: int = 1) -> xr.Dataset:
    """Rerun `check.n_points` points with the Exudyn plant (and the linear one where the grid is Exudyn's).

    Returns `verify_point` (verify), `verify_<criterion>_linear` and `_exudyn` (verify, window) per criterion,
    `verify_relative_difference` (verify, criterion, window) and the scalar `verify_max_relative_difference`
    (inf where an Exudyn run failed).
    """
    from functools import partial

    backend, model = split_platform(platform)
    points = verification_points(spec, check.n_points, check.seed)
    on_grid = grid_values(spec, full)[points]
    batches = [b for b in np.array_split(points, max(1, min(points.size, 2 * n_jobs))) if b.size]
    other = "exudyn" if backend == "linear" else "linear"
    rerun = np.concatenate(_fan_out(partial(evaluate_points, model, spec, backend=other), batches, n_jobs, False))
    linear, exudyn = (on_grid, rerun) if backend == "linear" else (rerun, on_grid)
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = np.abs(linear - exudyn) / np.abs(exudyn)
    relative = np.where(np.isfinite(relative), relative, np.inf)
    data = {
        "verify_point": ("verify", points, {"units": "1", "long_name": POINT_LABEL}),
        "verify_relative_difference": (
            ("verify", "criterion", "window"),
            relative,
            {"units": "1", "long_name": "|linear - Exudyn| / Exudyn"},
        ),
        "verify_max_relative_difference": (
            (),
            float(relative.max()),
            {"units": "1", "long_name": "largest relative criterion difference, linear vs Exudyn plant"},
        ),
    }
    for j, name in enumerate(spec.criteria):
        for plant, values in (("linear", linear), ("exudyn", exudyn)):
            data[f"verify_{name}_{plant}"] = (
                ("verify", "window"),
                values[:, j],
                {"units": crit.CRITERIA[name]["units"], "long_name": f"{name} criterion, {plant} plant"},
            )
    coords = {
        "criterion": (
            "criterion",
            np.array(spec.criteria, dtype=object),
            {"units": "1", "long_name": "camera criterion"},
        ),
        **spec.window_coords(),
    }
    tolerance = json.dumps(check.tolerance, sort_keys=True)
    return xr.Dataset(data, coords=coords, attrs={"verify_seed": check.seed, "verify_tolerance": tolerance})


def check_verification(spec: GridSpec, checked: xr.Dataset, tolerance: float | dict) -> None:
    """Raise VerificationFailed naming the worst point, criterion and window if a relative difference exceeds
    its criterion's `tolerance` (a number: every criterion's)."""
    relative = checked.verify_relative_difference.transpose("verify", "criterion", "window").values
    limit = np.array([tolerance[n] if isinstance(tolerance, dict) else tolerance for n in spec.criteria])
    p, j, w = np.unravel_index(int(np.argmax(relative / limit[:, None])), relative.shape)
    if relative[p, j, w] > limit[j]:
        index = int(checked.verify_point.values[p])
        fy, fz, k, c = spec.point(index)
        name, window = spec.criteria[j], list(spec.windows)[w]
        units = crit.CRITERIA[name]["units"]
        linear, exudyn = (checked[f"verify_{name}_{plant}"].values[p, w] for plant in ("linear", "exudyn"))
        raise VerificationFailed(
            f"linear and Exudyn plants differ by {relative[p, j, w]:.3%} (tolerance {limit[j]:.3%}) in the {name} "
            f"criterion, window {window}, at point {index} (f_y {fy:g} Hz, f_z {fz:g} Hz, K {k:g} N/m, C {c:g} "
            f"N s/m): linear {linear:.6g} {units}, Exudyn {exudyn:.6g} {units}"
        )
