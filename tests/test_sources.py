"""One vibration-source system: a stated source (``sources.NAME``) is used by a study case and a benchmark scenario
through the config alone, with one generator; cases sampled at different rates share one grid.

The worked example of docs/architecture.md ("Adding a vibration source") is `test_one_source_serves_the_study_and_
the_benchmark`."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from conftest import deep_update, excitation_options, load_config

from uavdamp.benchmark import scenarios
from uavdamp.config import checks
from uavdamp.config.load import load
from uavdamp.settings import ConfigError, parse, view
from uavdamp.sources import excitation, stated

SWEEP = {"kind": "sweep", "amplitude_m": 1.0e-3, "freq_hz": [4.0, 10.0], "sample_rate_hz": 500.0}


AS_STATED = {"amplitude_scaling": "measured", "amplitude_m": None, "amplitude_reading": None}


def _source(spec: dict, name: str = "src") -> stated.StatedSource:
    return parse(stated.StatedSource, spec, f"sources.{name}")


def _sine_run(freq_hz: float, amplitude: float, rate_hz: float, duration: float) -> xr.Dataset:
    """A helicopter run's layout (mount, axis, time) with the same sine on y and z at one mount."""
    t = np.arange(int(duration * rate_hz) + 1) / rate_hz
    s = amplitude * np.sin(2 * np.pi * freq_hz * t)
    moved = np.stack([np.zeros_like(s), s, s])[None]
    return xr.Dataset(
        {
            "mount_displacement": (("mount", "axis", "time"), moved),
            "mount_rotation": (("mount", "axis", "time"), np.zeros_like(moved)),
        },
        coords={"mount": ["at_cg"], "axis": ["x", "y", "z"], "time": t},
    )


def test_one_source_serves_the_study_and_the_benchmark():
    """The same ``sources.sweep`` entry as a study case (`source: sweep`, as stated) and as a benchmark scenario
    (``benchmark.sources: [sweep]``) gives the same mount motion sample for sample, and it is the closed-form
    chirp: y = A sin(2 pi (f0 t + (f1 - f0) t^2 / (2 T)) - pi/2 ... at t = 0 the sweep starts at -A (phase -90)."""
    source = _source(SWEEP, "sweep")
    options = excitation_options(
        {"sweep": {"source": "sweep", "amplitude_scaling": "measured", "motion": "full"}},
        duration=2.0,
        highpass_hz=1.0,
        band_hz=(3.0, 12.0),
    )
    case = excitation.cases_dataset({}, options, stated={"sweep": stated.generate(source, "sweep", 2.0)})
    bench = deep_update(load_config("quick.yaml")["benchmark"], {"sources": ["swept"], "duration_s": 2.0})
    scenario_options = parse(scenarios.ScenarioOptions, view(bench, scenarios.ScenarioOptions), "benchmark")
    scenario = scenarios.scenario_input("swept", scenario_options, None, 0.002, source=source)
    n = case.time.size
    np.testing.assert_array_equal(
        case.mount_displacement.sel(case="sweep").values, scenario.mount_displacement.values[:, :n]
    )
    t = case.time.values
    phase = 2 * np.pi * (4.0 * t + (10.0 - 4.0) * t**2 / (2 * 2.0)) - np.pi / 2
    np.testing.assert_allclose(
        case.mount_displacement.sel(case="sweep", mount_axis="y"), 1e-3 * np.cos(phase), atol=1e-12
    )
    assert float(case.sample_rate_hz.sel(case="sweep")) == pytest.approx(500.0)


def test_the_benchmark_synthetic_kinds_are_the_stated_generators():
    """A ``benchmark.synthetic`` entry and a stated source of the same kind and keys give the same input: one
    generator for both experiments."""
    spec = {"kind": "random", "band_hz": [4.0, 12.0], "seed": 7}
    t, y, z = scenarios.synthetic_input(spec, duration=1.0, amplitude=2e-3, time_step=0.002)
    source = _source(
        {"kind": "random", "band_hz": [4.0, 12.0], "seed": 7, "amplitude_m": 2e-3, "sample_rate_hz": 500.0}
    )
    _, moved, _ = stated.motion(source, 1.0)
    np.testing.assert_array_equal(moved.y, y)
    np.testing.assert_array_equal(moved.z, z)
    assert np.std(y) == pytest.approx(2e-3 / np.sqrt(2), rel=1e-12)  # scaled to a sine's RMS


