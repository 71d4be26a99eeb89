"""The one criterion system (`uavdamp.camera.criteria`): closed forms of each formula, and every stage's criterion
carries the registry's definition (seen failing with a units or long name changed in one consumer)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import xarray as xr
from conftest import camera_of, load_config

from uavdamp.benchmark import scoring
from uavdamp.camera import criteria as cc
from uavdamp.camera.image_quality import camera_criteria, line_of_sight_stats
from uavdamp.camera.optics import CameraOptics
from uavdamp.damping.clairvoyant import OBJECTIVES
from uavdamp.reference_table import criteria as table
from uavdamp.study import payload_runs

T = np.arange(2001) * 1e-3  # 2 s at 1 kHz: 14 whole periods of 7 Hz
SIN, COS = np.sin(2 * np.pi * 7 * T[:-1]), np.cos(2 * np.pi * 7 * T[:-1])


def test_displacement_std_and_peak_closed_forms():
    """a sin and b cos over whole periods: std sqrt((a^2 + b^2) / 2); the peak of (a cos, b sin) is max(a, b)."""
    a, b = 2e-3, 5e-4
    assert cc.displacement_std(np.stack([a * SIN, b * COS])) == pytest.approx(math.sqrt((a**2 + b**2) / 2), rel=1e-12)
    assert cc.displacement_peak(np.stack([a * COS, b * SIN])) == pytest.approx(a, rel=1e-12)
    assert cc.displacement_std(np.stack([a + 0 * SIN, -b + 0 * SIN])) == pytest.approx(0.0, abs=1e-18)  # about the mean


def test_line_of_sight_closed_forms():
    """std: hypot of the two stds; peak: the off-axis angle, |psi| for yaw alone, |theta| for pitch alone, and
    arccos(cos psi cos theta) for both (the angle between the rotated optical axis and its rest direction)."""
    assert cc.los_std(1e-3 * SIN, 2e-3 * COS) == pytest.approx(math.sqrt((1e-6 + 4e-6) / 2), rel=1e-12)
    assert cc.los_peak(0.3 * COS, 0 * COS) == pytest.approx(0.3, rel=1e-12)
    assert cc.los_peak(0 * COS, -0.2 * COS) == pytest.approx(0.2, rel=1e-12)
    psi, theta = np.array([0.3]), np.array([0.4])
    assert cc.los_peak(psi, theta) == pytest.approx(math.acos(math.cos(0.3) * math.cos(0.4)), rel=1e-12)


def test_frame_criteria_closed_forms():
    blur = np.arange(101.0)  # px: the 95th percentile of 0..100 is 95 (linear interpolation)
    assert cc.blur_p95(blur, 1.0) == pytest.approx(95.0)
    assert cc.unsharp_fraction(np.array([0.5, 1.0, 1.5, 2.5]), 1.0) == pytest.approx(0.5)  # at the threshold: sharp


def test_families_and_primaries():
    assert cc.FAMILIES == {
        "displacement": ("displacement_std", "displacement_peak"),
        "line_of_sight": ("los_std", "los_peak"),
        "blur": ("blur_p95", "unsharp_fraction"),
    }
    assert [cc.primary(f) for f in cc.FAMILIES] == ["displacement_std", "los_std", "blur_p95"]
    assert cc.PHASED == ("blur_p95", "unsharp_fraction")
    with pytest.raises(ValueError, match="unknown 'camera_std'"):
        cc.family_of("camera_std")


def test_window_mask_keeps_samples_a_rounding_error_off_its_ends():
    t = np.arange(11) * 0.1  # 0.30000000000000004, 0.7000000000000001: inside [0.3, 0.7]
    assert np.flatnonzero(cc.window_mask(t, 0.3, 0.7)).tolist() == [3, 4, 5, 6, 7]
    assert np.flatnonzero(cc.window_mask(t, 0.31, math.inf)).tolist() == [4, 5, 6, 7, 8, 9, 10]


def test_camera_criteria_evaluates_the_registry_formulas_over_the_window():
    disp = np.stack([1e-3 * np.sin(2 * np.pi * 7 * T), 0 * T])
    yaw, pitch = 1e-3 * np.cos(2 * np.pi * 7 * T), 0 * T
    got = camera_criteria(["displacement_std", "los_std", "los_peak"], T, disp, yaw, pitch, start_s=0.5, end_s=1.5)
    keep = (T >= 0.5 - 1e-12) & (T <= 1.5 + 1e-12)
    assert got["displacement_std"] == cc.displacement_std(disp[:, keep])
    assert got["los_std"] == cc.los_std(yaw[keep], pitch[keep])
    assert got["los_peak"] == pytest.approx(1e-3, rel=1e-9)
    with pytest.raises(ValueError, match=r"\['blur_p95'\] need a camera"):
        camera_criteria(["blur_p95"], T, disp, yaw, pitch)


def test_the_reference_tables_blur_takes_optics_without_a_sharp_threshold():
    """The reference table's camera is a `CameraOptics` (no frame rate metrics, no sharp threshold): its blur
    criterion is the same as a `CameraModel`'s with the same optics, and unsharp_fraction is NaN without one
    (seen failing: the table's gather stopped on the missing attribute)."""
    model = camera_of(load_config()["camera"])
    optics = CameraOptics(**{f.name: getattr(model, f.name) for f in dataclasses.fields(CameraOptics)})
    disp = np.stack([1e-3 * np.sin(2 * np.pi * 7 * T), 0 * T])
    yaw = 1e-3 * np.cos(2 * np.pi * 7 * T)
    names = ["blur_p95", "unsharp_fraction"]
    with_model = camera_criteria(names, T, disp, yaw, 0 * T, model)
    with_optics = camera_criteria(names, T, disp, yaw, 0 * T, optics)
    assert with_optics["blur_p95"] == with_model["blur_p95"] > 0
    assert math.isnan(with_optics["unsharp_fraction"]) and 0 <= with_model["unsharp_fraction"] <= 1


def test_every_consumer_carries_the_registry_definition():
    """The reference table's, the benchmark's, the payload stage's, the study's image metrics' and the
    clairvoyant's criteria are the registry's: same units (pixels as CF "1" with the pixel comment), and a long
    name that starts with the registry's."""
    for family, attrs in table.CRITERIA.items():
        defined = cc.CRITERIA[cc.primary(family)].attrs
        assert attrs["units"] == defined["units"] and attrs.get("comment") == defined.get("comment")
        assert attrs["long_name"].startswith(defined["long_name"])
    assert scoring.J_CRITERIA == tuple(cc.CRITERIA)
    for name in ("los_std", "blur_p95"):
        attrs = payload_runs.metric_attrs(name)
        assert attrs["units"] == cc.CRITERIA[name].units
        assert attrs["long_name"].startswith(cc.CRITERIA[name].long_name)
    stats = line_of_sight_stats(T, np.append(1e-3 * COS, 1e-3), 0 * T)
    for name in ("los_std", "los_peak"):
        assert stats[name][1:] == (cc.CRITERIA[name].units, cc.CRITERIA[name].long_name)
    assert set(OBJECTIVES) <= set(cc.CRITERIA)


def test_the_benchmarks_phased_criteria_are_each_frame_clocks_own():
    """`scoring.response_metrics` gives each PHASED criterion as the mean, lowest and highest over the frame-clock
    starts, each start's value the criterion of the record scored on its own (`camera_criteria` from the arrays:
    the image path made again per start), on a record whose yaw, pitch, y and z all differ."""
    camera = camera_of(load_config()["camera"])
    disp = np.stack([1e-3 * np.sin(2 * np.pi * 7 * T), 4e-4 * np.sin(2 * np.pi * 11 * T + 1.0)])
    yaw, pitch = 1e-3 * np.cos(2 * np.pi * 7 * T), 3e-4 * np.sin(2 * np.pi * 23 * T)
    response = xr.Dataset(
        {
            "camera_displacement": (("axis", "time"), disp),
            "camera_yaw": ("time", yaw),
            "camera_pitch": ("time", pitch),
        },
        coords={"time": T},
    )
    phases, period = 4, 1.0 / camera.frame_rate_hz
    got = scoring.response_metrics(response, camera, phases)
    each = [camera_criteria(cc.PHASED, T, disp, yaw, pitch, camera, T[0] + period * k / phases) for k in range(phases)]
    for name in cc.PHASED:
        values = [e[name] for e in each]
        assert got[name] == pytest.approx(np.mean(values), rel=1e-12)
        assert (got[f"{name}_low"], got[f"{name}_high"]) == (min(values), max(values))
    assert min(e["blur_p95"] for e in each) < max(e["blur_p95"] for e in each)  # the starts see different frames
