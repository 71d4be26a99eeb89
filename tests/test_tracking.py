"""The tracker's estimators against signals of known lines: resolution, accuracy, causality, bad options."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.linalg
from threadpoolctl import threadpool_info, threadpool_limits

from uavdamp.settings import parse
from uavdamp.signals import spectrum, tracking


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
    freq, amp = tracking.esprit_lines(x, 0.002, 3)  # the straight line's double pole at z = 1 is not a line
    np.testing.assert_allclose(freq, [6.07, 7.07, 7.99], rtol=1e-6)
    np.testing.assert_allclose(amp, [0.5, 1.1, 1.7], rtol=1e-5)


@pytest.mark.parametrize(
    ("dt", "max_freq_hz", "q"),
    [(0.002, 12.0, 1), (0.005, 12.0, 1), (1 / 1996, 12.0, 4), (1 / 1996, 47.0, 1), (1e-4, 12.0, 20)],
)
def test_the_decimation_keeps_at_least_40_samples_per_period_of_the_bands_top(dt, max_freq_hz, q):
    """q = floor(fs / (40 f_max)): 500 Hz for 12 Hz is 41.7 samples a period (none), a flight log's 1996 Hz 4."""
    assert tracking.SAMPLES_PER_PERIOD == 40
    assert tracking.decimation_factor(dt, max_freq_hz) == q


@pytest.mark.parametrize(("dt", "q"), [(5e-4, 4), (1e-3, 2)])
def test_a_fine_window_is_low_passed_then_decimated_before_esprit(monkeypatch, dt, q):
    """A 1 s window at 0.5 or 1 ms (q = 4 or 2: ESPRIT sees 500 samples at 2 ms) of ESPRIT's own model, a 7.07 Hz
    line on a straight line, beside a twice larger 495 Hz line, which decimation alone would fold onto 5 Hz, inside
    the 3-12 Hz band: the anti-alias filter leaves the tracker on 7.07 Hz, within 1e-4 Hz since the window's ends are
    extended along a line (the trend passes the filter whole; zero padding leaves 6e-4 Hz here)."""
    t = np.arange(round(1.0 / dt)) * dt
    x = 50.0 + 100.0 * t + _lines(t, [(7.07, 1.0, 0.3), (495.0, 2.0, 1.1)], seed=0)
    seen = []
    esprit = tracking.esprit_lines
    monkeypatch.setattr(
        tracking, "esprit_lines", lambda seg, dt, order: seen.append((seg.size, dt)) or esprit(seg, dt, order)
    )
    tracking._SEEN.clear()
    assert tracking.frequency_causal(t, x, t[-1], ESPRIT) == pytest.approx(7.07, abs=1e-4)
    assert seen == [(500, pytest.approx(2e-3, rel=1e-12))]
    folded = x[::q]  # what plain decimation would give: the 495 Hz line at 5 Hz, larger than 7.07 Hz
    assert tracking.esprit_dominant(folded, 2e-3, model_order=4, min_freq_hz=3.0, max_freq_hz=12.0) == pytest.approx(
        5.0, abs=0.01
    )


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


# ------------------------------------------------------------------- tracking.py: ESPRIT and the options
# ESPRIT lines and the tracker's options against closed forms and exact messages.
#
# Noise-free sums of sines plus a straight line are exactly the ESPRIT model, so the lines' frequencies and
# amplitudes come back to round-off (1e-9 here), however close the lines: 5 and 5.6 Hz in a 1 s window, which a
# Hann FFT blends into one peak.

DT = 0.002
T = np.arange(500) * DT  # 1 s
TWO_LINES = 2 * np.sin(2 * np.pi * 5 * T + 0.3) + 0.7 * np.sin(2 * np.pi * 5.6 * T + 1.1) + 0.1 + 0.03 * T


def test_esprit_resolves_two_close_lines_with_their_amplitudes():
    freq, amp = tracking.esprit_lines(TWO_LINES, DT, 2)
    np.testing.assert_allclose(freq, [5.0, 5.6], rtol=1e-9)
    np.testing.assert_allclose(amp, [2.0, 0.7], rtol=1e-9)


