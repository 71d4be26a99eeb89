"""Vibration levels: unit conversions against hand values, ArduPilot's VIBE against its closed form and a literal
sample-by-sample recursion, line levels of known sines, the track-and-balance comparison."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uavdamp.sources import levels as L


def test_one_g_at_10_hz_in_the_field_units():
    """1 g at 10 Hz: v = 9.80665 / (2 pi 10) = 0.156078 m/s = 6.14479 in/s 0-peak; d = v / (2 pi 10) = 2.48405 mm
    (hand computation from the exact g and inch)."""
    level = L.line_level(9.80665, 10.0)
    assert level["accel_g"] == pytest.approx(1.0, rel=1e-12)
    assert level["velocity_in_s"] == pytest.approx(6.14479, abs=1e-5)
    assert level["displacement_mm"] == pytest.approx(2.48405, abs=1e-5)


def test_the_audit_numbers_at_1_rev():
    """1.3 mm at 44.4 rad/s: 44.4^2 x 1.3e-3 = 2.5628 m s-2 = 0.26133 g and 44.4 x 1.3e-3 / 0.0254 = 2.2724 in/s."""
    f = 44.4 / (2 * math.pi)
    level = L.line_level(44.4**2 * 1.3e-3, f)
    assert level["accel_g"] == pytest.approx(0.26133, abs=1e-5)
    assert level["velocity_in_s"] == pytest.approx(2.2724, abs=1e-4)
    assert level["displacement_m"] == pytest.approx(1.3e-3, rel=1e-12)


def _vibe_closed_form(amplitude: float, freq_hz: float, dt: float) -> float:
    """Steady VIBE of A sin(2 pi f t): A / sqrt(2) times the gain of x - lowpass(x) of the discrete first-order
    filter y_k = y_(k-1) + a (x_k - y_(k-1)): |1 - H| = (1 - a) |1 - e^-jw| / |1 - (1 - a) e^-jw|, w = 2 pi f dt."""
    a = dt / (dt + 1 / (2 * math.pi * 5.0))
    w = 2 * math.pi * freq_hz * dt
    gain = (1 - a) * 2 * math.sin(w / 2) / math.sqrt(1 - 2 * (1 - a) * math.cos(w) + (1 - a) ** 2)
    return amplitude / math.sqrt(2) * gain


@pytest.mark.parametrize(("freq_hz", "rate_hz"), [(100.0, 1000.0), (7.07, 200.0), (28.3, 200.0), (3.0, 400.0)])
def test_vibe_of_a_sine_matches_the_closed_form(freq_hz, rate_hz):
    """The steady VIBE of a pure sine equals the closed form to the residual ripple of the 2 Hz filter on the
    squared signal at 2f averaged over the record (bounded by 1 / (number of periods of 2f) relative: < 1e-2 here,
    the tolerance) and exactly A / sqrt(2) x the floor filter's gain."""
    dt = 1 / rate_hz
    t = np.arange(0, 20.0, dt)
    amp = 3.0
    got = L.vibe(amp * np.sin(2 * np.pi * freq_hz * t + 0.3), dt)
    want = _vibe_closed_form(amp, freq_hz, dt)
    assert float(got) == pytest.approx(want, rel=1.0 / (2 * freq_hz * 20.0))


def test_vibe_tends_to_the_analog_high_pass_as_dt_shrinks():
    """At 64 kHz the discrete filters approach the analog first-order high-pass (gain (f/fc) / sqrt(1 + (f/fc)^2)
    = 0.99875 at 100 Hz; the discrete gain differs by O(f dt): 2.4e-4 here): VIBE of a 100 Hz sine of amplitude A
    is A / sqrt(2) x 0.99875 within 5e-4 relative. (At 1 kHz ArduPilot's filter passes 0.983 of it instead: the
    closed-form test above.)"""
    dt = 1 / 64000
    t = np.arange(0, 2.0, dt)
    want = 2.0 / math.sqrt(2) * 20 / math.sqrt(401)
    assert float(L.vibe(2.0 * np.sin(2 * np.pi * 100 * t), dt)) == pytest.approx(want, rel=5e-4)


def _ardupilot_loop(accel: np.ndarray, dt: float) -> np.ndarray:
    """ArduPilot's VIBE written out sample by sample (as its source reads), independent of scipy.signal."""
    a5 = dt / (dt + 1 / (2 * math.pi * 5.0))
    a2 = dt / (dt + 1 / (2 * math.pi * 2.0))
    floor, vib = None, None
    out = np.empty_like(accel)
    for k, x in enumerate(accel):
        floor = x if floor is None else floor + (x - floor) * a5
        d2 = (x - floor) ** 2
        vib = d2 if vib is None else vib + (d2 - vib) * a2
        out[k] = math.sqrt(vib)
    return out


