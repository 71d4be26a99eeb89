"""Spectrum helpers against signals of known content."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uavdamp.signals import spectrum


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


# ----------------------------------------------------------------------------------------------------
# Spectrum and tracking against closed forms (planted bugs: the window, the peak refinement).

HANN_HALF_BIN = math.sin(math.pi / 2) / (math.pi / 2) / (1 - 0.25)


@pytest.mark.parametrize("bin_offset", [0.5, 0.25])
def test_off_bin_sine_shows_the_hann_scalloping(bin_offset):
    """Kills 'Hann replaced by a rectangular window': peak = A sinc(d) / (1 - d^2) for an offset of d bins."""
    n, dt, amp = 4096, 1 / 1024, 3e-3
    f0 = (300 + bin_offset) / (n * dt)
    t = np.arange(n) * dt
    freq, spectrum_amp = spectrum.amplitude_spectrum(amp * np.sin(2 * np.pi * f0 * t + 0.7) + 2.0, dt)
    expected = amp * np.sinc(bin_offset) / (1 - bin_offset**2)
    k = int(np.argmax(spectrum_amp))
    assert k == 300 or (bin_offset == 0.5 and k == 301)
    assert spectrum_amp[k] == pytest.approx(expected, rel=2e-4)
    assert spectrum_amp[0] < 1e-3 * amp  # the offset 2.0 is removed (detrend="constant")
    assert bin_offset != 0.5 or expected == pytest.approx(amp * HANN_HALF_BIN, rel=1e-12)


def test_zero_padding_interpolates_the_same_spectrum():
    """Zero padding by 4 puts bins at the quarter-bin offsets: there the Hann peak is sinc(1/4) / (1 - 1/16)."""
    n, dt = 2048, 1 / 512
    f0 = 200.25 / (n * dt)
    t = np.arange(n) * dt
    freq, amp = spectrum.amplitude_spectrum(np.sin(2 * np.pi * f0 * t), dt, zero_padding=4)
    assert freq.size == 4 * n // 2 + 1 and freq[1] == pytest.approx(1 / (4 * n * dt), rel=1e-12)
    k = int(np.argmax(amp))
    assert freq[k] == pytest.approx(f0, rel=1e-12) and amp[k] == pytest.approx(1.0, rel=2e-4)


def test_linear_detrend_removes_a_ramp_exactly():
    """A pure straight line leaves nothing with detrend="linear"; with "constant" its slope leaks into the bins."""
    t = np.arange(1000) * 0.01
    _, amp = spectrum.amplitude_spectrum(0.3 + 2.0 * t, 0.01, detrend="linear")
    assert np.max(amp) < 1e-12
    _, leaked = spectrum.amplitude_spectrum(0.3 + 2.0 * t, 0.01, detrend="constant")
    assert np.max(leaked[1:]) > 0.1
    with pytest.raises(ValueError, match=r"detrend: must be one of \('constant', 'linear'\), got 'cubic'"):
        spectrum.amplitude_spectrum(t, 0.01, detrend="cubic")
    with pytest.raises(ValueError, match="zero_padding: must be >= 1, got 0"):
        spectrum.amplitude_spectrum(t, 0.01, zero_padding=0)
    with pytest.raises(ValueError, match="signal: need a 1-D array of at least 4 samples"):
        spectrum.amplitude_spectrum(t[:3], 0.01)


@pytest.mark.parametrize("f0", [3.37, 5.71])
def test_the_tracker_refines_the_peak_of_a_short_window(f0):
    """Kills 'the tracker's peak refinement switched off': a noise-free sine in a 0.5 s window.

    The least-squares sine fit is exact for a noise-free sine up to its search tolerance (1e-5 f); the
    interpolated Hann peak alone is biased by the negative-frequency image (0.2 % to 6 % here).
    """
    dt = 0.002
    t = np.arange(0, 2 + dt / 2, dt)
    x = np.sin(2 * np.pi * f0 * t + 0.4)
    times, freq = spectrum.track_dominant(t, x, update_period=0.5, window=0.5, min_freq_hz=3.0, max_freq_hz=12.5)
    np.testing.assert_allclose(times, [0.5, 1.0, 1.5, 2.0], rtol=1e-12)
    np.testing.assert_allclose(freq, f0, rtol=2e-5)
    single = spectrum.dominant_frequency_causal(t, x, 1.5, 0.5, min_freq_hz=3.0, max_freq_hz=12.5)
    assert single == pytest.approx(f0, rel=2e-5)


@pytest.mark.parametrize("f0", [3.37, 5.71, 7.013, 9.49])
def test_the_interpolated_peak_beats_the_zero_padded_bin(f0):
    """The log-parabola through three bins: within 1e-5 of f0 on 2 s of a clean sine (no interpolation: up to
    half the zero-padded bin, 1 / (2 * 8 * 2 s) = 0.031 Hz, i.e. 0.3-1 %)."""
    dt = 0.002
    t = np.arange(1000) * dt
    found = spectrum.dominant_frequency(np.sin(2 * np.pi * f0 * t + 0.4), dt, min_freq_hz=2.0)
    assert found == pytest.approx(f0, rel=1e-5)


def test_band_edges_and_nan_rules():
    dt = 0.002
    t = np.arange(1000) * dt
    x = np.sin(2 * np.pi * 4.0 * t) + 0.5 * np.sin(2 * np.pi * 9.0 * t)
    # the other line's sidelobe biases each peak by < 1e-3 relative here: the band, not the bias, is tested
    assert spectrum.dominant_frequency(x, dt) == pytest.approx(4.0, rel=1e-3)
    assert spectrum.dominant_frequency(x, dt, min_freq_hz=6.0) == pytest.approx(9.0, rel=1e-3)
    assert spectrum.dominant_frequency(x, dt, max_freq_hz=6.0) == pytest.approx(4.0, rel=1e-3)
    assert math.isnan(spectrum.dominant_frequency(np.full(100, 3.0), dt))
    assert math.isnan(spectrum.dominant_frequency(x, dt, min_freq_hz=5.01, max_freq_hz=5.05))  # bins every 1 / 16 Hz


def test_required_span_and_update_times():
    assert spectrum.required_span(1.0, 3.0, 2.0) == pytest.approx(2 / 3, rel=1e-15)
    assert spectrum.required_span(0.5, 3.0, 2.0) == 0.5
    assert spectrum.required_span(0.8, 0.0, 2.0) == 0.8
    np.testing.assert_allclose(spectrum.update_times(2.0, 0.5), [0.5, 1.0, 1.5, 2.0], rtol=1e-15)
    np.testing.assert_allclose(spectrum.update_times(1.49, 0.5), [0.5, 1.0], rtol=1e-15)
    with pytest.raises(ValueError, match="update_period: must be positive, got 0.0"):
        spectrum.update_times(2.0, 0.0)


def test_causal_segment_takes_the_last_window_up_to_t_now():
    """Samples (t_now - window, t_now]: round(window / dt) of them; fewer at the start if they span enough."""
    dt = 0.01
    t = np.arange(301) * dt
    x = np.arange(301.0)
    segment, step = spectrum.causal_segment(t, x, 2.0, 0.5)
    assert step == pytest.approx(dt, rel=1e-12)
    np.testing.assert_array_equal(segment, np.arange(151.0, 201.0))
    early, _ = spectrum.causal_segment(t, x, 0.7, 1.0, min_freq_hz=3.0)  # needs 2 / 3 s: 71 samples span 0.71 s
    np.testing.assert_array_equal(early, np.arange(0.0, 71.0))
    assert spectrum.causal_segment(t, x, 0.6, 1.0, min_freq_hz=3.0) is None  # 0.61 s < 2 / 3 s
    assert spectrum.causal_segment(t[:3], x[:3], 0.02, 1.0) is None
    with pytest.raises(ValueError, match="time: the sampling must be uniform"):
        spectrum.causal_segment(np.r_[t[:150], t[150:] + 0.001], x, 2.0, 1.0)
    with pytest.raises(ValueError, match="window: must be positive, got 0"):
        spectrum.causal_segment(t, x, 2.0, 0)


# ------------------------------------------------------------------- spectrum: the documented compositions


def _two_tone(n=1500, dt=0.002):
    t = np.arange(n) * dt
    return t, np.sin(2 * np.pi * 4.3 * t + 0.2) + 0.6 * np.sin(2 * np.pi * 9.1 * t) + 0.4 * t


@pytest.mark.parametrize(
    "options",
    [
        {},
        dict(min_freq_hz=6.0, max_freq_hz=12.0, zero_padding=4, min_cycles=3.0, detrend="constant", refine=False),
        dict(min_freq_hz=2.0, max_freq_hz=5.0, zero_padding=2, min_cycles=1.0, detrend="linear", refine=True),
    ],
)
def test_track_dominant_is_the_causal_estimate_at_each_update(options):
    """As documented: freq_hz[k] = dominant_frequency_causal(time, signal, t_k, window, **options), defaults
    min_freq_hz 0, max_freq_hz inf, zero_padding 8, min_cycles 2, detrend "linear", refine True."""
    t, x = _two_tone()
    times, freq = spectrum.track_dominant(t, x, update_period=0.5, window=1.0, **options)
    full = dict(min_freq_hz=0.0, max_freq_hz=np.inf, zero_padding=8, min_cycles=2.0, detrend="linear", refine=True)
    full.update(options)
    expected = [spectrum.dominant_frequency_causal(t, x, tk, 1.0, **full) for tk in times]
    np.testing.assert_array_equal(freq, expected)


@pytest.mark.parametrize(
    "options",
    [
        dict(min_freq_hz=6.0, max_freq_hz=12.0, zero_padding=4, min_cycles=3.0, detrend="constant"),
        dict(min_freq_hz=2.0, max_freq_hz=5.0, zero_padding=2, min_cycles=1.0, detrend="linear"),
    ],
)
def test_dominant_frequency_causal_is_segment_then_peak_then_sine_fit(options):
    t, x = _two_tone()
    segment, dt = spectrum.causal_segment(
        t, x, 2.5, 1.0, min_freq_hz=options["min_freq_hz"], min_cycles=options["min_cycles"]
    )
    band = dict(min_freq_hz=options["min_freq_hz"], max_freq_hz=options["max_freq_hz"])
    peak = spectrum.dominant_frequency(
        segment, dt, zero_padding=options["zero_padding"], detrend=options["detrend"], **band
    )
    fitted = spectrum.refine_by_sine_fit(segment, dt, peak, detrend=options["detrend"], **band)
    assert spectrum.dominant_frequency_causal(t, x, 2.5, 1.0, **options, refine=False) == peak
    assert spectrum.dominant_frequency_causal(t, x, 2.5, 1.0, **options) == fitted
    assert fitted != peak


def test_sine_fit_with_a_ramp_needs_the_linear_trend():
    """A 6.37 Hz sine on a steep ramp, 0.4 s: with the line in the model the fit is exact (to its 1e-5 f tolerance)
    from a start 1 % off; the constant-only model leaves the ramp to bend the sine."""
    dt = 0.002
    t = np.arange(200) * dt
    x = np.sin(2 * np.pi * 6.37 * t + 0.5) + 30.0 * t
    assert spectrum.refine_by_sine_fit(x, dt, 6.37 * 1.01, detrend="linear") == pytest.approx(6.37, rel=2e-5)
    assert spectrum.refine_by_sine_fit(x, dt, 6.37 * 1.01, detrend="constant") != pytest.approx(6.37, rel=1e-3)


def test_messages_are_whole():
    t = np.arange(10) * 0.1
    with pytest.raises(ValueError, match=r"^signal: need a 1-D array of at least 4 samples$"):
        spectrum.amplitude_spectrum(t[:3], 0.1)
    spectrum.amplitude_spectrum(t[:4], 0.1)  # four samples are enough
    with pytest.raises(ValueError, match=r"^time and signal: need 1-D arrays of the same length$"):
        spectrum.causal_segment(t, t[:9], 0.5, 1.0)
    with pytest.raises(ValueError, match=r"^time: must increase$"):
        spectrum.causal_segment(t[::-1], t, 0.5, 1.0)
    with pytest.raises(ValueError, match=r"^time: the sampling must be uniform$"):
        spectrum.causal_segment(np.r_[t[:5], t[5:] + 0.01], t, 0.95, 1.0)
    segment, _ = spectrum.causal_segment(t[:4], t[:4], 0.3, 0.4)  # four samples spanning the window: a segment
    np.testing.assert_array_equal(segment, t[:4])


def test_band_edges_are_inclusive_for_a_bin_centred_peak():
    """A sine exactly on bin 40 of a 2 s record (20 Hz, 0.5 Hz bins): a band starting or ending on that bin finds
    it (the parabola through a symmetric peak has no shift); a band starting half a bin later does not."""
    dt, n = 0.005, 400
    t = np.arange(n) * dt
    x = np.sin(2 * np.pi * 20.0 * t)
    kw = dict(zero_padding=1)
    assert spectrum.dominant_frequency(x, dt, min_freq_hz=20.0, **kw) == pytest.approx(20.0, rel=1e-9)
    assert spectrum.dominant_frequency(x, dt, max_freq_hz=20.0, **kw) == pytest.approx(20.0, rel=1e-9)
    assert spectrum.dominant_frequency(x, dt, min_freq_hz=20.0, max_freq_hz=20.0, **kw) == pytest.approx(20.0, rel=1e-9)
    assert spectrum.dominant_frequency(x, dt, min_freq_hz=20.25, **kw) > 20.1  # the 20.5 Hz bin, pulled back


def test_the_peak_is_the_vertex_of_the_log_parabola_through_three_bins():
    """An off-bin 7.3 Hz sine (2 s at 100 Hz) beside a weaker 21 Hz one: the peak is the vertex of the parabola
    through the log Hann amplitudes of the largest bin and its neighbours, on the 8-fold zero-padded grid by
    default, all computed here with numpy's FFT alone; a 0.4 Hz line is found with the default band."""
    dt, n = 0.01, 200
    t = np.arange(n) * dt
    x = np.sin(2 * np.pi * 7.3 * t + 0.4) + 0.3 * np.sin(2 * np.pi * 21.0 * t)
    window = np.hanning(n)
    amp = np.abs(np.fft.rfft((x - x.mean()) * window, 8 * n))
    freq = np.fft.rfftfreq(8 * n, dt)
    k = int(np.argmax(amp))
    a, b, c = np.log(amp[k - 1 : k + 2])
    vertex = freq[k] + 0.5 * (a - c) / (a - 2 * b + c) * (freq[1] - freq[0])
    assert spectrum.dominant_frequency(x, dt) == pytest.approx(vertex, rel=1e-12)
    assert abs(vertex - 7.3) < 0.05
    slow = np.sin(2 * np.pi * 0.4 * np.arange(2000) * dt)
    assert spectrum.dominant_frequency(slow, dt) == pytest.approx(0.4, abs=0.01)


