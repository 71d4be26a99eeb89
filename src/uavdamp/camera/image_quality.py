"""What the camera sees: per-frame blur, frame-to-frame jitter, MTF at Nyquist and line-of-sight statistics.

Input: the image-plane trajectory (u, v), px, of the scene point on the optical axis (camera.py), sampled
on a uniform time grid and taken as piecewise linear between samples.

Frames (choice): frame k starts at t_k = start + k / frame_rate; the tracked point, imaged on the centre
row, is exposed over [t_k + delay, t_k + delay + T], T the exposure and delay = line_time (H - 1) / 2 the
rolling-shutter start of the centre row (0 for a global shutter). A frame counts only when its last row,
exposed until t_k + line_time (H - 1) + T, ends inside the record (or window); later, partial frames are
dropped. The window ends are interpolated on the trajectory.

Per frame:
  blur_px   extent of the smear: the largest distance between two image positions within the exposure
            (the length of the streak a point leaves; for back-and-forth motion it counts a stroke once).
            Headline blur metric (choice): a sine of amplitude a px much faster than the exposure gives 2 a.
  path_px   path length: sum of |d(u, v)| over the exposure (equals blur_px for motion in one direction;
            4 a per period for the fast sine).
  centroid  time-mean image position over the exposure, px (the frame's apparent image position).
  smear_px  |b| T, b the slope (px s-1) of the least-squares line through the exposure's trajectory
            (trapezoid weights: approximates the time integral; choice).
  sigma_px  RMS deviation about that line, along its principal direction (largest eigenvalue of the 2-D
            residual covariance: the worst direction; choice).
  mtf       MTF at the sensor's Nyquist frequency nu = 0.5 cycles px-1: |sinc(pi nu smear)| exp(-2 pi^2
            sigma^2 nu^2). The linear-motion and Gaussian random-jitter MTFs are the textbook forms used in
            Kopeika's vibration-MTF series (Wulich & Kopeika 1987, Opt. Eng. 26(6) 529; Hadar, Fisher &
            Kopeika 1992, Opt. Eng. 31(3) 581); splitting each exposure into a linear part and a residual
            treated as Gaussian jitter, and multiplying the two, is a choice (Hadar et al. compute the OTF of
            the actual trajectory instead).
  skew_px   rolling shutter only (0 for a global shutter): image shift between the mid-exposures of the
            first and last rows, |p(t_k + (H - 1) line_time + T/2) - p(t_k + T/2)| (assumption: a distant
            scene moves in the image as the tracked point does).

Frame-to-frame jitter (choice): |c_{k+1} - c_k|, the distance between consecutive frame centroids; its RMS
over the frames is the metric. The centroid scatter sqrt(var(c_u) + var(c_v)) is reported beside it.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from uavdamp.camera.criteria import CRITERIA, window_mask
from uavdamp.camera.optics import CameraModel, CameraOptics, image_displacement_px

NYQUIST_CYCLES_PER_PX = 0.5


class Frames(NamedTuple):
    """Per-frame results, each (n_frames,) unless noted."""

    start_s: np.ndarray  # s, frame clock t_k (first row's exposure start)
    blur_px: np.ndarray  # px, smear extent (headline)
    path_px: np.ndarray  # px, path length
    centroid_px: np.ndarray  # px, (n_frames, 2) time-mean (u, v)
    smear_px: np.ndarray  # px, linear-fit displacement over the exposure
    sigma_px: np.ndarray  # px, RMS deviation about the linear fit, principal direction
    mtf_nyquist: np.ndarray  # 1, MTF at 0.5 cycles px-1
    skew_px: np.ndarray  # px, rolling-shutter shift first row to last row (0: global shutter)


def motion_mtf(nu_cycles_px: float | np.ndarray, smear_px: float | np.ndarray) -> np.ndarray:
    """Linear-motion MTF |sin(pi nu d) / (pi nu d)|, 1; nu in cycles px-1, d the smear length in px."""
    return np.abs(np.sinc(np.asarray(nu_cycles_px) * np.asarray(smear_px)))


def jitter_mtf(nu_cycles_px: float | np.ndarray, sigma_px: float | np.ndarray) -> np.ndarray:
    """Gaussian random-jitter MTF exp(-2 pi^2 sigma^2 nu^2), 1; sigma the RMS jitter in px."""
    return np.exp(-2.0 * np.pi**2 * np.asarray(sigma_px) ** 2 * np.asarray(nu_cycles_px) ** 2)


def _check_time(time: np.ndarray, *series: tuple[str, np.ndarray]) -> np.ndarray:
    """Validated uniform time grid, s; each named series must match it and be finite."""
    t = np.asarray(time, dtype=float)
    if t.ndim != 1 or t.size < 2 or not np.all(np.isfinite(t)):
        raise ValueError(f"time must be a finite 1-D array of >= 2 samples, got shape {t.shape}")
    step = np.diff(t)
    if not (np.all(step > 0) and np.ptp(step) <= 1e-6 * step.mean()):
        raise ValueError("time must be strictly increasing and uniform (relative spread of steps <= 1e-6)")
    for name, values in series:
        if np.shape(values) != t.shape:
            raise ValueError(f"{name} has shape {np.shape(values)}, time has {t.shape}")
        if not np.all(np.isfinite(values)):
            raise ValueError(f"{name} holds non-finite values")
    return t


def _span(time: np.ndarray, start_s: float | None, end_s: float | None) -> tuple[float, float]:
    """The window (start, end), s, defaulting to the record; ValueError if outside it or empty."""
    start = float(time[0]) if start_s is None else float(start_s)
    end = float(time[-1]) if end_s is None else float(end_s)
    tol = 1e-9 * (time[1] - time[0])
    if not (time[0] - tol <= start < end <= time[-1] + tol):
        raise ValueError(f"window [{start}, {end}] s must lie within the record [{time[0]}, {time[-1]}] s")
    return start, end


def frame_starts(
    time: np.ndarray, camera: CameraOptics, start_s: float | None = None, end_s: float | None = None
) -> np.ndarray:
    """Frame clock t_k = start + k / frame_rate, s, of the frames whose last row ends by `end_s`.

    ValueError if not one frame fits. The window defaults to the whole record.
    """
    t = _check_time(time)
    start, end = _span(t, start_s, end_s)
    span = camera.line_time_s * (camera.image_height_px - 1) + camera.exposure_s
    tol = 1e-6 * (t[1] - t[0])  # a frame ending on the last sample (up to rounding) is complete
    spare = end - start - span + tol  # s, time left after the first frame
    if spare < 0:
        raise ValueError(f"window [{start}, {end}] s is shorter than one frame's exposure ({span:.6g} s)")
    return start + np.arange(int(np.floor(spare * camera.frame_rate_hz)) + 1) / camera.frame_rate_hz


def _interp(time: np.ndarray, path: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Piecewise-linear (u, v) at times `at`, shape (len(at), 2)."""
    return np.stack([np.interp(at, time, path[:, i]) for i in range(2)], axis=-1)


