"""The levels survey: weak lines under a flight's slow drift, each input's lines, VIBE and track-and-balance ratio
against their definitions, and the padding between inputs of different line counts."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_levels import _vibe_closed_form

from uavdamp.settings import ConfigError, parse
from uavdamp.sources import levels as L
from uavdamp.sources import levels_survey as S

DT, T = 0.005, 40.0


def _drifting(weak_m: float) -> np.ndarray:
    """40 s at 200 Hz: a flight's drift (0.3 m over a 60 s period and a 0.1 m quadratic) on x, a 3 g line at
    7.0665 Hz and a weak line of `weak_m` at 28.266 Hz (4/rev) on every axis."""
    t = np.arange(0, T, DT)
    drift = 0.3 * np.sin(2 * np.pi * t / 60.0 + 0.3) + 0.1 * (t / T) ** 2
    one = 3 * 9.80665 / (2 * np.pi * 7.0665) ** 2 * np.sin(2 * np.pi * 7.0665 * t)
    weak = weak_m * np.cos(2 * np.pi * 28.266 * t + 1.0)
    return np.stack([drift + one + weak, one + weak, weak])


def test_a_weak_line_under_a_drift_is_read_within_two_percent():
    """The drift is not periodic in the record: a rectangular least-squares fit leaks it into the 4/rev line by
    tens of micrometres (1 um reads 16 um with uniform weights); the Hann-weighted fit
    reads 1 um within 2 % on every axis (the drift's sidelobes fall as f^-3)."""
    ds = L.line_levels(_drifting(1e-6), DT, {"1/rev": 7.0665, "4/rev": 28.266})
    assert ds.displacement_m.sel(line="4/rev").values == pytest.approx([1e-6] * 3, rel=0.02)
    assert float(ds.accel_g.sel(line="1/rev", axis="y")) == pytest.approx(3.0, rel=1e-3)


def test_lines_closer_than_the_window_resolves_are_refused():
    with pytest.raises(ValueError, match="2 / T"):
        L.line_levels(np.zeros((3, 1000)), DT, {"a": 10.0, "b": 10.3})  # 5 s: 2 / T = 0.4 Hz


def _record(amp_m: float, freq_hz: float, lines: dict, kind: str = "case") -> S.Record:
    t = np.arange(0, 10.0, DT)
    disp = np.stack([0 * t, amp_m * np.sin(2 * np.pi * freq_hz * t), 0.5 * amp_m * np.sin(2 * np.pi * freq_hz * t)])
    return S.Record(kind, "test", DT, lines, disp, rotation_rad=np.stack([0 * t, 1e-3 * np.sin(2 * np.pi * t), 0 * t]))


def test_survey_reads_each_input_at_its_lines():
    """Input a: 1 mm at 7 Hz read as "1/rev": lateral velocity 2 pi 7 x 1e-3 / 0.0254 = 1.7316 in/s, 8.658 times
    the 0.2 in/s limit; input b: the same motion with no named line (a padded, empty row, no ratio); the VIBE of
    both from the displacement's second derivative; the rotation's std."""
    ds = S.survey({"a": _record(1e-3, 7.0, {"1/rev": 7.0, "2/rev": 14.0}), "b": _record(1e-3, 7.0, {})})
    v = 2 * math.pi * 7.0 * 1e-3 / 0.0254
    assert float(ds.velocity_in_s.sel(input="a", line=0, axis="y")) == pytest.approx(v, rel=1e-4)
    assert float(ds.velocity_in_s.sel(input="a", line=0, axis="z")) == pytest.approx(0.5 * v, rel=1e-4)
    assert float(ds.track_and_balance_ratio.sel(input="a")) == pytest.approx(v / 0.2, rel=1e-4)
    assert np.isnan(float(ds.track_and_balance_ratio.sel(input="b")))
    assert list(ds.line_name.sel(input="b").values) == ["", ""] and np.all(np.isnan(ds.accel_g.sel(input="b")))
    expected = L.vibe(L.acceleration_from_displacement(_record(1e-3, 7.0, {}).displacement_m, DT), DT)
    assert ds.vibe_m_s2.sel(input="b").values == pytest.approx(expected, rel=1e-12)
    assert float(ds.rotation_std_rad.sel(input="a", axis="y")) == pytest.approx(1e-3 / math.sqrt(2), rel=1e-9)
    for v in ("accel_g", "velocity_in_s", "vibe_m_s2", "track_and_balance_ratio", "freq_hz"):
        assert ds[v].attrs["units"] and ds[v].attrs["long_name"]


def test_an_acceleration_record_is_read_as_logged():
    """A log's record is its acceleration: a 0.5 g line at 40 Hz reads 0.5 g, and its VIBE is the acceleration's
    own (no differentiation)."""
    t = np.arange(0, 10.0, 0.001)
    accel = np.stack([0 * t, 0.5 * 9.80665 * np.sin(2 * np.pi * 40.0 * t), 9.80665 + 0 * t])
    peaks = S.band_peaks(accel, 0.001, (20.0, 47.0))
    assert list(peaks) == ["peak y"] and peaks["peak y"] == pytest.approx(40.0, abs=0.01)  # x, z hold no line
    record = S.Record("flight log", "test", 0.001, peaks, acceleration_m_s2=accel)
    ds = S.survey({"log": record})
    assert float(ds.accel_g.sel(input="log", line=0, axis="y")) == pytest.approx(0.5, rel=1e-4)
    assert ds.vibe_m_s2.sel(input="log").values == pytest.approx(L.vibe(accel, 0.001), rel=1e-12)
    with pytest.raises(ValueError, match="exactly one"):
        S.record_levels(S.Record("case", "", 0.001, {}))


def test_helicopter_lines_are_the_rotors_orders_and_the_tails_blade_pass():
    lines = S.helicopter_lines(7.0, (1, 2, 4), 35.0, 2)
    assert lines == {"1/rev": 7.0, "2/rev": 14.0, "4/rev": 28.0, "tail 1/rev": 35.0, "tail 2/rev": 70.0}


@pytest.mark.parametrize(
    ("key", "value", "rule"),
    [
        ("settle_s", -1.0, ">= 0"),
        ("orders", [0, 1], ">= 1"),
        ("orders", [2, 2], "distinct"),
        ("source_duration_s", 1.0, "VIBE"),
    ],
)
def test_a_bad_levels_key_is_refused_by_name(key, value, rule):
    with pytest.raises(ConfigError, match=f"levels.{key}.*{rule}"):
        parse(S.LevelsSection, {"settle_s": 10.0, "orders": [1, 2], "source_duration_s": 10.0} | {key: value}, "levels")


def test_a_record_too_short_for_vibe_has_no_vibe_but_its_lines():
    """1.5 s (the quick config's cases) is below VIBE's 1.59 s: NaN VIBE, the line still read."""
    t = np.arange(0, 1.5, DT)
    disp = np.stack([0 * t, 1e-3 * np.sin(2 * np.pi * 7.0 * t), 0 * t])
    ds = S.survey({"short": S.Record("case", "", DT, {"1/rev": 7.0}, disp)})
    assert np.all(np.isnan(ds.vibe_m_s2.values))
    assert float(ds.displacement_m.sel(input="short", line=0, axis="y")) == pytest.approx(1e-3, rel=1e-3)


def test_lines_a_short_record_cannot_resolve_are_left_out_in_order():
    """A log's peaks at 10.0 and 10.6 Hz (found on the whole log) on a 2 s case: 2 / T = 1 Hz, so 10.6 goes; on a
    4 s record (0.5 Hz) both stay."""
    lines = {"peak x": 10.0, "peak y": 10.6, "peak z": 20.0}
    assert S.resolved(lines, 2.0) == {"peak x": 10.0, "peak z": 20.0}
    assert S.resolved(lines, 4.0) == lines
    t = np.arange(0, 2.0, DT)
    disp = np.stack([1e-3 * np.sin(2 * np.pi * 10 * t), 0 * t, 0 * t])
    ds = S.survey({"case": S.Record("case", "", DT, lines, disp)})
    assert list(ds.line_name.sel(input="case").values) == ["peak x", "peak z"]


def test_a_displacement_sines_levels_vibe_and_track_and_balance():
    """A 28.3 Hz lateral displacement sine of 0.01 mm sampled at 1 kHz: its line at (2 pi f)^2 d = 0.3162 m s-2 =
    0.03224 g (hand value); its VIBE the closed form of that acceleration within 1e-3 (the five-point derivative's
    gain error (2 pi f dt)^4 / 90 = 1.1e-5; the 2 Hz filter's ripple at 2f, about 2 / 2f = 3.5 % of the mean
    square, averages out over the 9 s kept); named 1/rev, its velocity 2 pi f d = 0.0700 in/s is 0.350 x the
    limit (named 4/rev: no ratio)."""
    dt, f, d = 1e-3, 28.3, 1e-5
    t = np.arange(0, 10.0, dt)
    x = np.stack([0 * t, d * np.sin(2 * np.pi * f * t), 0 * t])
    ds = S.survey({"a": S.Record("case", "", dt, {"4/rev": f}, x), "b": S.Record("case", "", dt, {"1/rev": f}, x)})
    assert float(ds.accel_g.sel(input="a", line=0, axis="y")) == pytest.approx(0.03224, abs=1e-5)
    want = _vibe_closed_form((2 * np.pi * f) ** 2 * d, f, dt)
    assert float(ds.vibe_m_s2.sel(input="a", axis="y")) == pytest.approx(want, rel=1e-3)
    assert np.isnan(float(ds.track_and_balance_ratio.sel(input="a")))
    assert float(ds.track_and_balance_ratio.sel(input="b")) == pytest.approx(0.35002, rel=1e-4)
