"""A measured flight as a study case and a benchmark scenario: windows, edges, sampling, upsampling.

The logs here are CSVs of known sines written for each test and read by `uavdamp.read_flight_log` (what the
flight_log stage writes), so every expected value is a closed form: a displacement line A sin(2 pi f t) from the
acceleration -A (2 pi f)^2 sin(2 pi f t).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import deep_update, excitation_options, load_config
from test_flight_log import G, write_csv

from uavdamp.benchmark.scenarios import MeasuredScenario, ScenarioOptions, measured_input
from uavdamp.config import checks
from uavdamp.signals import inertial
from uavdamp.sources import excitation
from uavdamp.sources.flight_log import read_flight_log

FS, BAND = 200.0, (10.0, 60.0)
LINES = {"y": (23.0, 40e-6), "z": (41.0, 25e-6)}  # Hz, m: a line per axis (FLU), inside the band


def _log(tmp_path, start_s=100.0, duration_s=9.0):
    """A CSV log of the LINES as displacement (FRD on disk: y and z negated), from log time start_s."""
    t = start_s + np.arange(int(round(duration_s * FS)) + 1) / FS
    acc, gyro = np.zeros((3, t.size)), np.zeros((3, t.size))
    acc[2] = -G
    for row, axis in ((1, "y"), (2, "z")):
        f, a = LINES[axis]
        acc[row] += a * (2 * np.pi * f) ** 2 * np.sin(2 * np.pi * f * (t - start_s))  # FRD = -FLU: -(-A w^2 sin)
    return write_csv(tmp_path / "flight.csv", t, acc, gyro)


def _case(log: str = "flight", **keys) -> dict:
    """A flight-log case as the config writes it."""
    return {"flight_log": log, "amplitude_scaling": "measured", "motion": "full", **keys}


def _options(cases: dict, duration: float):
    return excitation_options(cases, duration=duration, highpass_hz=2.0, band_hz=(15.0, 50.0))


def test_a_log_case_is_the_measured_motion_inside_its_window(tmp_path):
    log = read_flight_log(_log(tmp_path), band_hz=BAND)
    ds = excitation.cases_dataset({}, _options({"a": _case(window_s=[102.0, 106.5])}, 4.0), {"flight": log})
    ds = ds.sel(case="a")
    t = ds.time.values
    assert t[0] == 0.0 and t[-1] == pytest.approx(4.0)
    for axis, (f, a) in LINES.items():
        expected = a * np.sin(2 * np.pi * f * (t + 2.0))  # the window starts 2 s into the log
        got = ds.mount_displacement.sel(mount_axis=axis).values
        assert np.abs(got - expected).max() < 0.005 * a  # the reader's in-band accuracy (0.5 %)
    assert float(ds.scale.sel(axis="y")) == 1.0 and float(ds.rotation_scale) == 1.0
    assert str(ds.source.values) == "flight log 'flight'" and np.isnan(ds.amplitude)


def test_a_log_case_window_inside_the_untrusted_edges_is_refused(tmp_path):
    log = read_flight_log(_log(tmp_path), band_hz=BAND)
    edge = inertial.edge_s(BAND)  # 0.3 s
    rule = rf"study.cases.a.window_s: \[100.1, 105.0\] s must lie within \[{100 + edge:.3f}"
    with pytest.raises(ValueError, match=rule):
        excitation.cases_dataset({}, _options({"a": _case(window_s=[100.1, 105.0])}, 4.0), {"flight": log})
    # no window: the whole trusted span
    ds = excitation.cases_dataset({}, _options({"a": _case()}, 8.0), {"flight": log})
    assert float(ds.time[-1]) == pytest.approx(8.0)


def test_cases_sampled_differently_share_the_finest_grid(tmp_path):
    """A log case at the log's rate beside the same log upsampled 4 times: the coarse case is brought onto the fine
    grid band-limited (`uavdamp.sources.excitation.on_common_grid`) and then agrees with the fine one away from the
    record's ends within 1 % of the line (both are band-limited interpolations of the same samples), its own rate
    recorded."""
    log = read_flight_log(_log(tmp_path), band_hz=BAND)
    fine = read_flight_log(_log(tmp_path), band_hz=BAND, upsample=4)
    options = _options({"a": _case(), "b": _case("fine")}, 4.0)
    ds = excitation.cases_dataset({}, options, {"flight": log, "fine": fine})
    assert float(ds.time[1] - ds.time[0]) == pytest.approx(1 / FS / 4)
    assert list(ds.sample_rate_hz.values) == pytest.approx([FS, 4 * FS])
    t = ds.time.values
    inside = (t > 0.5) & (t < t[-1] - 0.5)
    a, b = (ds.mount_displacement.sel(case=c, mount_axis="z").values[inside] for c in ("a", "b"))
    assert np.abs(a - b).max() < 0.01 * LINES["z"][1]


def test_upsampling_is_band_limited_interpolation(tmp_path):
    """Every 4th fine sample is the log-rate one, and between them the fine samples are the sines themselves: a
    linear interpolation of the log-rate samples would lose 1 - sinc^2(41 / 200) = 13 % of the 41 Hz line."""
    coarse = read_flight_log(_log(tmp_path), band_hz=BAND)
    fine = read_flight_log(_log(tmp_path), band_hz=BAND, upsample=4)
    assert fine.attrs["time_step_s"] == pytest.approx(1 / FS / 4) and fine.attrs["sample_rate_hz"] == pytest.approx(FS)
    a, b = coarse.mount_displacement.values, fine.mount_displacement.values
    np.testing.assert_allclose(b[:, ::4], a, rtol=0, atol=1e-9 * np.abs(a).max())
    t = fine.time.values
    inside = (t > 1.0) & (t < t[-1] - 1.0)
    f, amp = LINES["z"]
    error = np.abs(b[2, inside] - amp * np.sin(2 * np.pi * f * t[inside])).max()
    assert error < 0.005 * amp
    linear = np.interp(t, coarse.time.values, a[2])
    assert np.abs(linear[inside] - amp * np.sin(2 * np.pi * f * t[inside])).max() > 0.05 * amp  # the check can fail


def test_a_measured_scenario_is_its_window_as_measured(tmp_path):
    log = read_flight_log(_log(tmp_path), band_hz=BAND)
    entry = MeasuredScenario(name="hop", flight_log="flight", window_s=(103.0, 108.0))
    options = ScenarioOptions(
        duration_s=4.0, amplitude_m=1e-3, highpass_hz=2.0, band_hz=(15.0, 50.0), helicopter=None, synthetic=()
    )
    t, motion = measured_input(entry, log, options)
    f, a = LINES["y"]
    assert np.abs(motion.y - a * np.sin(2 * np.pi * f * (t + 3.0))).max() < 0.005 * a


# A log case beside the default (helicopter) cases, checked before any job: the window against the log's span read
# from its timestamps, the band against the study's tracker. The CSV log's grid runs from 100 s to 109 s at 200 Hz.
LOW_BAND = [4.0, 12.0]  # across the default tracker band (3-12 Hz); edge_s = 3 / 4 = 0.75 s


def _beside_default(tmp_path, case_keys: dict, band=LOW_BAND, scenario=None) -> dict:
    override = {
        "flight_logs": {"mine": {"path": str(_log(tmp_path)), "band_hz": band, "on_ground": "record"}},
        "study": {"duration_s": 5.0, "cases": {"log": {**_case("mine"), **case_keys}}},
    }
    if scenario is not None:
        override["benchmark"] = {"flight_logs": [{"name": "hop", "flight_log": "mine", "window_s": scenario}]}
    return deep_update(load_config(), override)


@pytest.mark.parametrize(
    ("keys", "scenario", "message"),
    [
        (  # 100.5 s lies in the first edge_s of the 100-109 s span
            {"window_s": [100.5, 106.0]},
            None,
            r"study.cases.log.window_s: \[100.5, 106\] s must lie within \[100.750, 108.250\] s: the log's span "
            r"\[100.000, 109.000\] s",
        ),
        (  # 4 s of samples for a 5 s study
            {"window_s": [101.0, 105.0]},
            None,
            r"study.cases.log.window_s: \[101, 105\] s holds 4.000 s of the log's samples, shorter than "
            r"study.duration_s = 5 s",
        ),
        (
            {"window_s": [101.0, 106.0]},
            [100.2, 104.0],
            r"benchmark.flight_logs.hop.window_s: \[100.2, 104\] s must lie within \[100.750, 108.250\] s",
        ),
    ],
)
def test_a_log_case_window_is_placed_in_its_log_before_any_job(tmp_path, keys, scenario, message):
    with pytest.raises(ValueError, match=message):
        checks.validate(_beside_default(tmp_path, keys, scenario=scenario))


def test_a_log_case_that_fits_its_log_passes_beside_the_default_cases(tmp_path):
    """Exactly 5 s of samples (101-106 s at 200 Hz) for a 5 s study: accepted."""
    config, _ = checks.validate(_beside_default(tmp_path, {"window_s": [101.0, 106.0]}))
    assert sorted(config.study.cases) == ["case1", "case2", "case3", "log"]


def test_a_log_band_that_misses_the_tracker_is_refused_with_the_fix(tmp_path):
    with pytest.raises(ValueError) as error:
        checks.validate(_beside_default(tmp_path, {"window_s": [101.0, 106.0]}, band=[20.0, 47.0]))
    text = str(error.value)
    assert text.startswith("study.cases.log.flight_log: the log 'mine' is integrated in flight_logs.mine.band_hz")
    assert "[20, 47] Hz, which does not meet the tracker's band study.tracking.min_freq_hz/max_freq_hz [3, 12]" in text
    assert "config/multirotor.yaml" in text  # the fix


def test_a_log_the_band_cannot_use_is_refused_naming_its_entry(tmp_path):
    """A 150 Hz band top on a 200 Hz log (Nyquist 100 Hz): the reader's refusal, before any job, under the entry."""
    with pytest.raises(ValueError, match=r"^flight_logs.mine: .*flight.csv"):
        checks.validate(_beside_default(tmp_path, {"window_s": [101.0, 106.0]}, band=[4.0, 150.0]))