def test_cases_at_different_rates_share_the_finest_grid_band_limited():
    """A 200 Hz helicopter case beside a 1 kHz stated source: the helicopter case is resampled onto 1 kHz by a
    band-limited filter, keeping its 7 Hz line's amplitude (1.3 mm) within 0.2 % away from the record's ends (the
    bound of the passband ripple of resample_poly's Kaiser-window filter, beta 5: about 10^(-54 dB / 20)), and the
    1 kHz case is unchanged."""
    run = _sine_run(7.0, 1.3e-3, 200.0, 3.0)
    source = _source({**SWEEP, "sample_rate_hz": 1000.0})
    options = excitation_options(
        {
            "heli": {"run": "imbalanced", "mount": "at_cg", "amplitude_scaling": "measured", "motion": "planar"},
            "sweep": {"source": "sweep", "amplitude_scaling": "measured", "motion": "planar"},
        },
        duration=2.0,
        highpass_hz=1.0,
        band_hz=(3.0, 12.0),
    )
    ds = excitation.cases_dataset({"imbalanced": run}, options, stated={"sweep": stated.generate(source, "sweep", 2.0)})
    assert np.allclose(np.diff(ds.time.values), 1e-3)
    assert list(ds.sample_rate_hz.values) == pytest.approx([200.0, 1000.0])
    inner = (ds.time > 0.5) & (ds.time < 1.5)
    y = ds.mount_displacement.sel(case="heli", mount_axis="y").where(inner, drop=True)
    t = y.time.values
    fit = np.linalg.lstsq(np.stack([np.sin(2 * np.pi * 7 * t), np.cos(2 * np.pi * 7 * t)], 1), y.values, rcond=None)
    assert np.hypot(*fit[0]) == pytest.approx(1.3e-3, rel=2e-3)
    _, sweep, _ = stated.motion(source, 2.0)
    n = ds.time.size
    np.testing.assert_array_equal(ds.mount_displacement.sel(case="sweep").values, sweep.translation[:, :n])


def _seven_hz_fit(ds: xr.Dataset) -> np.ndarray:
    """(sin, cos) coefficients, m, of the heli case's 7 Hz line over 0.5-1.5 s."""
    y = ds.mount_displacement.sel(case="heli", mount_axis="y").where((ds.time > 0.5) & (ds.time < 1.5), drop=True)
    t = y.time.values
    basis = np.stack([np.sin(2 * np.pi * 7 * t), np.cos(2 * np.pi * 7 * t)], 1)
    return np.linalg.lstsq(basis, y.values, rcond=None)[0]


def test_a_rate_with_no_small_integer_ratio_is_brought_onto_the_grid_in_phase():
    """A 200 Hz helicopter case beside a 333.3 Hz stated source (ratio 1.6665 = 3333/2000, no ratio of small
    integers): the helicopter case lands on the 333.3 Hz grid with its 7 Hz line's sine and cosine parts as on its
    own 200 Hz grid within 0.2 % of the line (the resampler's passband ripple, previous test). The nearest ratio of
    denominator up to 64, 5/3, would put every sample 1e-4 of a step late per step: 0.15 ms at 1.5 s, a 0.66 % swing
    of the line into its cosine part. The timing error is recorded, below 1e-4 of the case's Nyquist period."""
    run = _sine_run(7.0, 1e-3, 200.0, 3.0)
    source = _source({**SWEEP, "sample_rate_hz": 333.3})
    heli = {"run": "imbalanced", "mount": "at_cg", "amplitude_scaling": "measured", "motion": "planar"}
    both = {"heli": heli, "odd": {"source": "sweep", "amplitude_scaling": "measured", "motion": "planar"}}
    common = {"duration": 2.0, "highpass_hz": 1.0, "band_hz": (3.0, 12.0)}
    sweep = {"sweep": stated.generate(source, "sweep", 2.0)}
    ds = excitation.cases_dataset({"imbalanced": run}, excitation_options(both, **common), stated=sweep)
    alone = excitation.cases_dataset({"imbalanced": run}, excitation_options({"heli": heli}, **common))
    assert float(ds.time[1]) == pytest.approx(1 / 333.3, rel=1e-12)
    np.testing.assert_allclose(_seven_hz_fit(ds), _seven_hz_fit(alone), rtol=0, atol=2e-3 * 1e-3)
    error = float(ds.grid_timing_error_s.sel(case="heli"))
    assert 0 <= error <= 1e-4 * 2 / 200.0 and float(ds.grid_timing_error_s.sel(case="odd")) == 0.0


def test_the_grid_ratio_keeps_the_drift_within_its_bound():
    """A log's median rate (1 / 5.0100 ms = 199.60 Hz) onto 1 kHz over 10 s: the ratio found keeps the gathered
    timing error within 1e-4 of the 10 ms Nyquist period; a rate no ratio of denominator up to 2^16 reaches is
    refused."""
    step, finest, span = 5.0100e-3, 1e-3, 10.0
    ratio = excitation.grid_ratio(step, finest, span)
    assert abs(step / float(ratio) - finest) * span / finest <= 1e-4 * 2 * step
    assert ratio.denominator > 64  # 5.01 = 501/100: beyond the former bound of 64
    with pytest.raises(ValueError, match="no ratio of denominator up to 65536"):
        excitation.grid_ratio(np.pi * 1e-3, 1e-3, 1e9)