def _exposure_points(time: np.ndarray, path: np.ndarray, t_a: np.ndarray, t_b: np.ndarray):
    """Times (n, m) and points (n, m, 2) of the trajectory within each [t_a, t_b]: interpolated ends,
    the samples strictly inside, padded at the end with copies of the end point (zero-length segments)."""
    lo = np.searchsorted(time, t_a, side="right")
    count = np.searchsorted(time, t_b, side="left") - lo
    slot = np.arange(max(int(count.max()), 0))
    inside = slot[None, :] < count[:, None]
    idx = np.where(inside, lo[:, None] + slot[None, :], 0)
    end = _interp(time, path, t_b)
    tau = np.concatenate([t_a[:, None], np.where(inside, time[idx], t_b[:, None]), t_b[:, None]], axis=1)
    mid = np.where(inside[..., None], path[idx], end[:, None, :])
    points = np.concatenate([_interp(time, path, t_a)[:, None, :], mid, end[:, None, :]], axis=1)
    return tau, points


def _extent(points: np.ndarray) -> np.ndarray:
    """Largest distance between two points of each frame, (n,)."""
    extent = np.zeros(points.shape[0])
    for lag in range(1, points.shape[1]):
        dist = np.linalg.norm(points[:, lag:] - points[:, :-lag], axis=-1).max(axis=1)
        extent = np.maximum(extent, dist)
    return extent


