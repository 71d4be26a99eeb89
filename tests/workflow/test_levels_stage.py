"""The levels stage on the session's quick run: what it reads from the study's cases and stated sources agrees
with independent readings of the same inputs (the cases' own amplitude reading, the sources' stated levels)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import quick_run_config

from uavdamp import io

INCH = 0.0254  # m per inch


def test_a_cases_lateral_1_rev_is_its_dominant_line(quick_run):
    """Case 1's lateral 1/rev velocity equals its dominant y line as the excitation stage read it (a Hann spectrum,
    `cases.nc`): 2 pi f A / 0.0254 in/s, within 2 % (two estimators of one line)."""
    out = quick_run / "reports-quick"
    levels, cases = io.open_dataset(out / "levels/levels.nc"), io.open_dataset(out / "excitation/cases.nc")
    one = levels.sel(input="case case1")
    k = list(one.line_name.values).index("1/rev")
    f, a = (float(cases[v].sel(case="case1", axis="y")) for v in ("dominant_freq", "dominant_amplitude"))
    assert float(one.velocity_in_s.sel(line=k, axis="y")) == pytest.approx(2 * math.pi * f * a / INCH, rel=0.02)
    assert float(one.track_and_balance_ratio) == pytest.approx(2 * math.pi * f * a / INCH / 0.2, rel=0.02)


def test_a_stated_source_reads_back_its_stated_levels(quick_run):
    """The sine-on-random source's N/rev lines read back at their stated g within four standard deviations of a
    line amplitude in its random floor (sqrt(1.5 S / T): S the floor's one-sided PSD, T the record, 1.5 the Hann
    weights' noise bandwidth); the multirotor source's VIBE at its stated level within 3 % (the second derivative's
    gain at 100 Hz sampled at 1 kHz is 1.7 % low)."""
    config = quick_run_config()
    levels = io.open_dataset(quick_run / "reports-quick/levels/levels.nc")
    heli = config["sources"]["heli_sine_on_random"]
    floor = max(heli["levels"]["floor_g2_hz"])
    sigma = math.sqrt(1.5 * floor / config["levels"]["source_duration_s"])
    one = levels.sel(input="source heli_sine_on_random")
    names = list(one.line_name.values)
    for name, key in (("4/rev", "n_per_rev_g"), ("8/rev", "two_n_per_rev_g")):
        read = one.accel_g.sel(line=names.index(name)).values
        assert read == pytest.approx(heli["levels"][key], abs=4 * sigma), name
    rotor = config["sources"]["multirotor_30"]
    vibe = float(levels.vibe_m_s2.sel(input="source multirotor_30").max())
    assert vibe == pytest.approx(rotor["vibe_m_s2"], rel=0.03)


def test_a_logs_lines_lie_in_its_band(quick_run):
    levels = io.open_dataset(quick_run / "reports-quick/levels/levels.nc")
    for name, spec in quick_run_config()["flight_logs"].items():
        freq = levels.freq_hz.sel(input=f"log {name}").values
        freq = freq[np.isfinite(freq)]
        assert freq.size >= 1 and np.all((freq >= spec["band_hz"][0]) & (freq <= spec["band_hz"][1]))
    assert (quick_run / "reports-quick/figures/levels.png").stat().st_size > 20_000
