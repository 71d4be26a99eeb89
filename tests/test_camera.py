"""Camera model: config parsing, derived quantities, the projection of the on-axis scene point."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy.spatial.transform import Rotation

from uavdamp.camera.optics import CameraModel, image_displacement_px
from uavdamp.settings import parse


def parse_camera(section) -> CameraModel:
    return parse(CameraModel, section, "camera")


CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"


def _section(**change) -> dict:
    section = {
        "focal_length_m": 6.0e-3,
        "pixel_pitch_m": 2.9e-6,
        "image_width_px": 1920,
        "image_height_px": 1080,
        "exposure_s": 4.0e-3,
        "frame_rate_hz": 30.0,
        "scene_distance_m": 20.0,
    }
    section.update(change)
    return {k: v for k, v in section.items() if v is not None}


CAMERA = parse_camera(_section())


def test_config_section_parses_and_derives_focal_px_and_nyquist():
    cam = parse_camera(yaml.safe_load(CONFIG.read_text())["camera"])
    assert cam.focal_px == pytest.approx(6.0e-3 / 2.9e-6, rel=1e-12)
    assert cam.nyquist_cycles_per_m == pytest.approx(1.0 / (2 * 2.9e-6), rel=1e-12)
    assert cam.line_time_s == 0.0 and cam.sharp_threshold_px == 1.0
    assert isinstance(cam.image_width_px, int)
    assert cam.attrs()["camera_focal_length_m"] == 6.0e-3


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"exposure_s": None}, r"camera.exposure_s: missing key"),
        ({"colour": "rgb"}, r"camera.colour: unknown key"),
        ({"focal_length_m": -6e-3}, r"camera\.focal_length_m must be a finite number > 0"),
        ({"scene_distance_m": math.inf}, r"camera\.scene_distance_m: expected a finite number"),
        ({"image_width_px": 1920.5}, r"camera\.image_width_px: expected an integer"),
        ({"frame_rate_hz": "30"}, r"camera\.frame_rate_hz: expected a finite number"),
        ({"frame_rate_hz": True}, r"camera\.frame_rate_hz: expected a finite number"),
        ({"exposure_s": 0.05}, r"camera\.exposure_s \(0\.05 s\) exceeds the frame period"),
        ({"line_time_s": -1e-6}, r"camera\.line_time_s must be >= 0"),
        ({"line_time_s": 40e-6}, r"camera\.line_time_s \(4e-05 s\) x 1080 rows exceeds the frame period"),
        ({"sharp_threshold_px": 0.0}, r"camera\.sharp_threshold_px must be a finite number > 0"),
    ],
)
def test_bad_config_names_the_key(change, message):
    with pytest.raises(ValueError, match=message):
        parse_camera(_section(**change))


def test_signs_follow_the_raster_convention():
    """Yaw left or move left: the scene moves right (u > 0); pitch down: up (v < 0); move up: down (v > 0)."""
    u, v = image_displacement_px(CAMERA, 1e-3, 0.0, 0.0, 0.0)
    assert u > 0 and v == pytest.approx(0.0, abs=1e-12)
    u, _ = image_displacement_px(CAMERA, 0.0, 0.0, 1e-3, 0.0)
    assert u > 0
    _, v = image_displacement_px(CAMERA, 0.0, 1e-3, 0.0, 0.0)
    assert v < 0
    _, v = image_displacement_px(CAMERA, 0.0, 0.0, 0.0, 1e-3)
    assert v > 0


def test_exact_projection_matches_rotation_matrices():
    """Independent computation: camera axes from scipy's intrinsic z-then-y rotation, pinhole projection."""
    rng = np.random.default_rng(12)
    psi, theta = rng.uniform(-0.1, 0.1, 20), rng.uniform(-0.1, 0.1, 20)
    y, z = rng.uniform(-0.5, 0.5, 20), rng.uniform(-0.5, 0.5, 20)
    u, v = image_displacement_px(CAMERA, psi, theta, y, z)
    d = CAMERA.scene_distance_m
    for i in range(20):
        rot = Rotation.from_euler("ZY", [psi[i], theta[i]])  # R = Rz(psi) Ry(theta)
        p = rot.inv().apply(np.array([d, 0.0, 0.0]) - np.array([0.0, y[i], z[i]]))
        assert u[i] == pytest.approx(-CAMERA.focal_px * p[1] / p[0], rel=1e-12)
        assert v[i] == pytest.approx(-CAMERA.focal_px * p[2] / p[0], rel=1e-12)


def test_single_motions_in_closed_form():
    """Pure yaw: f tan(psi); pure pitch: -f tan(theta); pure translation: f y / D and f z / D (exact)."""
    f, d = CAMERA.focal_px, CAMERA.scene_distance_m
    assert image_displacement_px(CAMERA, 0.05, 0.0, 0.0, 0.0)[0] == pytest.approx(f * math.tan(0.05), rel=1e-12)
    assert image_displacement_px(CAMERA, 0.0, 0.05, 0.0, 0.0)[1] == pytest.approx(-f * math.tan(0.05), rel=1e-12)
    u, v = image_displacement_px(CAMERA, 0.0, 0.0, 2e-3, -3e-3)
    assert (u, v) == (pytest.approx(f * 2e-3 / d, rel=1e-12), pytest.approx(-f * 3e-3 / d, rel=1e-12))


@pytest.mark.parametrize(("angle", "rel_error"), [(0.1, 0.1**2 / 3), (0.01, 0.01**2 / 3)])
def test_small_angle_form_error(angle, rel_error):
    """u ~ f (psi + y/D), v ~ f (z/D - theta): relative error a^2/3 (tan a = a + a^3/3) of the exact form."""
    u, v = image_displacement_px(CAMERA, angle, angle, 0.0, 0.0)
    small = CAMERA.focal_px * angle
    assert -v / small - 1 == pytest.approx(rel_error, rel=0.02)
    # yaw with pitch: u = f tan(psi) / cos(theta), so its error adds theta^2 / 2
    assert u / small - 1 == pytest.approx(rel_error + angle**2 / 2, rel=0.05)


def test_scene_behind_the_camera_and_nan_are_refused():
    with pytest.raises(ValueError, match="not in front of the camera"):
        image_displacement_px(CAMERA, 2.0, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="yaw holds non-finite values"):
        image_displacement_px(CAMERA, np.array([0.0, np.nan]), 0.0, 0.0, 0.0)
