"""Input cases: amplitude readings and scalings against sums of sines of known amplitude."""

import numpy as np
import pytest
import xarray as xr
from conftest import excitation_options

from uavdamp.sources import excitation

DT, HIGHPASS_HZ, BAND_HZ = 0.005, 2.0, (3.0, 12.0)
# (freq Hz, amplitude m, phase rad): Y dominated by 7.07 Hz, Z by 7.99 Hz with lines 1 Hz apart (as case 1)
LINES = {
    "y": [(6.6, 0.4e-3, 0.2), (7.07, 14.2e-3, 1.0), (7.54, 0.4e-3, 2.0)],
    "z": [(6.07, 0.5e-3, 0.3), (7.07, 1.1e-3, 1.1), (7.99, 1.7e-3, 2.2)],
}


def _gain(freq_hz):
    """Closed-form gain of the zero-phase 4th-order Butterworth high-pass (applied forward and back): |H|^2."""
    return 1.0 / (1.0 + (HIGHPASS_HZ / freq_hz) ** 8)


def _dominant(axis):
    f, a, _ = max(LINES[axis], key=lambda line: line[1])
    return a * _gain(f)


def fake_run(duration=6.0):
    t = np.arange(0, duration + DT / 2, DT)
    drift = 2e-2 * np.sin(2 * np.pi * 1.0 * t)  # the free fuselage's slow wobble, removed by the high-pass
    disp = {axis: drift + sum(a * np.sin(2 * np.pi * f * t + p) for f, a, p in lines) for axis, lines in LINES.items()}
    rotation = 1e-3 * np.stack([np.sin(2 * np.pi * f * t) for f in (5.0, 6.0, 7.0)])  # rad, about x, y, z
    return xr.Dataset(
        {
            "mount_displacement": (("mount", "axis", "time"), np.stack([np.zeros_like(t), disp["y"], disp["z"]])[None]),
            "mount_rotation": (("axis", "time"), rotation),
        },
        coords={"mount": ["cg"], "axis": ["x", "y", "z"], "time": t},
    )


def cases(reading, scaling, amplitude=1.3e-3):
    case = {
        "run": "imbalanced",
        "mount": "cg",
        "motion": "planar",
        "amplitude_m": amplitude,
        "amplitude_reading": reading,
        "amplitude_scaling": scaling,
    }
    return excitation.cases_dataset(
        {"imbalanced": fake_run()},
        excitation_options({"a": case}, duration=5.0, highpass_hz=HIGHPASS_HZ, band_hz=BAND_HZ),
    ).sel(case="a")


@pytest.mark.parametrize(("freq_hz", "amplitude"), [(4.13, 1.7e-3), (7.07, 0.3e-3), (9.871, 2.0)])
def test_dominant_line_amplitude_of_an_off_bin_sine(freq_hz, amplitude):
    t = np.arange(0, 5.0, DT)
    x = amplitude * np.sin(2 * np.pi * freq_hz * t + 0.7) + 0.1 * amplitude * np.sin(2 * np.pi * 10.9 * t)
    assert excitation.dominant_line_amplitude(x, DT, 3.0, 10.0) == pytest.approx(amplitude, rel=2e-3)


def test_peak_per_axis_brings_each_peak_to_the_amplitude():
    ds = cases("peak", "per_axis")
    moved = ds.mount_displacement.sel(mount_axis=["y", "z"])
    np.testing.assert_allclose(np.abs(moved).max("time"), 1.3e-3, rtol=1e-12)


@pytest.mark.parametrize("axis", ["y", "z"])
def test_dominant_per_axis_brings_each_dominant_line_to_the_amplitude(axis):
    ds = cases("dominant", "per_axis")
    assert float(ds.scale.sel(axis=axis)) == pytest.approx(1.3e-3 / _dominant(axis), rel=5e-3)
    assert float(ds.dominant_amplitude.sel(axis=axis)) == pytest.approx(1.3e-3, rel=1e-9)


@pytest.mark.parametrize("reading", excitation.READINGS)
def test_common_scaling_keeps_the_helicopters_ratio(reading):
    ds = cases(reading, "common")
    assert float(ds.scale.sel(axis="y")) == float(ds.scale.sel(axis="z"))
    y, z = (ds.mount_displacement.sel(mount_axis=a).values for a in "yz")
    raw = {
        a: excitation.high_pass(fake_run().mount_displacement.sel(mount="cg", axis=a).values, DT, HIGHPASS_HZ)[: y.size]
        for a in "yz"
    }
    np.testing.assert_allclose(y / float(ds.scale.sel(axis="y")), raw["y"], rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(z / float(ds.scale.sel(axis="z")), raw["z"], rtol=1e-12, atol=1e-18)
    # the larger axis (Y here) carries the amplitude; Z keeps its own ratio to it
    if reading == "dominant":
        assert float(ds.scale.sel(axis="y")) == pytest.approx(1.3e-3 / _dominant("y"), rel=5e-3)
        assert float(ds.dominant_amplitude.sel(axis="z")) == pytest.approx(
            1.3e-3 * _dominant("z") / _dominant("y"), rel=1e-2
        )
    else:
        assert float(np.abs(ds.mount_displacement.sel(mount_axis="y")).max()) == pytest.approx(1.3e-3, rel=1e-12)


@pytest.mark.parametrize(
    ("key", "value"), [("amplitude_reading", "rms"), ("amplitude_scaling", "by_y"), ("amplitude_reading", None)]
)
def test_bad_reading_or_scaling_is_refused_naming_the_key(key, value):
    case = {
        "run": "imbalanced",
        "mount": "cg",
        "motion": "planar",
        "amplitude_m": 1e-3,
        "amplitude_reading": "peak",
        "amplitude_scaling": "per_axis",
    }
    case = {k: v for k, v in {**case, key: value}.items() if v is not None}
    with pytest.raises(ValueError, match=f"study.cases.a.{key}"):
        excitation.cases_dataset(
            {"imbalanced": fake_run()},
            excitation_options({"a": case}, duration=5.0, highpass_hz=HIGHPASS_HZ, band_hz=BAND_HZ),
        )