def _blas_threads() -> list[int]:
    return [pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas"]


def test_esprit_solves_on_one_blas_thread_and_gives_the_pools_back(monkeypatch):
    """ESPRIT's SVD and its two least-squares solves run with every BLAS pool (numpy's and scipy.linalg's OpenBLAS)
    at one thread (small dense problems: more threads only contend), and the pools are as they were after the call.
    Seen failing with the limit left out, and with the last solve moved out of it."""
    seen = []
    svd, lstsq = scipy.linalg.svd, scipy.linalg.lstsq
    monkeypatch.setattr(scipy.linalg, "svd", lambda *a, **k: seen.append(_blas_threads()) or svd(*a, **k))
    monkeypatch.setattr(scipy.linalg, "lstsq", lambda *a, **k: seen.append(_blas_threads()) or lstsq(*a, **k))
    with threadpool_limits(2):  # two threads before the call, on any machine
        before = _blas_threads()
        tracking.esprit_lines(TWO_LINES, DT, 2)
        after = _blas_threads()
    assert before and before == after == [2] * len(before)
    assert seen == [[1] * len(before)] * 3


@pytest.mark.parametrize("seed", range(4))
def test_esprit_leaves_a_noisy_trends_near_dc_poles_out_of_its_lines(seed):
    """A steep straight line (5 units/s, 25 times the tones' amplitude over the window) plus the two tones and 1 %
    noise: the trend's double pole splits into a pair near z = 1 with a large amplitude (0.02-0.03 Hz, about 30
    units, before the cut at 1 / (N dt) = 1 Hz); only the tones are lines, and with no lower band edge the dominant
    one is still the 2-unit tone at 5 Hz."""
    noise = 0.02 * np.random.default_rng(200 + seed).standard_normal(T.size)
    x = TWO_LINES + 5.0 * T + noise
    freq, amp = tracking.esprit_lines(x, DT, 2)
    assert tracking.trend_cutoff_hz(T.size, DT) == pytest.approx(1.0 / (500 * DT))
    assert freq.size == 2 and np.all(freq >= 1.0)
    np.testing.assert_allclose(freq, [5.0, 5.6], atol=0.1)  # noise-limited, as the noisy tests above
    found = tracking.esprit_dominant(x, DT, model_order=2, min_freq_hz=0.0, max_freq_hz=12.0)
    assert found == pytest.approx(5.0, abs=0.1)


def test_esprit_keeps_a_line_of_two_cycles_in_the_window():
    """The cut is the resolution, one cycle in the window: a 2 Hz tone in a 1 s window is a line."""
    x = np.sin(2 * np.pi * 2.0 * T + 0.4) + 0.5 * T
    freq, amp = tracking.esprit_lines(x, DT, 1)
    np.testing.assert_allclose(freq, [2.0], rtol=1e-6)
    np.testing.assert_allclose(amp, [1.0], rtol=1e-5)


def test_esprit_dominant_band_edges_are_inclusive_and_constant_segments_are_nan():
    assert tracking.esprit_dominant(TWO_LINES, DT, model_order=2, min_freq_hz=3, max_freq_hz=12) == pytest.approx(
        5.0, rel=1e-9
    )
    assert tracking.esprit_dominant(TWO_LINES, DT, model_order=2, min_freq_hz=5.3, max_freq_hz=12) == pytest.approx(
        5.6, rel=1e-9
    )
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
    with pytest.raises(
        ValueError,
        match=r"^study\.tracking\.model_order: 2 sinusoids need more than 15 samples in "
        r"the window$",
    ):
        tracking.esprit_lines(x[:15], DT, 2)


def test_frequency_causal_fft_is_spectrum_with_the_options_band():
    options = tracking.TrackerOptions(
        method="fft",
        model_order=2,
        window=1.0,
        min_freq_hz=3.0,
        max_freq_hz=5.3,
        min_cycles=1.5,
        zero_padding=8,
        initial_freq_hz=7.0,
    )
    t = np.arange(1001) * DT
    x = np.sin(2 * np.pi * 4.0 * t) + 2 * np.sin(2 * np.pi * 9.0 * t)
    got = tracking.frequency_causal(t, x, 2.0, options)
    assert 3.5 < got < 5.3  # the stronger 9 Hz line is outside the band (it biases the 4 Hz fit by 4 %)
    assert got == spectrum.dominant_frequency_causal(
        t, x, 2.0, 1.0, min_freq_hz=3.0, max_freq_hz=5.3, zero_padding=8, min_cycles=1.5
    )
    esprit = dataclasses.replace(options, method="esprit", max_freq_hz=12.0)
    assert np.isnan(tracking.frequency_causal(t, x, 0.3, esprit))  # 0.3 s < 1.5 cycles of 3 Hz
    times, freq = tracking.track(t, x, update_period=1.0, options=esprit)
    np.testing.assert_allclose(times, [1.0, 2.0], rtol=1e-15)
    np.testing.assert_allclose(freq, 9.0, rtol=1e-9)


VALID = dict(
    method="esprit",
    model_order=1,
    window=1.0,
    min_freq_hz=0.0,
    max_freq_hz=12.0,
    min_cycles=0.5,
    zero_padding=1,
    initial_freq_hz=0.5,
)


def test_the_smallest_valid_options_pass():
    tracking.TrackerOptions(**VALID).validate()


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"method": "music"}, r"study\.tracking\.method: must be one of \('fft', 'esprit'\), got 'music'"),
        ({"model_order": 0}, r"study\.tracking\.model_order: must be an integer >= 1, got 0"),
        ({"zero_padding": 0}, r"study\.tracking\.zero_padding: must be an integer >= 1, got 0"),
        ({"window": 0.0}, r"study\.tracking\.window_s: must be positive, got 0\.0"),
        ({"min_cycles": 0.0}, r"study\.tracking\.min_cycles: must be positive, got 0\.0"),
        (
            {"min_freq_hz": 5.0, "max_freq_hz": 5.0},
            r"study\.tracking\.max_freq_hz: the band \[5\.0, 5\.0\] Hz is empty",
        ),
        ({"min_freq_hz": -1.0}, r"study\.tracking\.max_freq_hz: the band \[-1\.0, 12\.0\] Hz is empty"),
        ({"initial_freq_hz": 0.0}, r"study\.tracking\.initial_freq_hz: must be positive, got 0\.0"),
    ],
)
def test_each_bad_option_is_refused_naming_its_key(change, message):
    with pytest.raises(ValueError, match=rf"^{message}$"):
        tracking.TrackerOptions(**{**VALID, **change}).validate()


