"""The camera's criteria, each defined once: its name, units, long name, family and formula.

Every number by which the study, the reference table, the benchmark and the payload stage judge one run over one
time window is one of these (smaller is better); they differ only in the window they take (and, for the frame
criteria, where the frame clock starts: at the window's start, `uavdamp.camera.image_quality`):

    displacement_std   sqrt(var y + var z) of the camera's displacement (1/N, about the window's mean), m: the
                       paper's Eq. 1 up to the square root
    displacement_peak  largest |(y, z)| of the camera's displacement, m
    los_std            sqrt(var yaw + var pitch) (1/N), rad: the line of sight's rms about its mean
    los_peak           largest angle between the optical axis and its rest direction,
                       arctan2(|(sin psi cos theta, sin theta)|, cos psi cos theta), rad
    blur_p95           95th percentile over the window's frames of the smear extent, in pixels (units "1")
    unsharp_fraction   share of the window's frames whose smear extent exceeds the camera's sharp threshold, 1

Families (`FAMILIES`, first member first): a benchmark law is tuned per family, and the reference table's
`criterion` names a family and tabulates its first member. Per-axis statistics (the study's std_total, the yaw and
pitch stds), the gimbal's roll and the damper's energy are other quantities under other names.

Window (`window_mask`, one rule for every consumer): the samples with start - tol <= t <= end + tol, tol = 1e-9 of
the time step (a sample a rounding error off a window end belongs to the window).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

# CF units of a length measured in pixels: UDUNITS (the unit library CF names) has no pixel, so such a quantity has
# units "1" (a length on the sensor over the pixel pitch), its long_name ends "in pixels" and it carries this comment
PIXEL_COMMENT = "units 1: a length on the sensor divided by the pixel pitch, i.e. in pixels (UDUNITS has no pixel unit)"


def pixel_attrs(long_name: str) -> dict[str, str]:
    """CF attributes of a quantity in pixels: units "1", the long_name (ending "in pixels") and PIXEL_COMMENT."""
    return {"units": "1", "long_name": long_name, "comment": PIXEL_COMMENT}


@dataclass(frozen=True)
class Criterion:
    """One criterion: `uses` names what its formula `fn` takes ("displacement": the (y, z) displacement (2, n) m;
    "angles": yaw and pitch (n,) rad each; "frames": the frames' smear extents (n_frames,) px and the sharp
    threshold px). `pixels`: the value is in pixels (CF units "1", `pixel_attrs`)."""

    name: str
    family: str
    units: str
    long_name: str
    uses: str
    fn: Callable[..., float]
    pixels: bool = False

    @property
    def attrs(self) -> dict[str, str]:
        """CF attributes (units, long_name; pixels: the pixel comment)."""
        return pixel_attrs(self.long_name) if self.pixels else {"units": self.units, "long_name": self.long_name}

    @property
    def phased(self) -> bool:
        """True where the value depends on where the frame clock starts (the frame criteria)."""
        return self.uses == "frames"


def displacement_std(displacement: np.ndarray) -> float:
    """sqrt(var y + var z), m (1/N), of a (2, n) displacement in m."""
    return float(np.sqrt(np.var(np.asarray(displacement, dtype=float), axis=1).sum()))


def displacement_peak(displacement: np.ndarray) -> float:
    """Largest |(y, z)|, m, of a (2, n) displacement in m."""
    return float(np.linalg.norm(np.asarray(displacement, dtype=float), axis=0).max())


def los_std(yaw: np.ndarray, pitch: np.ndarray) -> float:
    """sqrt(var yaw + var pitch), rad (1/N)."""
    return float(np.hypot(np.std(yaw), np.std(pitch)))


def off_axis_angle(yaw: np.ndarray, pitch: np.ndarray) -> np.ndarray:
    """Angle between the optical axis and its rest direction, rad, of yaw psi then pitch theta (rad)."""
    psi, theta = np.asarray(yaw, dtype=float), np.asarray(pitch, dtype=float)
    return np.arctan2(np.hypot(np.sin(psi) * np.cos(theta), np.sin(theta)), np.cos(psi) * np.cos(theta))


def los_peak(yaw: np.ndarray, pitch: np.ndarray) -> float:
    """Largest `off_axis_angle`, rad."""
    return float(off_axis_angle(yaw, pitch).max())


def blur_p95(blur_px: np.ndarray, sharp_threshold_px: float) -> float:
    """95th percentile of the frames' smear extents, px (the threshold is not used)."""
    return float(np.percentile(blur_px, 95))


def unsharp_fraction(blur_px: np.ndarray, sharp_threshold_px: float) -> float:
    """Share of the frames whose smear extent exceeds `sharp_threshold_px` (NaN: no threshold, NaN)."""
    if np.isnan(sharp_threshold_px):
        return float("nan")
    return float(1.0 - np.mean(np.asarray(blur_px) <= sharp_threshold_px))


CRITERIA: dict[str, Criterion] = {
    c.name: c
    for c in (
        Criterion(
            "displacement_std",
            "displacement",
            "m",
            "camera displacement sqrt(var y + var z)",
            "displacement",
            displacement_std,
        ),
        Criterion(
            "displacement_peak", "displacement", "m", "largest |camera displacement|", "displacement", displacement_peak
        ),
        Criterion(
            "los_std",
            "line_of_sight",
            "rad",
            "line-of-sight rms about its mean, sqrt(var yaw + var pitch)",
            "angles",
            los_std,
        ),
        Criterion(
            "los_peak",
            "line_of_sight",
            "rad",
            "peak angle between the optical axis and its rest direction",
            "angles",
            los_peak,
        ),
        Criterion(
            "blur_p95",
            "blur",
            "1",
            "95th percentile over frames of the smear extent, in pixels",
            "frames",
            blur_p95,
            pixels=True,
        ),
        Criterion(
            "unsharp_fraction",
            "blur",
            "1",
            "share of frames whose smear extent exceeds the camera's sharp threshold",
            "frames",
            unsharp_fraction,
        ),
    )
}
FAMILIES: dict[str, tuple[str, ...]] = {
    family: tuple(name for name, c in CRITERIA.items() if c.family == family)
    for family in dict.fromkeys(c.family for c in CRITERIA.values())
}
PHASED = tuple(name for name, c in CRITERIA.items() if c.phased)


def get(name: str) -> Criterion:
    """The criterion `name`; ValueError naming it and the known ones."""
    if name not in CRITERIA:
        raise ValueError(f"criterion: unknown {name!r} (known: {list(CRITERIA)})")
    return CRITERIA[name]


def family_of(name: str) -> str:
    """The family of criterion `name` (ValueError names an unknown one)."""
    return get(name).family


def primary(family: str) -> str:
    """The family's first member: what the reference table tabulates for `family`."""
    if family not in FAMILIES:
        raise ValueError(f"criterion family: unknown {family!r} (known: {list(FAMILIES)})")
    return FAMILIES[family][0]


def window_mask(time: np.ndarray, start_s: float, end_s: float) -> np.ndarray:
    """The samples of the uniform grid `time` (s) in [start_s, end_s], ends included within 1e-9 of a step."""
    t = np.asarray(time, dtype=float)
    tol = 1e-9 * float(t[1] - t[0]) if t.size > 1 else 0.0
    return (t >= start_s - tol) & (t <= end_s + tol)
