"""The reference-table grid as arrays (`GridSpec`), and how its points are numbered and chunked.

Each grid point drives the isolated platform with y = A sin(2 pi f_y t), z = A sin(2 pi f_z t) at stiffness K
and constant damping C for `duration` s; every criterion of `uavdamp.reference_table.criteria` is scored over
every named window of that one run (`uavdamp.reference_table.chunks` computes them).

Points are numbered in C order over (freq_y, freq_z, stiffness, damping); they are grouped in (K, C) blocks, and
chunk i of N takes blocks i, i + N, i + 2N, ... so that every chunk sees the whole range of K and C.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uavdamp.camera.optics import CameraOptics
from uavdamp.reference_table import criteria as crit
from uavdamp.reference_table.params import ReferenceGrid

DIMS = ("freq_y", "freq_z", "stiffness", "damping")
COORD_ATTRS = {
    "freq_y": {"units": "Hz", "long_name": "fuselage input frequency, y (lateral) axis"},
    "freq_z": {"units": "Hz", "long_name": "fuselage input frequency, z (vertical) axis"},
    "stiffness": {"units": "N m-1", "long_name": "isolator stiffness K"},
    "damping": {"units": "N s m-1", "long_name": "isolator damping C (constant)"},
}
FAILED_ATTRS = {"units": "1", "long_name": "1 where the solver failed (criterion NaN)"}
POINT_LABEL = "flat grid point index, C order over (freq_y, freq_z, stiffness, damping)"


@dataclass(frozen=True)
class GridSpec:
    """The grid's axes as arrays, the run each point gets, and the blur criterion's camera (None: no blur)."""

    freq_y: np.ndarray  # Hz
    freq_z: np.ndarray  # Hz
    stiffness: np.ndarray  # N m-1
    damping: np.ndarray  # N s m-1
    amplitude: float  # m
    duration: float  # s
    windows: dict  # {name: (start, end)} s, criterion windows
    camera: CameraOptics | None = None

    @classmethod
    def of(cls, grid: ReferenceGrid, camera: CameraOptics | None = None) -> GridSpec:
        """The spec of a parsed grid section (and the camera of the blur criterion)."""
        return cls(
            freq_y=grid.freq_y.array(),
            freq_z=grid.freq_z.array(),
            stiffness=grid.stiffness.array(),
            damping=grid.damping.array(),
            amplitude=grid.amplitude,
            duration=grid.duration,
            windows={name: (float(w[0]), float(w[1])) for name, w in grid.windows.items()},
            camera=camera,
        )

    @property
    def criteria(self) -> tuple[str, ...]:
        """The criteria this grid scores (`criteria.CRITERIA` order; blur only with a camera)."""
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


def criterion_variables(spec: GridSpec, values: np.ndarray, dims: tuple[str, ...]) -> dict:
    """{criterion_<name>: (("window", *dims), values of that criterion, attrs)} from (..., criteria, windows)."""
    return {
        crit.variable(name): (("window", *dims), np.moveaxis(values[..., j, :], -1, 0), crit.CRITERIA[name])
        for j, name in enumerate(spec.criteria)
    }