@pytest.mark.parametrize(
    ("override", "message"),
    [
        (
            {"study": {"cases": {"case1": {"run": None, "mount": None, "source": "nowhere", **AS_STATED}}}},
            "study.cases.case1.source: .nowhere. is not a name of the sources",
        ),
        ({"benchmark": {"sources": ["nowhere"]}}, r"benchmark.sources\[0\]: 'nowhere' is not a name of the sources"),
        (
            {"study": {"cases": {"case1": {"run": None, "mount": None, "source": "multirotor_30"}}}},
            "amplitude_scaling: must be measured or common for a stated source",
        ),
        ({"sources": {"multirotor_30": {"freq_hz": [1.0, 2.0]}}}, "sources.multirotor_30.freq_hz: kind 'multirotor'"),
        (
            {"study": {"cases": {"case3": {"amplitude_scaling": "per_axis"}}}},
            r"study.cases.case3.amplitude_scaling: per_axis would change the ratios between the axes of the helicopter",
        ),
    ],
    ids=[
        "unknown-case-source",
        "unknown-benchmark-source",
        "per-axis-scaling",
        "key-of-another-kind",
        "per-axis-hover",
    ],
)
def test_a_bad_source_use_is_refused_before_any_job(override, message):
    """Refused by the config check (before any job) naming the key: an unknown source, a scaling that would change
    the source's ratios between axes (a stated source; the trimmed hover, whose per-axis scaling multiplied its
    vertical line by about 4), a key the source's kind does not take."""
    with pytest.raises((ConfigError, ValueError), match=message):
        checks.validate(deep_update(load_config("quick.yaml"), override))


def test_the_shipped_sources_generate_at_their_stated_levels():
    """The default config's sources reach the generators with their stated levels: the multirotor's largest-axis
    VIBE is 30 m s-2 (`uavdamp.sources.levels.vibe` of the generated acceleration, scaled to it), the helicopter
    profile's line table holds the config's 0.2 in/s lateral 1/rev and 0.15 g vertical 4/rev at 1/rev = 7.0665 Hz
    and 4/rev = 28.266 Hz (the signal against its line table: tests/test_profiles.py)."""
    config = load(load_config())
    heli = stated.generate(config.sources["heli_sine_on_random"], "heli", 2.0)
    multi = stated.generate(config.sources["multirotor_30"], "multi", 2.0)
    assert multi.attrs["stated_vibe_m_s2"] == 30.0
    assert float(multi.vibe_m_s2.max()) == pytest.approx(30.0, rel=1e-9)
    assert float(heli.velocity_in_s.sel(line="1/rev", axis="y")) == pytest.approx(0.2, rel=1e-12)
    assert float(heli.accel_g.sel(line="4/rev", axis="z")) == pytest.approx(0.15, rel=1e-12)
    assert list(heli.freq_hz.sel(line=["1/rev", "4/rev"]).values) == pytest.approx([7.0665, 4 * 7.0665])


def test_a_stated_sources_lines_are_its_stated_frequencies():
    """By hand: a 7 Hz four-blade rotor with a 35 Hz two-blade tail puts lines at 7, 28, 56, 84 (1, N, 2N, 3N/rev)
    and 35, 70 Hz; four 3000 rpm two-blade motors spread +-5 % at 100 (1 + 0.05 u) Hz, u = -1, -1/3, 1/3, 1, and
    twice that; a sweep its two ends; tones each tone."""
    heli = stated.StatedSource(
        kind="sine_on_random", rotor_hz=7.0, blades=4, tail_rotor_hz=35.0, tail_blades=2, seed=1, highpass_hz=2.0
    )
    np.testing.assert_allclose(heli.lines_hz(), [7, 28, 35, 56, 70, 84], rtol=1e-12)
    multi = stated.StatedSource(kind="multirotor", motor_rpm=3000.0, blades=2, motors=4, spread=0.05)
    one = 100 * (1 + 0.05 * np.array([-1, -1 / 3, 1 / 3, 1]))
    np.testing.assert_allclose(multi.lines_hz(), np.sort(np.r_[one, 2 * one]), rtol=1e-12)
    sweep = stated.StatedSource(kind="sweep", freq_hz=(4.0, 10.0), amplitude_m=1e-3)
    tones = stated.StatedSource(kind="tones", freq_y_hz=(8.0,), freq_z_hz=(5.0, 6.0), amplitude_m=1e-3)
    assert list(sweep.lines_hz()) == [4.0, 10.0] and list(tones.lines_hz()) == [5.0, 6.0, 8.0]
