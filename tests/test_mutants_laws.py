"""Damping laws, the metric registry and the image metrics' window: closed forms and exact messages (issue 17).

Messages are matched whole (anchored), so a test fails when an error names the wrong key or loses its text.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_image_quality import CAM, F

from uavdamp import image_quality as iq
from uavdamp import laws, metrics
from uavdamp.contract import Observation


def _obs(t_now: float = 0.0) -> Observation:
    return Observation(t_now, np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(2), np.zeros(2), np.zeros(2))


def test_schedule_keeps_its_period_and_refuses_empty_with_its_message():
    schedule = laws.Schedule([1, 2], update_period=0.25)
    assert schedule.update_period == 0.25 and laws.Schedule([1.0]).update_period is None
    assert [schedule(_obs()) for _ in range(3)] == [1.0, 2.0, 2.0] and isinstance(schedule(_obs()), float)
    for bad in ([], [[1.0, 2.0]]):
        with pytest.raises(ValueError, match=r"^damping schedule must be a non-empty 1-D sequence$"):
            laws.Schedule(bad)
    with pytest.raises(ValueError, match=r"^damping: must be finite, got inf$"):
        laws.Constant(math.inf)


class _Model:
    """predict([[f_y, f_z, K]]) = f_y + 10 f_z + K / 1000 (N s m-1): which input went where is visible."""

    def predict(self, X):
        X = np.asarray(X, dtype=float)
        return X[:, 0] + 10 * X[:, 1] + X[:, 2] / 1000


def test_anfis_law_needs_both_frequencies_and_accepts_any_positive_stiffness():
    freqs = {"y": math.nan, "z": 8.0}

    def track(time, signal, t_now):
        return freqs["y"] if signal is obs.mount_y else freqs["z"]

    obs = _obs()
    law = laws.AnfisLaw(_Model(), 0.5, 3.0, track)  # K = 0.5 N/m: small but valid
    assert law(obs) == 3.0  # f_y not yet known: the initial demand
    freqs["y"] = 7.0
    assert law(obs) == pytest.approx(7.0 + 80.0 + 0.5e-3, rel=1e-15)
    freqs["z"] = math.nan
    assert law(obs) == pytest.approx(87.0005, rel=1e-15)  # holds its last demand
    law.reset()
    assert law(obs) == 3.0
    for bad in (0.0, -1.0, math.inf):
        with pytest.raises(ValueError, match=rf"^stiffness must be > 0, got {bad}$"):
            laws.AnfisLaw(_Model(), bad, 3.0, track)


def test_a_metric_registered_twice_is_refused_naming_it(monkeypatch):
    monkeypatch.setattr(metrics, "REGISTRY", dict(metrics.REGISTRY))
    with pytest.raises(ValueError, match=r"^metric 'std_total' is registered twice$"):
        metrics.register("std_total")(lambda response, options: None)


def test_named_keeps_value_and_drops_coordinates():
    value = metrics.xr.DataArray([1.0, 2.0], dims="axis", coords={"axis": ["y", "z"], "extra": 3})
    out = metrics._named(value, "m", "two values")
    assert out.attrs == {"units": "m", "long_name": "two values"} and list(out.coords) == []
    np.testing.assert_array_equal(out.values, [1.0, 2.0])
    assert metrics._named(2.5, "J", "one").item() == 2.5


# ---------------------------------------------------------------------- image metrics over a window


def _ramp():
    """0.3 s at 0.1 ms; yaw 0 until 0.1 s, then a rate of 0.5 rad s-1 (a smear of F 0.5 T = 4.1 px a frame)."""
    time = np.arange(3001) * 1e-4
    yaw = 0.5 * np.maximum(time - 0.1, 0.0)
    return time, np.zeros((2, time.size)), yaw, np.zeros_like(time)


def test_frame_metrics_honour_the_window():
    """Window [0.1, 0.2] s at 25 frames/s and 4 ms exposure: frames at 0.10, 0.14, 0.18 s; a pure yaw psi moves
    the image by F tan(psi), so a frame's smear is F (tan psi_end - tan psi_start)."""
    frames = iq.frame_metrics(*_ramp(), CAM, 0.1, 0.2)
    starts = np.array([0.1, 0.14, 0.18])
    np.testing.assert_allclose(frames.start_s, starts, rtol=1e-12)
    psi = 0.5 * (starts - 0.1)
    np.testing.assert_allclose(frames.blur_px, F * (np.tan(psi + 0.5 * CAM.exposure_s) - np.tan(psi)), rtol=1e-9)


def test_image_metrics_honour_the_window():
    """In [0.1, 0.2] s: every frame smeared (sharp fraction 0), peak yaw 0.5 * 0.1 s = 0.05 rad (record: 0.1)."""
    out = iq.image_metrics(*_ramp(), CAM, 0.1, 0.2)
    assert out["sharp_fraction"][0] == 0.0
    assert out["los_yaw_peak"][0] == pytest.approx(0.05, rel=1e-12)
    whole = iq.image_metrics(*_ramp(), CAM)
    assert whole["los_yaw_peak"][0] == pytest.approx(0.1, rel=1e-12) and whole["sharp_fraction"][0] > 0


@pytest.mark.parametrize("series", ["camera_displacement y", "camera_displacement z", "camera_yaw", "camera_pitch"])
def test_a_non_finite_response_series_is_refused_naming_it(series):
    time, disp, yaw, pitch = _ramp()
    disp, yaw, pitch = disp.copy(), yaw.copy(), pitch.copy()
    target = {
        "camera_displacement y": disp[0],
        "camera_displacement z": disp[1],
        "camera_yaw": yaw,
        "camera_pitch": pitch,
    }[series]
    target[5] = np.nan
    with pytest.raises(ValueError, match=rf"^{series} holds non-finite values$"):
        iq.frame_metrics(time, disp, yaw, pitch, CAM)


def test_integer_displacements_are_read_as_floats():
    time = np.arange(3001) * 1e-4
    ints = np.zeros((2, time.size), dtype=int)
    frames = iq.frame_metrics(time, ints, np.zeros_like(time), np.zeros_like(time), CAM)
    assert np.all(frames.blur_px == 0.0)
