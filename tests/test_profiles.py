"""Stated sources: the sine-on-random helicopter source's lines and floor against their definition, the multirotor
source's VIBE against ArduPilot's recursion written out, seeding, refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import welch
from scipy.stats import chi2

from uavdamp.contract import MountMotion
from uavdamp.sources import profiles as P

G = 9.80665
ROTOR_HZ, TAIL_HZ = 44.4 / (2 * math.pi), 222.0 / (2 * math.pi)


def _sine_fit(x: np.ndarray, dt: float, freqs) -> np.ndarray:
    """Amplitudes of sines at known freqs by one least-squares fit (with an offset): the test's own estimator."""
    t = np.arange(x.size) * dt
    cols = [np.ones_like(t)] + [f(2 * np.pi * fr * t) for fr in freqs for f in (np.cos, np.sin)]
    coef = np.linalg.lstsq(np.column_stack(cols), x, rcond=None)[0]
    return np.hypot(coef[1::2], coef[2::2])


def test_lines_without_floor_are_exact():
    """Without the floor the acceleration is the lines alone: the fitted amplitudes equal the stated ones (g) to
    round-off, and the displacement's equal a / (2 pi f)^2 (the analytic double integral)."""
    lines = P.helicopter_lines(ROTOR_HZ, 4, TAIL_HZ, 2)
    ds = P.sine_on_random(lines, None, duration_s=4.0, sample_rate_hz=500.0, highpass_hz=2.0, seed=3)
    dt = 1 / 500.0
    freqs = [line.freq_hz for line in lines]
    for i, _axis in enumerate("xyz"):
        stated = np.array([line.accel_g[i] for line in lines])
        got = _sine_fit(ds.mount_acceleration.values[i], dt, freqs) / G
        np.testing.assert_allclose(got, stated, rtol=1e-8)
        disp = _sine_fit(ds.mount_displacement.values[i], dt, freqs)
        np.testing.assert_allclose(disp, stated * G / (2 * np.pi * np.array(freqs)) ** 2, rtol=1e-8)
    # the 1/rev stated at the track-and-balance limit laterally: 0.2 in/s 0-peak
    assert float(ds.velocity_in_s.sel(line="1/rev", mount_axis="y")) == pytest.approx(0.2, rel=1e-12)


def test_lines_on_the_floor_within_their_noise():
    """With the floor (one-sided PSD S) a least-squares sine coefficient has standard deviation sqrt(S / T) (T the
    record length; the noise's autocovariance summed against the cosine: (2/n)^2 (n/2) fs S/2): each line's fitted
    amplitude lies within 5 sqrt(S / T) of the stated one (a Rayleigh deviation beyond 5 sigma: p = 4e-6)."""
    T, fs = 60.0, 500.0
    ds = P.helicopter_source(ROTOR_HZ, 4, tail_hz=TAIL_HZ, duration_s=T, sample_rate_hz=fs, seed=11)
    floor = P.helicopter_floor()
    freqs = ds.freq_hz.values
    for i, axis in enumerate("xyz"):
        got = _sine_fit(ds.mount_acceleration.values[i], 1 / fs, freqs)
        stated = ds.accel_m_s2.sel(mount_axis=axis).values
        in_band = (freqs >= floor.band_hz[0]) & (freqs <= floor.band_hz[1])
        sigma = np.sqrt(floor.psd_g2_hz[i] * G**2 / T) * in_band
        assert np.all(np.abs(got - stated) <= 5 * sigma + 1e-9 * stated), (axis, got - stated, sigma)


def _welch_bounds(nu: float, n_tests: int, p: float = 0.01) -> tuple[float, float]:
    """Two-sided chi-square interval of a Welch estimate / true PSD with nu degrees of freedom, Bonferroni over
    n_tests frequencies (family-wise p)."""
    q = p / (2 * n_tests)
    return chi2.ppf(q, nu) / nu, chi2.ppf(1 - q, nu) / nu