def test_vibe_series_is_ardupilot_recursion():
    """The scipy.signal filter chain equals the sample-by-sample recursion on a random signal (round-off only)."""
    rng = np.random.default_rng(4)
    dt = 1 / 500
    x = 9.81 + rng.normal(0, 5.0, 2000)
    np.testing.assert_allclose(L.vibe_series(x, dt), _ardupilot_loop(x, dt), rtol=1e-9, atol=1e-12)


def test_vibe_refuses_a_rate_below_the_floor_filter():
    with pytest.raises(ValueError, match="sample rate above 10"):
        L.vibe_series(np.zeros(100), 0.2)


def test_line_levels_find_known_lines():
    """Two lines per axis, off their nominal frequencies by 0.03 Hz (within 0.5 / T = 0.05 Hz), on a displacement
    record: the located frequencies within 1e-3 Hz and the amplitudes within 1e-4 relative (noise-free: the fit is
    exact but for the frequency search's tolerance, 1e-5 f)."""
    dt, T = 0.005, 10.0
    t = np.arange(0, T, dt)
    f1, f4 = 7.07 + 0.03, 28.28 + 0.03
    amps = {"x": (1e-3, 2e-5), "y": (5e-4, 1e-5), "z": (2e-4, 3e-5)}
    x = np.stack([a1 * np.sin(2 * np.pi * f1 * t + 0.4) + a4 * np.cos(2 * np.pi * f4 * t) for a1, a4 in amps.values()])
    ds = L.line_levels(x, dt, {"1/rev": 7.07, "4/rev": 28.28})
    assert ds.freq_hz.sel(line="1/rev") == pytest.approx(f1, abs=1e-3)
    assert ds.freq_hz.sel(line="4/rev") == pytest.approx(f4, abs=1e-3)
    for axis, (a1, a4) in amps.items():
        d1 = float(ds.displacement_m.sel(line="1/rev", axis=axis))
        d4 = float(ds.displacement_m.sel(line="4/rev", axis=axis))
        assert d1 == pytest.approx(a1, rel=1e-4) and d4 == pytest.approx(a4, rel=1e-4)
        g1 = float(ds.accel_g.sel(line="1/rev", axis=axis))
        assert g1 == pytest.approx(a1 * (2 * math.pi * f1) ** 2 / 9.80665, rel=1e-3)
    assert ds.velocity_in_s.attrs["units"] == "in s-1" and "0-peak" in ds.velocity_in_s.attrs["long_name"]


def test_line_levels_refuse_a_line_above_nyquist():
    with pytest.raises(ValueError, match="Nyquist"):
        L.line_levels(np.zeros((3, 100)), 0.01, {"tail": 70.0})


def test_acceleration_from_displacement_gain():
    """The five-point second derivative of sin(w t) has gain (-2cos 2th + 32 cos th - 30) / (12 th^2) (th = w dt,
    the symbol of the fourth-order central difference): within th^4 / 90 (+ 10 %) of 1 in the interior."""
    dt = 0.005
    t = np.arange(0, 2.0, dt)
    for f in (7.07, 28.3):
        th = 2 * math.pi * f * dt
        acc = L.acceleration_from_displacement(np.sin(2 * math.pi * f * t), dt)
        interior = slice(10, -10)
        gain = np.max(np.abs(acc[interior])) / (2 * math.pi * f) ** 2
        assert abs(gain - 1) <= 1.1 * th**4 / 90 + 1e-3


def test_track_and_balance_ratio():
    """A lateral 1/rev of 0.4 in/s is twice the 0.2 in/s limit and a third of the 1.2 in/s damage level."""
    f = 7.07
    accel = 0.4 * 0.0254 * 2 * math.pi * f
    ds = L.levels_dataset(["1/rev"], [f], np.array([[0.0], [accel], [0.0]]))
    cmp = L.track_and_balance(ds)
    assert float(cmp.limit_ratio) == pytest.approx(2.0, rel=1e-12)
    assert float(cmp.damage_ratio) == pytest.approx(1 / 3, rel=1e-12)
    with pytest.raises(ValueError, match="'4/rev' is not among"):
        L.track_and_balance(ds, line="4/rev")