def test_the_sine_fit_removes_a_slope_by_default():
    """A 5.2 Hz sine on a ramp of 30 amplitudes per second, 1 s record: the default fit (offset and slope) finds
    5.2 Hz within its 1e-5 relative search tolerance; without the slope (detrend="constant") the ramp drags it."""
    dt = 1e-3
    t = np.arange(1000) * dt
    x = np.sin(2 * np.pi * 5.2 * t + 0.3) + 30.0 * t
    assert spectrum.refine_by_sine_fit(x, dt, 5.0) == pytest.approx(5.2, rel=1e-4)
    assert abs(spectrum.refine_by_sine_fit(x, dt, 5.0, detrend="constant") - 5.2) > 1e-2


def test_the_dc_bin_is_the_hann_weighted_mean_of_the_detrended_signal():
    """x = t^2 less its mean: the DC bin is |sum((x - mean) w)| / sum(w) (single-sided: not doubled)."""
    t = np.arange(64) * 0.01
    x = t**2
    w = np.hanning(x.size)
    _, amp = spectrum.amplitude_spectrum(x, 0.01)
    assert amp[0] == pytest.approx(abs(np.sum((x - x.mean()) * w)) / w.sum(), rel=1e-12)
    assert amp[0] > 1e-4


def test_the_causal_segment_at_its_edges():
    """The segment ends on the sample at t_now (not the next one); a 10-sample window is whole at 10 samples
    (span = window) and not at 9; by default the whole window is needed; equal or uneven times are refused."""
    time = np.arange(100) * 0.01
    x = np.arange(100.0)
    segment, dt = spectrum.causal_segment(time, x, time[40], 0.1)
    assert segment.tolist() == x[31:41].tolist() and dt == pytest.approx(0.01)
    fine = np.arange(1000) * 1e-4  # t_now on a sample: the next one, 1e-4 s later, is not in the segment
    assert spectrum.causal_segment(fine, np.arange(1000.0), fine[400], 1e-3)[0][-1] == 400.0
    assert spectrum.causal_segment(time, x, time[9], 0.1) is not None  # samples 0..9 span 0.1 s
    assert spectrum.causal_segment(time, x, time[8], 0.1) is None
    assert spectrum.causal_segment(time, x, time[50], 0.03) is None  # 3 samples: fewer than 4
    assert spectrum.causal_segment(time, x, time[30], 0.5) is None  # 0.31 s of record < the 0.5 s window
    assert spectrum.causal_segment(time, x, time[30], 0.5, min_freq_hz=10.0, min_cycles=2.0) is not None
    with pytest.raises(ValueError, match="must increase"):
        spectrum.causal_segment(np.zeros(10), np.zeros(10), 0.0, 0.1)
    uneven = time.copy()
    uneven[50] += 1e-7  # 1e-5 of a step
    with pytest.raises(ValueError, match="uniform"):
        spectrum.causal_segment(uneven, x, uneven[60], 0.2)


def test_the_required_span_is_the_cycles_of_the_lowest_line_or_the_window():
    assert spectrum.required_span(5.0, 0.5, 2.0) == 4.0
    assert spectrum.required_span(5.0, 0.0, 2.0) == 5.0
    assert spectrum.required_span(1.0, 0.5, 2.0) == 1.0
