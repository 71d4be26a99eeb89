"""What the quick run records about its inputs beyond the ANFIS's training range: every tracker update
that sat at its band edge, and the extrapolation the config allowed (config/quick.yaml allows the tracker's
3-12 Hz band beyond its coarse table's 4-10 Hz)."""

from __future__ import annotations

import numpy as np
import xarray as xr
from conftest import quick_run_config


def test_the_band_edge_record_counts_every_update_at_the_edge(quick_run):
    """At the edge: within one FFT bin of the band search, 1 / (window_s x zero_padding) Hz, of either end
    (counted here from tracked_freq and the config, independently of uavdamp.study.comparison.at_band_edge)."""
    tracking = quick_run_config()["study"]["tracking"]
    low, high = tracking["min_freq_hz"], tracking["max_freq_hz"]
    tolerance = 1.0 / (tracking["window_s"] * tracking["zero_padding"])
    with xr.open_dataset(quick_run / "reports-quick" / "study" / "comparison.nc") as ds:
        freq = ds.tracked_freq.transpose("case", "axis", "update_time").values
        edge = ds.at_band_edge.transpose("case", "axis", "update_time").values
        count = ds.band_edge_updates.transpose("case", "axis").values
        share = ds.band_edge_share.transpose("case", "axis").values
        long_name = ds.band_edge_updates.attrs["long_name"]
        warning, cases = ds.attrs.get("band_edge_warning", ""), [str(c) for c in ds.case.values]
    expected = np.zeros(freq.shape, dtype=int)
    for index, f in np.ndenumerate(freq):
        if not np.isnan(f) and (abs(f - low) <= tolerance or abs(high - f) <= tolerance):
            expected[index] = 1
    np.testing.assert_array_equal(edge, expected)
    np.testing.assert_array_equal(count, expected.sum(axis=-1))
    assert f"band's edge [{low:g}, {high:g}] Hz" in long_name, long_name
    expected_share = expected.sum(axis=-1) / np.isfinite(freq).sum(axis=-1)
    np.testing.assert_allclose(share, expected_share, rtol=1e-12)
    for i, case in enumerate(cases):  # the run says so above 5 %, naming the case
        assert (f"{case} " in warning) == bool(np.any(expected_share[i] > 0.05)), (case, warning)


def test_the_allowed_extrapolation_is_recorded_in_the_study_and_the_benchmark(quick_run):
    band = "study.tracking.min_freq_hz/max_freq_hz: the tracker band [3, 12] Hz lies outside [4, 10] Hz"
    for path in ("study/comparison.nc", "benchmark/criteria.nc"):
        with xr.open_dataset(quick_run / "reports-quick" / path) as ds:
            assert ds.attrs.get("extrapolation_warning", "").startswith(band), (path, ds.attrs.keys())