def test_esprit_is_computed_once_per_segment_and_again_for_a_changed_one(monkeypatch):
    # every law and damper of a benchmark scenario tracks the same mount signal: one ESPRIT fit per distinct window
    calls = []
    original = tracking.esprit_lines
    monkeypatch.setattr(tracking, "esprit_lines", lambda *a: calls.append(1) or original(*a))
    monkeypatch.setattr(tracking, "_SEEN", tracking.OrderedDict())
    x = TWO_LINES + 1e-3 * np.sin(np.arange(TWO_LINES.size))  # not a segment another test has put in the memory
    first = tracking.esprit_dominant(x, DT, model_order=2, min_freq_hz=3, max_freq_hz=12)
    again = tracking.esprit_dominant(x.copy(), DT, model_order=2, min_freq_hz=3, max_freq_hz=12)
    assert first == again and len(calls) == 1
    changed = x.copy()
    changed[7] += 1e-9
    tracking.esprit_dominant(changed, DT, model_order=2, min_freq_hz=3, max_freq_hz=12)
    tracking.esprit_dominant(x, 2 * DT, model_order=2, min_freq_hz=3, max_freq_hz=12)
    tracking.esprit_dominant(x, DT, model_order=3, min_freq_hz=3, max_freq_hz=12)
    assert len(calls) == 4  # a changed sample, step or model order is a new fit
    monkeypatch.setattr(tracking, "_SEEN", tracking.OrderedDict())
    assert tracking.esprit_dominant(x, DT, model_order=2, min_freq_hz=3, max_freq_hz=12) == first  # computed afresh


def test_a_damped_lines_amplitude_is_its_envelopes_rms_over_the_window():
    """x = A exp(-s t) sin(2 pi f t) over 1 s: one damped pole pair, whose amplitude is 2 |c| times the RMS of its
    envelope, i.e. A times the RMS of exp(-s t) over the samples (closed form of the model, not the code's
    normalisation); the frequency is f to 1e-6. With no trend in the signal, the model's two spare exponentials
    land on the line too and take no amplitude (below 1e-9 of it)."""
    dt, f, a, s = 1e-3, 12.0, 2.0, 1.5
    t = np.arange(1000) * dt
    freq, amp = tracking.esprit_lines(a * np.exp(-s * t) * np.sin(2 * np.pi * f * t), dt, 1)
    k = int(np.argmax(amp))
    assert freq[k] == pytest.approx(f, rel=1e-6)
    assert amp[k] == pytest.approx(a * np.sqrt(np.mean(np.exp(-2 * s * t))), rel=1e-6)
    assert np.delete(amp, k).max() < 1e-9 * a


def test_the_trend_cutoff_is_the_frequency_resolution_and_a_constant_has_no_line():
    assert tracking.trend_cutoff_hz(400, 5e-3) == pytest.approx(0.5)  # 1 / (400 x 5 ms)
    kwargs = {"model_order": 1, "min_freq_hz": 0.0, "max_freq_hz": 100.0}
    assert np.isnan(tracking.esprit_dominant(np.full(200, 0.3), 5e-3, **kwargs))


def test_remembered_lines_are_read_only_and_the_oldest_are_forgotten_first(monkeypatch):
    """The memo of `_esprit_lines_seen` hands out read-only arrays (callers share them) and, when full, drops the
    least recently used segment."""
    monkeypatch.setattr(tracking, "_SEEN", type(tracking._SEEN)())
    monkeypatch.setattr(tracking, "_SEEN_SIZE", 2)
    t = np.arange(64) * 1e-3
    segments = [np.sin(2 * np.pi * f * t) for f in (40.0, 50.0, 60.0)]
    first = tracking._esprit_lines_seen(segments[0], 1e-3, 1)
    assert not first[0].flags.writeable and not first[1].flags.writeable
    tracking._esprit_lines_seen(segments[1], 1e-3, 1)
    tracking._esprit_lines_seen(segments[0], 1e-3, 1)  # used again: now the most recent
    tracking._esprit_lines_seen(segments[2], 1e-3, 1)
    kept = {key[0] for key in tracking._SEEN}
    digest = [tracking.hashlib.blake2b(s.tobytes(), digest_size=16).digest() for s in segments]
    assert kept == {digest[0], digest[2]}
