"""The camera on the platform: a pinhole model and where a scene point lands on its sensor.

Frames and signs (those of the platform model, src/uavdamp/platform/): x forward along the optical
axis at rest, y left, z up. The camera yaws by psi about z (positive turns the axis to the left) and
then pitches by theta about its own y (positive turns the axis down, right-hand rule about y left), so
the optical axis is R ex with R = Rz(psi) Ry(theta) = (cos psi cos theta, sin psi cos theta, -sin theta).
The optical centre is taken at the camera's centre of mass, whose translation (y, z) the platform
reports (assumption: the lens sits on the centre of mass; the offset is a few cm against a scene
tens of m away).

The tracked scene point P is the one on the optical axis at rest, P = (D, 0, 0), D the scene distance.
Its image position (u, v) in px is measured from the image centre, u along image columns (to the
right of a viewer looking along +x, i.e. towards -y) and v along image rows (downwards, -z): the
usual raster convention. Exact pinhole projection, with p = R^T (P - c) the point in camera axes
and c = (0, y, z):

    u = -f_px p_y / p_x,    v = -f_px p_z / p_x,

    p_x = (D cos psi - y sin psi) cos theta + z sin theta
    p_y = -D sin psi - y cos psi
    p_z = (D cos psi - y sin psi) sin theta - z cos theta

To first order in the angles and in y/D, z/D:  u = f_px (psi + y/D),  v = f_px (z/D - theta).
So a camera yawing left or moving left moves the image of the scene to the right (u > 0); pitching
down (theta > 0) moves it up (v < 0); moving up moves it down (v > 0). The exact form is used; the
small-angle form differs from it by relative errors of order a^2: tan(a) ~ a gives a^2/3 (0.33 % at
0.1 rad, 3.3e-5 at 10 mrad), and with both angles u = f tan(psi) / cos(theta) adds theta^2/2 (0.5 % at
0.1 rad); the translation terms are exact when the angles are zero (tested).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

_REQUIRED = (
    "focal_length_m",
    "pixel_pitch_m",
    "image_width_px",
    "image_height_px",
    "exposure_s",
    "frame_rate_hz",
    "scene_distance_m",
)


@dataclass(frozen=True)
class CameraOptics:
    """Pinhole camera with a global or rolling shutter: what the image path and the blur need (the grid's view of
    the config section ``camera``: not the sharp-frame threshold, so editing it does not rerun the grid), SI units.

    line_time_s: rolling-shutter delay between the exposure starts of consecutive rows, s (0: global shutter).
    """

    focal_length_m: float  # m
    pixel_pitch_m: float  # m, centre-to-centre distance of the sensor's pixels (square pixels)
    image_width_px: int  # px, columns
    image_height_px: int  # px, rows
    exposure_s: float  # s, exposure (integration) time of a row
    frame_rate_hz: float  # Hz, frames per second
    scene_distance_m: float  # m, distance D of the observed scene along the optical axis
    line_time_s: float = 0.0  # s, rolling-shutter row delay; 0 = global shutter

    def __post_init__(self) -> None:
        self.validate()

    def validate(self) -> None:
        """ValueError naming the first bad value (the typed loader has checked types and finiteness)."""
        for name in _REQUIRED:
            _positive(self, name)
        if not (math.isfinite(self.line_time_s) and self.line_time_s >= 0):
            raise ValueError(f"camera.line_time_s must be >= 0, got {self.line_time_s!r}")
        period = 1.0 / self.frame_rate_hz
        if self.exposure_s > period:
            raise ValueError(f"camera.exposure_s ({self.exposure_s} s) exceeds the frame period {period:.6g} s")
        if self.line_time_s * self.image_height_px > period:
            raise ValueError(
                f"camera.line_time_s ({self.line_time_s} s) x {self.image_height_px} rows exceeds the frame period "
                f"{period:.6g} s"
            )

    @property
    def focal_px(self) -> float:
        """Focal length in pixels, f / pixel pitch, px (rad-1 for small angles)."""
        return self.focal_length_m / self.pixel_pitch_m

    @property
    def nyquist_cycles_per_m(self) -> float:
        """Sensor Nyquist frequency 1 / (2 pixel pitch), cycles m-1 on the sensor (0.5 cycles px-1)."""
        return 0.5 / self.pixel_pitch_m

    def attrs(self) -> dict[str, float]:
        """The parameters as flat NetCDF attributes, named camera_<key>."""
        return {f"camera_{f.name}": getattr(self, f.name) for f in fields(self)}


@dataclass(frozen=True)
class CameraModel(CameraOptics):
    """The config section ``camera``: the optics (`CameraOptics`) and the sharp-frame threshold of the image
    metrics. sharp_threshold_px: a frame is sharp when its blur is at most this, px."""

    sharp_threshold_px: float = 1.0  # px, blur at most this counts as a sharp frame

    def validate(self) -> None:
        CameraOptics.validate(self)
        _positive(self, "sharp_threshold_px")


def _positive(camera, name: str) -> None:
    value = getattr(camera, name)
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise ValueError(f"camera.{name} must be a finite number > 0, got {value!r}")


def image_displacement_px(
    camera: CameraModel, yaw: np.ndarray, pitch: np.ndarray, y: np.ndarray, z: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Image position (u, v), px, of the scene point on the optical axis at rest (module docstring).

    yaw, pitch: line-of-sight angles psi, theta, rad; y, z: camera translation, m. Arrays broadcast.
    Exact pinhole projection; ValueError if the point is not in front of the camera.
    """
    psi, theta = np.asarray(yaw, dtype=float), np.asarray(pitch, dtype=float)
    y, z = np.asarray(y, dtype=float), np.asarray(z, dtype=float)
    for name, arr in (("yaw", psi), ("pitch", theta), ("y", y), ("z", z)):
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"image_displacement_px: {name} holds non-finite values")
    d = camera.scene_distance_m
    a = d * np.cos(psi) - y * np.sin(psi)
    p_x = a * np.cos(theta) + z * np.sin(theta)
    p_y = -d * np.sin(psi) - y * np.cos(psi)
    p_z = a * np.sin(theta) - z * np.cos(theta)
    if not np.all(p_x > 0):
        raise ValueError("image_displacement_px: the scene point is not in front of the camera (angles or translation)")
    f = camera.focal_px
    return -f * p_y / p_x, -f * p_z / p_x
