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
