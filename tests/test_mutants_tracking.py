"""ESPRIT lines and the tracker's options against closed forms and exact messages (issue 17 survivors).

Noise-free sums of sines plus a straight line are exactly the ESPRIT model, so the lines' frequencies and
amplitudes come back to round-off (1e-9 here), however close the lines: 5 and 5.6 Hz in a 1 s window, which a
Hann FFT blends into one peak.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from uavdamp import spectrum, tracking

DT = 0.002
T = np.arange(500) * DT  # 1 s
TWO_LINES = 2 * np.sin(2 * np.pi * 5 * T + 0.3) + 0.7 * np.sin(2 * np.pi * 5.6 * T + 1.1) + 0.1 + 0.03 * T


def test_esprit_resolves_two_close_lines_with_their_amplitudes():
    freq, amp = tracking.esprit_lines(TWO_LINES, DT, 2)
    np.testing.assert_allclose(freq, [5.0, 5.6], rtol=1e-9)
    np.testing.assert_allclose(amp, [2.0, 0.7], rtol=1e-9)


def test_esprit_dominant_band_edges_are_inclusive_and_constant_segments_are_nan():
    assert tracking.esprit_dominant(TWO_LINES, DT, model_order=2, min_freq_hz=3, max_freq_hz=12) == pytest.approx(
        5.0, rel=1e-9)
    assert tracking.esprit_dominant(TWO_LINES, DT, model_order=2, min_freq_hz=5.3, max_freq_hz=12) == pytest.approx(
        5.6, rel=1e-9)
    f_low = tracking.esprit_lines(TWO_LINES, DT, 2)[0][0]
    assert tracking.esprit_dominant(TWO_LINES, DT, model_order=2, min_freq_hz=f_low, max_freq_hz=f_low) == f_low
    assert np.isnan(tracking.esprit_dominant(TWO_LINES, DT, model_order=2, min_freq_hz=7, max_freq_hz=12))
    flat = np.full(500, 0.25)
    flat[0] = 0.25
    assert np.isnan(tracking.esprit_dominant(flat, DT, model_order=2, min_freq_hz=3, max_freq_hz=12))
    step = np.r_[0.0, np.ones(499)]  # only the first sample differs: not constant
    assert not np.isnan(tracking.esprit_dominant(step + TWO_LINES, DT, model_order=2, min_freq_hz=3, max_freq_hz=12))


def test_esprit_needs_enough_samples_for_its_model_order():
    """Hankel rows N // 2 must reach 2 p + 2 exponentials + 2: p = 2 needs 8 rows, i.e. N = 16 samples."""
    x = TWO_LINES[:16]
    tracking.esprit_lines(x, DT, 2)
    with pytest.raises(ValueError, match=r"^study\.tracking\.model_order: 2 sinusoids need more than 15 samples in "
                                         r"the window$"):
        tracking.esprit_lines(x[:15], DT, 2)


def test_frequency_causal_fft_is_spectrum_with_the_options_band():
    options = tracking.TrackerOptions(method="fft", model_order=2, window=1.0, min_freq_hz=3.0, max_freq_hz=5.3,
                                      min_cycles=1.5, zero_padding=8, initial_freq_hz=7.0)
    t = np.arange(1001) * DT
    x = np.sin(2 * np.pi * 4.0 * t) + 2 * np.sin(2 * np.pi * 9.0 * t)
    got = tracking.frequency_causal(t, x, 2.0, options)
    assert 3.5 < got < 5.3  # the stronger 9 Hz line is outside the band (it biases the 4 Hz fit by 4 %)
    assert got == spectrum.dominant_frequency_causal(t, x, 2.0, 1.0, min_freq_hz=3.0, max_freq_hz=5.3,
                                                     zero_padding=8, min_cycles=1.5)
    esprit = dataclasses.replace(options, method="esprit", max_freq_hz=12.0)
    assert np.isnan(tracking.frequency_causal(t, x, 0.3, esprit))  # 0.3 s < 1.5 cycles of 3 Hz
    times, freq = tracking.track(t, x, update_period=1.0, options=esprit)
    np.testing.assert_allclose(times, [1.0, 2.0], rtol=1e-15)
    np.testing.assert_allclose(freq, 9.0, rtol=1e-9)


VALID = dict(method="esprit", model_order=1, window=1.0, min_freq_hz=0.0, max_freq_hz=12.0, min_cycles=0.5,
             zero_padding=1, initial_freq_hz=0.5)


def test_the_smallest_valid_options_pass():
    tracking.TrackerOptions(**VALID).validate()


@pytest.mark.parametrize(("change", "message"), [
    ({"method": "music"}, r"study\.tracking\.method: must be one of \('fft', 'esprit'\), got 'music'"),
    ({"model_order": 0}, r"study\.tracking\.model_order: must be an integer >= 1, got 0"),
    ({"zero_padding": 0}, r"study\.tracking\.zero_padding: must be an integer >= 1, got 0"),
    ({"window": 0.0}, r"study\.tracking\.window_s: must be positive, got 0\.0"),
    ({"min_cycles": 0.0}, r"study\.tracking\.min_cycles: must be positive, got 0\.0"),
    ({"min_freq_hz": 5.0, "max_freq_hz": 5.0}, r"study\.tracking\.max_freq_hz: the band \[5\.0, 5\.0\] Hz is empty"),
    ({"min_freq_hz": -1.0}, r"study\.tracking\.max_freq_hz: the band \[-1\.0, 12\.0\] Hz is empty"),
    ({"initial_freq_hz": 0.0}, r"study\.tracking\.initial_freq_hz: must be positive, got 0\.0"),
])
def test_each_bad_option_is_refused_naming_its_key(change, message):
    with pytest.raises(ValueError, match=rf"^{message}$"):
        tracking.TrackerOptions(**{**VALID, **change}).validate()