def _linear_fit(tau: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Slope (n, 2) px s-1 of the trapezoid-weighted least-squares line, and the principal RMS residual (n,)."""
    seg = np.diff(tau, axis=1)
    w = np.zeros_like(tau)
    w[:, :-1] += seg / 2
    w[:, 1:] += seg / 2
    w /= w.sum(axis=1, keepdims=True)
    dt = tau - (w * tau).sum(axis=1, keepdims=True)
    dp = points - (w[..., None] * points).sum(axis=1, keepdims=True)
    slope = (w[..., None] * dt[..., None] * dp).sum(axis=1) / (w * dt**2).sum(axis=1)[:, None]
    r = dp - dt[..., None] * slope[:, None, :]
    cuu, cvv, cuv = ((w * r[..., 0] ** 2).sum(1), (w * r[..., 1] ** 2).sum(1), (w * r[..., 0] * r[..., 1]).sum(1))
    largest = (cuu + cvv) / 2 + np.sqrt(((cuu - cvv) / 2) ** 2 + cuv**2)
    return slope, np.sqrt(largest)


def frames_from_image_path(
    time: np.ndarray,
    u_px: np.ndarray,
    v_px: np.ndarray,
    camera: CameraOptics,
    start_s: float | None = None,
    end_s: float | None = None,
) -> Frames:
    """Per-frame blur, centroid, MTF and skew (module docstring) from the image trajectory (u, v), px."""
    t = _check_time(time, ("u_px", u_px), ("v_px", v_px))
    path = np.stack([np.asarray(u_px, dtype=float), np.asarray(v_px, dtype=float)], axis=-1)
    t_k = frame_starts(t, camera, start_s, end_s)
    rows = camera.image_height_px - 1
    t_a = t_k + camera.line_time_s * rows / 2
    t_b = t_a + camera.exposure_s
    tau, points = _exposure_points(t, path, t_a, t_b)
    segments = np.linalg.norm(np.diff(points, axis=1), axis=-1)
    centroid = (((points[:, 1:] + points[:, :-1]) / 2) * np.diff(tau, axis=1)[..., None]).sum(axis=1)
    slope, sigma = _linear_fit(tau, points)
    smear = np.linalg.norm(slope, axis=-1) * camera.exposure_s
    mid = t_k + camera.exposure_s / 2
    skew = np.linalg.norm(_interp(t, path, mid + camera.line_time_s * rows) - _interp(t, path, mid), axis=-1)
    return Frames(
        start_s=t_k,
        blur_px=_extent(points),
        path_px=segments.sum(axis=1),
        centroid_px=centroid / camera.exposure_s,
        smear_px=smear,
        sigma_px=sigma,
        mtf_nyquist=motion_mtf(NYQUIST_CYCLES_PER_PX, smear) * jitter_mtf(NYQUIST_CYCLES_PER_PX, sigma),
        skew_px=skew,
    )


def _criterion(name: str, *args) -> tuple[float, str, str]:
    """(value, units, long_name) of criterion `name` (`uavdamp.camera.criteria`) from its formula's arguments."""
    c = CRITERIA[name]
    return c.fn(*args), c.units, c.long_name


def frame_summary(frames: Frames, sharp_threshold_px: float) -> dict[str, tuple[float, str, str]]:
    """Scalar metrics {name: (value, units, long_name)} over the frames; jitter NaN for a single frame."""
    blur = frames.blur_px
    step = np.linalg.norm(np.diff(frames.centroid_px, axis=0), axis=-1)
    jitter = float(np.sqrt(np.mean(step**2))) if step.size else float("nan")
    scatter = float(np.sqrt(np.var(frames.centroid_px, axis=0).sum()))
    return {
        "blur_median": (
            float(np.median(blur)),
            "1",
            "median over frames of the smear extent during the exposure, in pixels",
        ),
        "blur_p95": _criterion("blur_p95", blur, sharp_threshold_px),
        "blur_max": (float(blur.max()), "1", "largest smear extent of a frame, in pixels"),
        "blur_path_median": (
            float(np.median(frames.path_px)),
            "1",
            "median over frames of the image path length, in pixels",
        ),
        "blur_path_p95": (
            float(np.percentile(frames.path_px, 95)),
            "1",
            "95th percentile of the image path length, in pixels",
        ),
        "sharp_fraction": (
            float(np.mean(blur <= sharp_threshold_px)),
            "1",
            f"fraction of frames with smear extent <= {sharp_threshold_px:g} px",
        ),
        "frame_jitter_rms": (jitter, "1", "RMS distance between the centroids of consecutive frames, in pixels"),
        "centroid_std": (scatter, "1", "scatter of the frame centroids, sqrt(var u + var v), in pixels"),
        "mtf_nyquist_median": (
            float(np.median(frames.mtf_nyquist)),
            "1",
            "median over frames of the motion and jitter MTF at the sensor Nyquist frequency",
        ),
        "rolling_shutter_skew_p95": (
            float(np.percentile(frames.skew_px, 95)),
            "1",
            "95th percentile of the rolling-shutter image shift from first to last row, in pixels",
        ),
    }


def line_of_sight_stats(
    time: np.ndarray,
    yaw: np.ndarray,
    pitch: np.ndarray,
    start_s: float | None = None,
    end_s: float | None = None,
) -> dict[str, tuple[float, str, str]]:
    """Std (ddof 0, about the mean) and peak |angle| (from rest) of yaw and pitch, and the criteria los_std and
    los_peak (`uavdamp.camera.criteria`), over the samples within [start, end] (`criteria.window_mask`)."""
    t = _check_time(time, ("yaw", yaw), ("pitch", pitch))
    keep = window_mask(t, *_span(t, start_s, end_s))
    psi, theta = np.asarray(yaw, dtype=float)[keep], np.asarray(pitch, dtype=float)[keep]
    return {
        "los_yaw_std": (float(np.std(psi)), "rad", "standard deviation of the camera yaw"),
        "los_yaw_peak": (float(np.abs(psi).max()), "rad", "peak absolute camera yaw"),
        "los_pitch_std": (float(np.std(theta)), "rad", "standard deviation of the camera pitch"),
        "los_pitch_peak": (float(np.abs(theta).max()), "rad", "peak absolute camera pitch"),
        "los_std": _criterion("los_std", psi, theta),
        "los_peak": _criterion("los_peak", psi, theta),
    }


def frame_metrics(
    time: np.ndarray,
    camera_displacement: np.ndarray,
    camera_yaw: np.ndarray,
    camera_pitch: np.ndarray,
    camera: CameraOptics,
    start_s: float | None = None,
    end_s: float | None = None,
) -> Frames:
    """Per-frame results from a response's arrays: time (time,) s, camera_displacement (2, time) m as (y, z),
    camera_yaw and camera_pitch (time,) rad."""
    disp = np.asarray(camera_displacement, dtype=float)
    if disp.ndim != 2 or disp.shape[0] != 2:
        raise ValueError(f"camera_displacement must be (axis=(y, z), time), got shape {disp.shape}")
    _check_time(
        time,
        ("camera_displacement y", disp[0]),
        ("camera_displacement z", disp[1]),
        ("camera_yaw", camera_yaw),
        ("camera_pitch", camera_pitch),
    )
    u, v = image_displacement_px(camera, camera_yaw, camera_pitch, disp[0], disp[1])
    return frames_from_image_path(time, u, v, camera, start_s, end_s)


def image_metrics(
    time: np.ndarray,
    camera_displacement: np.ndarray,
    camera_yaw: np.ndarray,
    camera_pitch: np.ndarray,
    camera: CameraModel,
    start_s: float | None = None,
    end_s: float | None = None,
) -> dict[str, tuple[float, str, str]]:
    """All scalar image metrics {name: (value, units, long_name)} of a response over [start_s, end_s]."""
    frames = frame_metrics(time, camera_displacement, camera_yaw, camera_pitch, camera, start_s, end_s)
    return {
        **line_of_sight_stats(time, camera_yaw, camera_pitch, start_s, end_s),
        **frame_summary(frames, camera.sharp_threshold_px),
    }


def camera_criteria(
    names,
    time: np.ndarray,
    camera_displacement: np.ndarray,
    camera_yaw: np.ndarray,
    camera_pitch: np.ndarray,
    camera: CameraOptics | None = None,
    start_s: float | None = None,
    end_s: float | None = None,
    *,
    image_px: tuple[np.ndarray, np.ndarray] | None = None,
) -> dict[str, float]:
    """The criteria `names` (`uavdamp.camera.criteria`) of a response's arrays over [start_s, end_s] (default: the
    record), the frame clock starting at the window's start; the frame criteria need a `camera` (a `CameraOptics`
    without a sharp threshold gives unsharp_fraction NaN). image_px: the arrays' image path (u, v) px
    (`image_displacement_px`) where the caller has it (several frame clocks on one record), else made here."""
    t = _check_time(time, ("camera_yaw", camera_yaw), ("camera_pitch", camera_pitch))
    start, end = _span(t, start_s, end_s)
    keep = window_mask(t, start, end)
    if keep.sum() < 2:
        raise ValueError(f"window [{start}, {end}] s holds fewer than 2 samples")
    chosen = [CRITERIA[name] for name in names]
    frames = None
    if any(c.uses == "frames" for c in chosen):
        if camera is None:
            raise ValueError(f"criteria {[c.name for c in chosen if c.uses == 'frames']} need a camera")
        if image_px is None:
            frames = frame_metrics(t, camera_displacement, camera_yaw, camera_pitch, camera, start, end)
        else:
            frames = frames_from_image_path(t, *image_px, camera, start, end)
    args = {
        "displacement": lambda: (np.asarray(camera_displacement, dtype=float)[:, keep],),
        "angles": lambda: (np.asarray(camera_yaw, dtype=float)[keep], np.asarray(camera_pitch, dtype=float)[keep]),
        "frames": lambda: (frames.blur_px, getattr(camera, "sharp_threshold_px", math.nan)),
    }
    return {c.name: c.fn(*args[c.uses]()) for c in chosen}
