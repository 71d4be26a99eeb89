"""The study's metrics against closed forms on hand-built responses (planted bugs the mutation run found).

A response here is `contract.response_dataset` of chosen arrays, so every expected value is a closed form:
sampled sines over whole periods (sum sin^2 = N / 2, sum sin = 0), a planted peak, and C w^2 X^2 T / 2 per
period for a damper of constant C moving as X sin(w t).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from uavdamp.contract import response_dataset
from uavdamp.study import metrics

DT = 1e-3  # s
OPTIONS = SimpleNamespace(early_s=0.5, settle_s=1.0, camera=None)


def response(t, camera_y, camera_z, *, damping=None, stroke_rate_y=None, stroke_rate_z=None):
    zeros = np.zeros_like(t)
    values = {
        "camera_displacement": np.stack([camera_y, camera_z]),
        "camera_yaw": zeros,
        "camera_pitch": zeros,
        "damping": zeros if damping is None else damping,
        "mount_displacement": np.stack([zeros, zeros, zeros]),
        "mount_rotation": np.stack([zeros, zeros, zeros]),
        "base_displacement": np.stack([zeros, zeros]),
        "isolator_stroke": np.stack([zeros, zeros]),
        "isolator_velocity": np.stack(
            [zeros if stroke_rate_y is None else stroke_rate_y, zeros if stroke_rate_z is None else stroke_rate_z]
        ),
    }
    return response_dataset(t, values, {})


def test_peak_early_is_the_planted_peak_before_early_s():
    """A -4 mm spike at 0.3 s, a 9 mm one at 0.7 s (after early_s = 0.5 s), on y; +2 mm at exactly 0.5 s on z."""
    t = np.round(np.arange(0, 2 + DT / 2, DT), 9)
    y, z = np.zeros_like(t), np.zeros_like(t)
    y[300], y[700], z[500], z[501] = -4e-3, 9e-3, 2e-3, 5e-3
    peak = metrics.peak_early(response(t, y, z), OPTIONS)
    np.testing.assert_array_equal(peak.values, [4e-3, 2e-3])
    assert peak.attrs["units"] == "m" and "0.5 s" in peak.attrs["long_name"]


def test_std_total_and_std_settled_of_a_transient_then_a_sine():
    """y: 5 mm constant before 1 s, then 2 mm sin(2 pi 5 (t - 1)) to 3 s (ten whole periods, 2000 + 1 samples).

    std_settled (t >= settle_s = 1 s): the 2001 samples hold the sine's 2000 of whole periods (the last is sin = 0),
    sigma^2 = A^2 (2000 / 2) / 2001. std_total: 1000 samples at 5 mm, 2001 of the sine: mean m = 5 mm 1000 / 3001,
    sigma^2 = (1000 (5 mm)^2 + A^2 1000) / 3001 - m^2. A window of the first 0.5 s would give 0.
    """
    t = np.round(np.arange(0, 3 + DT / 2, DT), 9)
    a, step = 2e-3, 5e-3
    y = np.where(t < 1.0, step, a * np.sin(2 * np.pi * 5 * (t - 1.0)))
    z = np.where(t < 1.0, 0.0, -a * np.sin(2 * np.pi * 5 * (t - 1.0)))
    ds = response(t, y, z)
    settled = metrics.std_settled(ds, OPTIONS)
    expected_settled = a * math.sqrt(1000 / 2001)
    np.testing.assert_allclose(settled.values, [expected_settled, expected_settled], rtol=1e-12)
    mean = step * 1000 / 3001
    expected_total_y = math.sqrt((1000 * step**2 + 1000 * a**2) / 3001 - mean**2)
    total = metrics.std_total(ds, OPTIONS)
    np.testing.assert_allclose(total.values, [expected_total_y, a * math.sqrt(1000 / 3001)], rtol=1e-12)
    assert "after 1.0 s" in settled.attrs["long_name"]


@pytest.mark.parametrize("c", [3.0, 40.0])
def test_energy_of_a_constant_damper_over_whole_periods(c):
    """C w^2 X^2 T / 2 per period and axis for a stroke X sin(w t): sum_n C v_n^2 dt over 4 whole periods.

    y: X = 1 mm at 5 Hz; z: X = 0.5 mm at 5 Hz (v = X w cos(w t)); the left-point sum of cos^2 over whole
    periods sampled uniformly is exactly half the samples.
    """
    w = 2 * np.pi * 5.0
    t = np.round(np.arange(0, 0.8 + DT / 2, DT), 9)  # 4 periods, 801 samples: the last one is not summed
    vy, vz = 1e-3 * w * np.cos(w * t), 0.5e-3 * w * np.cos(w * t)
    ds = response(t, 0 * t, 0 * t, damping=np.full_like(t, c), stroke_rate_y=vy, stroke_rate_z=vz)
    period = 2 * np.pi / w
    expected = 4 * c * w**2 * (1e-3**2 + 0.5e-3**2) * period / 2
    energy = metrics.energy_dissipated(ds, OPTIONS)
    assert float(energy) == pytest.approx(expected, rel=1e-12)
    assert energy.attrs["units"] == "J"


def test_energy_uses_the_damping_held_over_each_step():
    """C switches from 10 to 30 at sample 400 (0.4 s): the left-point sum weighs each step by the C at its start."""
    w = 2 * np.pi * 5.0
    t = np.round(np.arange(0, 0.8 + DT / 2, DT), 9)
    v = 1e-3 * w * np.cos(w * t)
    c = np.where(t < 0.4 - DT / 2, 10.0, 30.0)
    ds = response(t, 0 * t, 0 * t, damping=c, stroke_rate_y=v)
    period = 2 * np.pi / w
    expected = (2 * 10.0 + 2 * 30.0) * w**2 * 1e-3**2 * period / 2  # two whole periods at each C
    assert float(metrics.energy_dissipated(ds, OPTIONS)) == pytest.approx(expected, rel=1e-12)


def test_evaluate_stacks_every_metric_and_refuses_one_without_units(monkeypatch):
    t = np.round(np.arange(0, 2 + DT / 2, DT), 9)
    ds = response(t, np.sin(t), np.cos(t), damping=np.ones_like(t))
    out = metrics.evaluate(ds, OPTIONS)
    assert {"peak_early", "std_total", "std_settled", "energy_dissipated"} <= set(out.data_vars)
    assert out.std_total.dims == ("axis",) and out.energy_dissipated.dims == ()
    monkeypatch.setattr(metrics, "REGISTRY", dict(metrics.REGISTRY))
    metrics.register("bare")(lambda response, options: metrics.xr.DataArray(1.0))
    with pytest.raises(ValueError, match="metric 'bare' returned 'bare' without units or long_name"):
        metrics.evaluate(ds, OPTIONS)
