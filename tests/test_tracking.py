"""The tracker's estimators against signals of known lines: resolution, accuracy, causality, bad options."""

import numpy as np
import pytest

from uavdamp import spectrum, tracking
from uavdamp.settings import parse


def parse_tracking(section) -> tracking.TrackerOptions:
    return parse(tracking.TrackerOptions, section, "study.tracking")


def _options(**changes) -> tracking.TrackerOptions:
    """Tracker options: 1 s window, 3-12 Hz, 1.5 cycles, changed by keyword."""
    values = dict(
        method="esprit",
        window=1.0,
        min_freq_hz=3.0,
        max_freq_hz=12.0,
        min_cycles=1.5,
        zero_padding=8,
        model_order=4,
        initial_freq_hz=7.07,
    )
    return tracking.TrackerOptions(**{**values, **changes})


ESPRIT = _options()


def _lines(t, lines, seed, snr_db=None):
    """Sum of sines (freq Hz, amplitude, phase rad) plus seeded white noise at snr_db against the largest line."""
    x = sum(a * np.sin(2 * np.pi * f * t + p) for f, a, p in lines)
    if snr_db is None:
        return x
    largest = max(a for _, a, _ in lines)
    return x + np.sqrt(0.5 * largest**2 / 10 ** (snr_db / 10)) * np.random.default_rng(seed).standard_normal(t.size)


@pytest.mark.parametrize("seed", range(6))
def test_esprit_resolves_two_tones_1hz_apart_in_noise_from_a_1s_window(seed):
    rng = np.random.default_rng(100 + seed)
    f1 = rng.uniform(5.0, 9.0)
    t = np.arange(500) * 0.002  # 1 s window
    x = _lines(t, [(f1, 1.0, rng.uniform(0, 2 * np.pi)), (f1 + 1.0, 0.7, rng.uniform(0, 2 * np.pi))], seed, 20.0)
    found = tracking.frequency_causal(t, x, t[-1], ESPRIT)
    assert abs(found - f1) < 0.1
    # the FFT tracker on the same window blends the two lines (Hann main lobe +-2 Hz): it is off by more
    fft = spectrum.dominant_frequency_causal(t, x, t[-1], 1.0, min_freq_hz=3.0, max_freq_hz=12.0, min_cycles=1.5)
    assert abs(fft - f1) > abs(found - f1)


def test_esprit_finds_lines_and_amplitudes_of_a_noise_free_sum_exactly():
    # the model (sines plus a straight line) is exact here: frequencies and amplitudes to rounding
    t = np.arange(500) * 0.002
    x = _lines(t, [(6.07, 0.5, 0.3), (7.07, 1.1, 1.0), (7.99, 1.7, 2.0)], seed=0) + 0.3 + 0.2 * t
    freq, amp = tracking.esprit_lines(x, 0.002, 3)
    line = freq > 1.0  # the straight line is a double pole at z = 1: a (near-)zero frequency, if any
    freq, amp = freq[line], amp[line]
    np.testing.assert_allclose(freq, [6.07, 7.07, 7.99], rtol=1e-6)
    np.testing.assert_allclose(amp, [0.5, 1.1, 1.7], rtol=1e-5)


@pytest.mark.parametrize("f0", [3.37, 7.013, 11.83])
def test_single_off_bin_sine(f0):
    t = np.arange(0, 1.0 + 1e-9, 0.002)
    x = _lines(t, [(f0, 1.0, 0.4)], seed=int(f0 * 100), snr_db=10.0)
    assert tracking.frequency_causal(t, x, t[-1], ESPRIT) == pytest.approx(f0, rel=0.01)


def test_fft_method_is_the_spectrum_tracker_bit_for_bit():
    t = np.arange(0, 3.0, 0.002)
    x = _lines(t, [(6.3, 1.0, 0.1), (9.1, 0.4, 0.2)], seed=4, snr_db=10.0)
    options = _options(method="fft")
    times, freq = tracking.track(t, x, update_period=0.5, options=options)
    expected = spectrum.track_dominant(
        t, x, update_period=0.5, window=1.0, min_freq_hz=3.0, max_freq_hz=12.0, min_cycles=1.5, zero_padding=8
    )
    np.testing.assert_array_equal(times, expected[0])
    np.testing.assert_array_equal(freq, expected[1])


def test_every_method_is_causal_and_shares_the_window_semantics():
    t = np.arange(1501) * 0.002  # 0 to 3 s
    x = _lines(t, [(6.3, 1.0, 0.1)], seed=7, snr_db=10.0)
    junk = x.copy()
    junk[t > 1.5] = 5.0 * np.sin(2 * np.pi * 10.0 * t[t > 1.5])
    for method in tracking.METHODS:
        options = _options(method=method, min_cycles=2.0)
        times, freq = tracking.track(t, x, update_period=0.5, options=options)
        _, freq_junk = tracking.track(t, junk, update_period=0.5, options=options)
        np.testing.assert_array_equal(freq[times <= 1.5], freq_junk[times <= 1.5])
        assert np.isnan(freq[0])  # 0.5 s < 2 cycles of the lowest searched 3 Hz
        assert freq_junk[times == 3.0][0] == pytest.approx(10.0, rel=0.01), method


@pytest.mark.parametrize(
    ("key", "value", "match"),
    [
        ("method", "music", "study.tracking.method"),
        ("model_order", 0, "study.tracking.model_order"),
        ("model_order", 2.5, "study.tracking.model_order"),
        ("window_s", -1.0, "study.tracking.window_s: must be positive"),
        ("window_s", "long", "study.tracking.window_s: expected a finite number"),
        ("zero_padding", 1.5, "study.tracking.zero_padding: expected an integer"),
        ("surplus", 1, r"study.tracking.surplus: unknown key"),
        ("max_freq_hz", 2.0, "study.tracking.max_freq_hz"),
    ],
)
def test_bad_options_are_refused_naming_the_key(key, value, match):
    cfg = {
        "method": "esprit",
        "window_s": 1.0,
        "min_freq_hz": 3.0,
        "max_freq_hz": 12.0,
        "min_cycles": 1.5,
        "zero_padding": 8,
        "model_order": 10,
        "initial_freq_hz": 7.07,
    }
    assert parse_tracking(cfg).model_order == 10
    with pytest.raises(ValueError, match=match):
        parse_tracking({**cfg, key: value})


def test_a_model_order_too_large_for_the_window_is_refused():
    t = np.arange(0, 1.0, 0.01)  # 100 samples: at most 23 sinusoids
    options = _options(model_order=30)
    with pytest.raises(ValueError, match="study.tracking.model_order"):
        tracking.frequency_causal(t, np.sin(2 * np.pi * 7 * t), t[-1], options)
