"""The reference table's config section as typed sections: the grid, the verification, the table's choice, the jobs.

ReferenceGrid            what the chunks compute: axes (Hz, N m-1, N s m-1), amplitude, run length, windows
ReferenceTableSection    the section: the grid, the criterion and window the ANFIS learns, the flat band's
                         tolerance, the verification against Exudyn, chunks and threads
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uavdamp.reference_table.criteria import CRITERIA, check_choice
from uavdamp.settings import require, setting

SPACINGS = ("linear", "log")


@dataclass(frozen=True)
class Axis:
    """A grid axis: ``{values: [...]}`` or ``{start, stop, num, spacing: linear | log}``."""

    values: tuple[float, ...] | None = setting(default=None)
    start: float | None = setting(default=None)
    stop: float | None = setting(default=None)
    num: int | None = setting(default=None)
    spacing: str = setting(default="linear")

    def validate(self, where: str) -> None:
        ranged = (self.start, self.stop, self.num)
        if self.values is not None:
            require(all(v is None for v in ranged), where, "give either values or start, stop and num, not both")
        else:
            require(all(v is not None for v in ranged), where, "needs values, or start, stop and num")
            require(self.spacing in SPACINGS, f"{where}.spacing", f"must be one of {SPACINGS}, got {self.spacing!r}")
            require(self.num >= 1, f"{where}.num", f"must be >= 1, got {self.num}")
            if self.spacing == "log":
                require(self.start > 0, f"{where}.start", f"log spacing needs a positive start, got {self.start}")
        values = self.array()
        require(values.size > 0, where, "needs at least one value")
        require(bool(np.all(values > 0)), where, f"values must be positive, got {values.tolist()}")
        require(bool(np.all(np.diff(values) > 0)), where, "values must be strictly increasing")

    def array(self) -> np.ndarray:
        """The axis values."""
        if self.values is not None:
            return np.asarray(self.values, dtype=float)
        space = np.geomspace if self.spacing == "log" else np.linspace
        return space(self.start, self.stop, self.num)


@dataclass(frozen=True)
class ReferenceGrid:
    """What the grid computes (``reference_table`` without the table's and the jobs' options): the chunks' view."""

    freq_y: Axis = setting("freq_y_hz")  # Hz
    freq_z: Axis = setting("freq_z_hz")  # Hz
    stiffness: Axis = setting("stiffness_n_m")  # N m-1
    damping: Axis = setting("damping_n_s_m")  # N s m-1
    amplitude: float = setting("amplitude_m")  # m
    duration: float = setting("duration_s")  # s, run length of each point
    windows: dict[str, tuple[float, ...]] = setting("windows_s")  # s, {name: (start, end)}

    def validate(self) -> None:
        where = "reference_table."
        require(self.amplitude > 0, where + "amplitude_m", f"must be > 0, got {self.amplitude}")
        require(self.duration > 0, where + "duration_s", f"must be > 0, got {self.duration}")
        require(bool(self.windows), where + "windows_s", "needs at least one window {name: [start, end]}")
        for name, bounds in self.windows.items():
            require(
                len(bounds) == 2 and 0 <= bounds[0] < bounds[1] <= self.duration,
                f"{where}windows_s.{name}",
                f"need [start, end] with 0 <= start < end <= duration_s ({self.duration} s), got {list(bounds)}",
            )


@dataclass(frozen=True)
class VerifyOptions:
    """The gather's check of the grid against the Exudyn plant (``reference_table.verify``): the grid's corners and
    seeded random points up to n_points, and the largest relative difference allowed per criterion (1)."""

    n_points: int = setting()
    seed: int = setting()
    tolerance: dict[str, float] = setting()

    def validate(self) -> None:
        where = "reference_table.verify."
        require(self.n_points >= 1, where + "n_points", f"must be >= 1, got {self.n_points}")
        for name, value in self.tolerance.items():
            require(name in CRITERIA, where + "tolerance", f"{name!r} is not one of {list(CRITERIA)}")
            require(value > 0, f"{where}tolerance.{name}", f"must be > 0, got {value}")
        missing = sorted(set(CRITERIA) - set(self.tolerance))
        require(not missing, where + "tolerance", f"no tolerance for {missing}")


@dataclass(frozen=True, kw_only=True)
class ReferenceTableSection(ReferenceGrid):
    """The config section ``reference_table``."""

    criterion: str = setting()  # the criterion the ANFIS learns (criteria.CRITERIA)
    window: str = setting()  # the window it learns (a key of windows_s)
    flat_tolerance: float = setting()  # 1, the flat band holds criteria within this of the optimum
    verify: VerifyOptions = setting()
    n_chunks: int = setting()  # Snakemake scatter: chunk jobs
    threads: int = setting()  # joblib workers per chunk job

    def validate(self) -> None:
        super().validate()
        check_choice(self.criterion, self.window, self.windows)
        require(self.flat_tolerance >= 0, "reference_table.flat_tolerance", f"must be >= 0, got {self.flat_tolerance}")
        require(self.n_chunks >= 1, "reference_table.n_chunks", f"must be >= 1, got {self.n_chunks}")
        require(self.threads >= 1, "reference_table.threads", f"must be >= 1, got {self.threads}")
