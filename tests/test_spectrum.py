"""Spectrum helpers against signals of known content."""

import numpy as np
import pytest

from uavdamp import spectrum


def test_amplitude_of_a_bin_centred_sine():
    dt, n = 0.01, 1000
    t = np.arange(n) * dt
    freq, amp = spectrum.amplitude_spectrum(2.5e-3 * np.sin(2 * np.pi * 5.0 * t) + 1.0, dt)
    k = np.argmax(amp)
    assert freq[k] == pytest.approx(5.0)
    assert amp[k] == pytest.approx(2.5e-3, rel=1e-3)


@pytest.mark.parametrize("f0", [3.17, 7.071, 8.0])
def test_dominant_frequency_between_bins(f0):
    dt = 0.005
    t = np.arange(0, 2.0, dt)
    rng = np.random.default_rng(1)
    signal = np.sin(2 * np.pi * f0 * t + 0.3) + 0.5 * np.sin(2 * np.pi * 1.0 * t) + 0.05 * rng.standard_normal(t.size)
    found = spectrum.dominant_frequency(signal, dt, min_freq_hz=2.0)
    assert found == pytest.approx(f0, rel=0.01)


def test_band_without_bins_and_bad_input():
    t = np.arange(0, 1, 0.01)
    assert np.isnan(spectrum.dominant_frequency(np.sin(t), 0.01, min_freq_hz=1e3))
    with pytest.raises(ValueError, match="dt"):
        spectrum.amplitude_spectrum(np.sin(t), 0.0)


# ---------------------------------------------------------------------------- causal tracking


def _noisy_sine(f0, dt, duration, snr_db, seed, phase=0.4):
    """Unit sine at f0 Hz plus white noise at the given SNR (signal power / noise power), seeded."""
    t = np.arange(int(round(duration / dt)) + 1) * dt
    noise_std = np.sqrt(0.5 / 10 ** (snr_db / 10))
    rng = np.random.default_rng(seed)
    return t, np.sin(2 * np.pi * f0 * t + phase) + noise_std * rng.standard_normal(t.size)


@pytest.mark.parametrize("dt", [0.002, 0.004])
@pytest.mark.parametrize("f0", [3.37, 5.71, 7.013, 9.49, 11.83])
def test_tracking_finds_a_noisy_sine_within_one_percent_with_a_1s_window(f0, dt):
    t, x = _noisy_sine(f0, dt, 4.0, snr_db=10.0, seed=int(f0 * 1000))
    times, freq = spectrum.track_dominant(t, x, update_period=0.5, window=1.0, min_freq_hz=3.0, max_freq_hz=12.5)
    np.testing.assert_allclose(times, np.arange(1, 9) * 0.5)
    assert np.isnan(freq[0])  # 0.5 s < 2 cycles of the lowest searched 3 Hz
    assert np.all(np.abs(freq[1:] / f0 - 1) < 0.01), freq


def test_tracking_starts_once_two_cycles_of_the_lowest_frequency_are_seen():
    t, x = _noisy_sine(7.0, 0.002, 2.0, snr_db=30.0, seed=3)
    options = dict(window=1.0, max_freq_hz=12.0)
    assert np.isnan(spectrum.dominant_frequency_causal(t, x, 0.0, min_freq_hz=3.0, **options))
    assert np.isnan(spectrum.dominant_frequency_causal(t, x, 0.5, min_freq_hz=3.0, **options))  # needs 0.667 s
    early = spectrum.dominant_frequency_causal(t, x, 0.5, min_freq_hz=4.0, **options)  # needs 0.5 s: has 0.502 s
    assert early == pytest.approx(7.0, rel=0.01)
    assert spectrum.required_span(1.0, 3.0, 2.0) == pytest.approx(2 / 3)
    assert spectrum.required_span(0.4, 3.0, 2.0) == 0.4


def _frequency_step(f_before, f_after, t_step, dt, duration, snr_db, seed):
    """Continuous-phase sine whose frequency steps at t_step, plus seeded noise."""
    t = np.arange(int(round(duration / dt)) + 1) * dt
    phase = 2 * np.pi * np.where(t < t_step, f_before * t, f_before * t_step + f_after * (t - t_step))
    noise_std = np.sqrt(0.5 / 10 ** (snr_db / 10))
    return t, np.sin(phase) + noise_std * np.random.default_rng(seed).standard_normal(t.size)