def test_floor_psd_matches_its_definition():
    """Welch (Hann, 2 s segments, 50 % overlap) of the floor alone: K segments give nu = 2K / (1 + 2 c^2) degrees
    of freedom (c = 0.167, the Hann 50 %-overlap correlation, Welch 1967). Every in-band bin (two bins in from the
    edges) lies within the Bonferroni chi-square interval of S (family-wise p = 0.01); the band mean of the M bins
    within the chi-square interval of nu M / 2 degrees of freedom (choice: half, for the Hann window's correlation
    of neighbouring bins; p = 0.01); below the band < 1e-3 S. The displacement's PSD is the acceleration's over
    (2 pi f)^4 within the same intervals."""
    fs, T = 250.0, 120.0
    floor = P.Floor((2e-5, 1e-5, 4e-5), (10.0, 80.0))
    ds = P.sine_on_random((), floor, duration_s=T, sample_rate_hz=fs, highpass_hz=2.0, seed=5)
    nperseg = int(2 * fs)
    freq, psd = welch(ds.mount_acceleration.values / G, fs=fs, nperseg=nperseg, axis=-1)
    _, dpsd = welch(ds.mount_displacement.values, fs=fs, nperseg=nperseg, axis=-1)
    k = (ds.time.size - nperseg) // (nperseg // 2) + 1
    nu = 2 * k / (1 + 2 * 0.167**2)
    df = freq[1] - freq[0]
    inside = (freq >= floor.band_hz[0] + 2 * df) & (freq <= floor.band_hz[1] - 2 * df)
    m = int(inside.sum())
    lo, hi = _welch_bounds(nu, 6 * m)
    band_lo, band_hi = _welch_bounds(nu * m / 2, 6)
    below = (freq > 0) & (freq <= floor.band_hz[0] - 3 * df)
    for i in range(3):
        s = floor.psd_g2_hz[i]
        for ratio in (psd[i, inside] / s, dpsd[i, inside] / (s * G**2 / (2 * np.pi * freq[inside]) ** 4)):
            assert lo <= ratio.min() and ratio.max() <= hi, (i, ratio.min(), ratio.max(), lo, hi)
            assert band_lo <= ratio.mean() <= band_hi, (i, ratio.mean(), band_lo, band_hi)
        assert psd[i, below].max() < 1e-3 * s


def _ardupilot_vibe(accel: np.ndarray, dt: float) -> np.ndarray:
    """ArduPilot's VIBE recursion sample by sample (5 Hz floor, 2 Hz filter on the square), one axis."""
    a5, a2 = (dt / (dt + 1 / (2 * math.pi * fc)) for fc in (5.0, 2.0))
    floor = vib = None
    out = np.empty_like(accel)
    for k, x in enumerate(accel):
        floor = x if floor is None else floor + (x - floor) * a5
        d2 = (x - floor) ** 2
        vib = d2 if vib is None else vib + (d2 - vib) * a2
        out[k] = vib
    return out


@pytest.mark.parametrize("level", [15.0, 30.0, 60.0])
def test_multirotor_source_hits_its_vibe(level):
    """The largest axis's steady VIBE, from the recursion written out (mean of the filtered square after 10 time
    constants of the 2 Hz filter), equals the stated level within 1e-6 relative (one linear scale factor: exact up
    to round-off); the axes keep the stated weights' order (z largest); the blade pass lies in 70-140 Hz."""
    fs = 1000.0
    ds = P.multirotor_source(level, duration_s=5.0, seed=7)
    dt = 1 / fs
    skip = math.ceil(10 / (2 * math.pi * 2.0) / dt)
    vibes = [math.sqrt(np.mean(_ardupilot_vibe(a, dt)[skip:])) for a in ds.mount_acceleration.values]
    assert max(vibes) == pytest.approx(level, rel=1e-6)
    assert int(np.argmax(vibes)) == 2
    blade_pass = ds.freq_hz.values[["1x blade pass" in str(n) for n in ds.line.values]]
    assert blade_pass.min() >= 70.0 and blade_pass.max() <= 140.0


def test_one_seed_one_signal():
    kw = {"duration_s": 2.0, "sample_rate_hz": 500.0, "seed": 1}
    a = P.helicopter_source(ROTOR_HZ, 4, tail_hz=TAIL_HZ, **kw)
    b = P.helicopter_source(ROTOR_HZ, 4, tail_hz=TAIL_HZ, **kw)
    c = P.helicopter_source(ROTOR_HZ, 4, tail_hz=TAIL_HZ, **{**kw, "seed": 2})
    np.testing.assert_array_equal(a.mount_displacement.values, b.mount_displacement.values)
    assert np.max(np.abs(a.mount_displacement.values - c.mount_displacement.values)) > 1e-6
    motion = P.mount_motion(a)
    assert isinstance(motion, MountMotion) and motion.translation.shape == motion.rotation.shape == (3, a.time.size)


def test_refusals_name_the_key():
    kw = {"duration_s": 1.0, "sample_rate_hz": 200.0, "seed": 0}
    with pytest.raises(ValueError, match=r"lines\['1/rev'\].freq_hz: .*highpass_hz"):
        P.sine_on_random([P.Line("1/rev", 1.0, (0, 0.01, 0))], None, highpass_hz=2.0, **kw)
    with pytest.raises(ValueError, match=r"lines\['12/rev'\].freq_hz: .*Nyquist\) = \[2.0, 80.0\)"):
        P.helicopter_source(ROTOR_HZ, 4, tail_hz=TAIL_HZ, **{**kw, "sample_rate_hz": 160.0})
    with pytest.raises(ValueError, match=r"floor.band_hz"):
        P.sine_on_random((), P.Floor((1e-5,) * 3, (5.0, 150.0)), highpass_hz=2.0, **kw)