def test_step_change_is_followed_once_the_window_has_filled():
    # window 1 s > period 0.5 s: the first update whose window (t_k - 1, t_k] lies after the 3.2 s step is 4.5 s
    t, x = _frequency_step(5.0, 9.0, 3.2, 0.002, 6.0, snr_db=10.0, seed=5)
    times, freq = spectrum.track_dominant(t, x, update_period=0.5, window=1.0, min_freq_hz=3.0, max_freq_hz=12.0)
    before = (times >= 1.0) & (times <= 3.2)
    after = times >= 3.2 + 1.0
    assert times[after][0] == pytest.approx(4.5)
    assert np.all(np.abs(freq[before] / 5.0 - 1) < 0.01), freq
    assert np.all(np.abs(freq[after] / 9.0 - 1) < 0.01), freq
    # straddling updates: the part holding most of the Hann-weighted window wins
    assert freq[times == 3.5][0] == pytest.approx(5.0, rel=0.03)  # 0.7 s of 5 Hz, 0.3 s of 9 Hz
    assert freq[times == 4.0][0] == pytest.approx(9.0, rel=0.03)  # 0.2 s of 5 Hz, 0.8 s of 9 Hz


def test_step_at_an_update_is_followed_at_the_very_next_update_when_window_equals_period():
    t, x = _frequency_step(5.0, 9.0, 3.0, 0.002, 5.0, snr_db=20.0, seed=6)
    times, freq = spectrum.track_dominant(t, x, update_period=0.5, window=0.5, min_freq_hz=4.0, max_freq_hz=12.0)
    assert freq[times == 3.0][0] == pytest.approx(5.0, rel=0.01)
    assert freq[times == 3.5][0] == pytest.approx(9.0, rel=0.01)


def test_tracking_is_causal():
    t, x = _noisy_sine(6.3, 0.002, 3.0, snr_db=10.0, seed=7)
    junk = x.copy()
    later = t > 1.5
    junk[later] = 5.0 * np.sin(2 * np.pi * 10.0 * t[later])  # a different, larger signal after t_k = 1.5 s
    options = dict(update_period=0.5, window=1.0, min_freq_hz=3.0, max_freq_hz=12.0)
    times, freq = spectrum.track_dominant(t, x, **options)
    _, freq_junk = spectrum.track_dominant(t, junk, **options)
    np.testing.assert_array_equal(freq[times <= 1.5], freq_junk[times <= 1.5])
    assert freq_junk[times == 3.0][0] == pytest.approx(10.0, rel=0.01)  # the change is seen afterwards
    # a shorter record ending at t_k gives the same number
    keep = t <= 1.5 + 1e-9
    assert (
        spectrum.dominant_frequency_causal(t[keep], x[keep], 1.5, 1.0, min_freq_hz=3.0, max_freq_hz=12.0)
        == freq[times == 1.5][0]
    )


def test_sine_fit_removes_the_bias_of_a_short_window():
    # a 0.5 s window holds 1.6 cycles of 3.2 Hz: the Hann peak is pulled by the negative-frequency image
    t = np.arange(250) * 0.002
    x = np.sin(2 * np.pi * 3.2 * t + 1.0)
    hann = spectrum.dominant_frequency(x, 0.002, min_freq_hz=1.0, detrend="linear")
    fitted = spectrum.refine_by_sine_fit(x, 0.002, hann)
    assert abs(fitted / 3.2 - 1) < 1e-4 < abs(hann / 3.2 - 1)


def test_linear_detrend_keeps_a_drifting_signal_in_band():
    t = np.arange(500) * 0.002
    x = 0.1 * np.sin(2 * np.pi * 4.1 * t) + 2.0 * t  # slow drift much larger than the vibration
    assert spectrum.dominant_frequency(x, 0.002, min_freq_hz=3.0, detrend="linear") == pytest.approx(4.1, rel=0.01)
    with pytest.raises(ValueError, match="detrend"):
        spectrum.amplitude_spectrum(x, 0.002, detrend="quadratic")
