"""The closed-loop study: input cases, the comparison dataset, the rerun promise, the HTML report."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
import yaml
from conftest import (
    camera_of,
    deep_update,
    excitation_options,
    planar_cases,
    planned_rules,
    platform_from,
    quick_run_config,
    sine_yz,
    snakemake_dry,
    study_options_of,
)

from uavdamp import io
from uavdamp.config import checks
from uavdamp.contract import MountMotion
from uavdamp.damping import laws
from uavdamp.sources import excitation
from uavdamp.study import comparison as study
from uavdamp.study import metrics, strategies


def fake_run(duration=6.0, dt=0.005):
    t = np.arange(0, duration + dt / 2, dt)
    slow, fast = np.sin(2 * np.pi * 1.0 * t), 0.1 * np.sin(2 * np.pi * 7.0 * t)
    disp = np.stack([np.zeros_like(t), 2e-2 * slow + fast, 1e-2 * slow + fast])
    rotation = 1e-3 * np.stack([slow, slow, slow])  # rad: the slow wobble, gone after the high-pass
    return xr.Dataset(
        {"mount_displacement": (("mount", "axis", "time"), disp[None]), "mount_rotation": (("axis", "time"), rotation)},
        coords={"mount": ["cg"], "axis": ["x", "y", "z"], "time": t},
    )


def test_cases_high_pass_and_scale():
    peak = {"amplitude_reading": "peak", "amplitude_scaling": "per_axis"}
    cases = {
        "a": {
            "run": "imbalanced",
            "mount": "cg",
            "motion": "planar",
            "amplitude_m": 1.3e-3,
            **peak,
        },
        "b": {
            "run": "imbalanced",
            "mount": "cg",
            "motion": "planar",
            "amplitude_m": 0.5e-3,
            **peak,
        },
    }
    ds = excitation.cases_dataset(
        {"imbalanced": fake_run()}, excitation_options(cases, duration=5.0, highpass_hz=3.0, band_hz=(3, 12))
    )
    assert ds.mount_displacement.dims == ("case", "mount_axis", "time")
    assert float(ds.time[-1]) == pytest.approx(5.0)
    peaks = np.abs(ds.mount_displacement.sel(mount_axis=["y", "z"])).max("time")
    np.testing.assert_allclose(peaks.sel(case="a"), 1.3e-3, rtol=1e-12)
    np.testing.assert_allclose(peaks.sel(case="b"), 0.5e-3, rtol=1e-12)
    # the 1 Hz drift is gone: what is left is the 7 Hz vibration
    np.testing.assert_allclose(ds.dominant_freq, 7.0, rtol=0.01)
    y = ds.mount_displacement.sel(case="a", mount_axis="y").values
    t = ds.time.values
    fit = np.linalg.lstsq(
        np.column_stack([np.sin(2 * np.pi * t), np.cos(2 * np.pi * t), np.sin(14 * np.pi * t), np.cos(14 * np.pi * t)]),
        y,
        rcond=None,
    )[0]
    assert np.hypot(*fit[:2]) < 0.05 * np.hypot(*fit[2:])
    with pytest.raises(ValueError, match="study.cases.c.run"):
        excitation.cases_dataset(
            {"imbalanced": fake_run()},
            excitation_options(
                {
                    "c": {
                        "run": "nope",
                        "mount": "cg",
                        "motion": "planar",
                        "amplitude_m": 1e-3,
                        **peak,
                    }
                },
                duration=5.0,
                highpass_hz=3.0,
                band_hz=(3, 12),
            ),
        )


@pytest.fixture(scope="module")
def comparison(quick_run):
    return io.open_dataset(quick_run / "reports-quick/study/comparison.nc")


def test_comparison_layout(comparison, quick_config):
    ds = comparison
    assert ds.camera_displacement.dims == ("case", "stiffness", "strategy", "axis", "time")
    assert ds.damping.dims == ("case", "stiffness", "strategy", "time")
    assert ds.tracked_freq.dims == ("case", "axis", "update_time")
    for name in ("peak_early", "std_total"):
        assert ds[name].dims == ("case", "stiffness", "strategy", "axis") and ds[name].attrs["units"] == "m"
    assert list(ds.strategy.values) == quick_run_config()["study"]["strategies"]  # with the plug-in law
    assert list(ds.stiffness.values) == quick_config["study"]["stiffness_n_m"]
    assert ds.camera_yaw.dims == ds.camera_pitch.dims == ("case", "stiffness", "strategy", "time")
    assert np.all(np.isnan(ds.damping.sel(strategy="rigid")))
    assert np.all(np.isnan(ds.energy_dissipated.sel(strategy="rigid")))
    assert np.all(ds.energy_dissipated.sel(strategy=["passive", "anfis", "skyhook"]) > 0)
    # the metrics' values: closed forms in tests/test_mutants_metrics.py (not recomputed here with the same expressions)


def test_semi_active_damping_is_piecewise_constant_within_bounds(comparison, quick_config):
    iso = quick_config["platform"]["isolator"]
    period = iso["update_period_s"]
    time = comparison.time.values
    c = comparison.damping.sel(strategy="anfis").values  # (case, stiffness, time)
    assert np.all(np.isfinite(c))
    assert np.all((c >= iso["damping_min_n_s_m"]) & (c <= iso["damping_max_n_s_m"]))
    changes = np.flatnonzero(np.any(np.diff(c, axis=-1) != 0, axis=(0, 1))) + 1
    on_update = np.isclose(time[changes] / period, np.round(time[changes] / period), atol=1e-9)
    assert np.all(on_update), time[changes][~on_update]
    skyhook = comparison.damping.sel(strategy="skyhook").values
    assert set(np.unique(skyhook)) <= {iso["damping_min_n_s_m"], iso["damping_max_n_s_m"]}


def test_tracked_frequencies_of_case1_sit_at_the_rotor_frequency(comparison):
    """Case 1's lateral input is the 1/rev imbalance: 44.4 rad/s = 7.07 Hz (helicopter stage)."""
    y = comparison.tracked_freq.sel(case="case1", axis="y").values
    assert np.all(np.isnan(y[:1]) | (np.abs(y[:1] - 7.07) < 1.0))  # first update: may be too early
    assert np.nanmedian(y) == pytest.approx(44.4 / (2 * np.pi), rel=0.03)


def test_anfis_edit_reruns_only_the_two_anfis_and_the_stages_they_feed(quick_run, tmp_path):
    """The anfis section trains the study's ANFIS and the payload's: an edit reruns those, the study, the payload
    stage and the summary, not the grid or the tables."""
    config = yaml.safe_load((quick_run / "config" / "quick.yaml").read_text())
    config["anfis"]["epochs"] = config["anfis"]["epochs"] + 7
    edited = quick_run / "config" / "quick_anfis_edit.yaml"
    edited.write_text(yaml.safe_dump(config))
    edit = ("--configfile", str(edited.relative_to(quick_run)), "config/plugin.yaml")  # the run's plug-in kept
    result = snakemake_dry(quick_run, "-n", "-j1", "all", *edit)
    assert result.returncode == 0, result.stderr[-3000:]
    expected = {"anfis", "study", "payload_anfis", "payload", "summary", "all"}
    assert planned_rules(result) == expected, result.stdout[-3000:]


def test_a_new_strategy_and_metric_reach_the_output(quick_config, monkeypatch):
    """Adding a strategy or a metric is a function and its registration: the study output has them by name."""
    monkeypatch.setattr(strategies, "REGISTRY", dict(strategies.REGISTRY))
    monkeypatch.setattr(metrics, "REGISTRY", dict(metrics.REGISTRY))

    @strategies.register("stiff_damper")
    def stiff_damper(ctx):
        return strategies.Strategy(
            "stiff_damper",
            "isolated",
            laws.Constant(ctx.bounds.c_max),
            {"stiff_c": (ctx.bounds.c_max, "N s m-1", "the stiff damper's C")},
        )

    @metrics.register("mean_base_y")
    def mean_base_y(response, options):
        return metrics._named(float(response.base_displacement.sel(axis="y").mean()), "m", "mean base y")

    t, y, z = sine_yz(7.0, 8.0, 1e-3, 0.6, 0.004)
    cases = planar_cases("sine", t, y, z)
    cfg = {k: v for k, v in quick_config["study"].items() if k not in ("cases", "duration_s", "highpass_hz", "figures")}
    options = study_options_of({**cfg, "strategies": ["passive", "stiff_damper"], "stiffness_n_m": [50.0]})
    platform = {k: v for k, v in quick_config["platform"].items() if k not in ("response", "stroke")}
    ds = study.run_study(cases, platform_from(platform), None, options)
    assert list(ds.strategy.values) == ["passive", "stiff_damper"]
    c_max = quick_config["platform"]["isolator"]["damping_max_n_s_m"]
    assert np.all(ds.damping.sel(strategy="stiff_damper") == c_max)
    assert float(ds.stiff_c.sel(case="sine", stiffness=50.0)) == c_max
    # the new metric is the mean of the base's y displacement: compare with a separate run of the same plant
    from uavdamp.platform.plants import Plants

    plant = Plants(platform_from(platform)).for_run("isolated", laws.Constant(c_max))
    base = plant.run(t, MountMotion.planar(y, z), stiffness=50.0, law=laws.Constant(c_max)).base_displacement.sel(
        axis="y"
    )
    assert float(ds.mean_base_y.sel(case="sine", stiffness=50.0, strategy="stiff_damper")) == float(base.mean())
    assert ds.mean_base_y.attrs["units"] == "m"


def test_unknown_strategy_is_refused_naming_it(quick_config):
    """Before any job (`uavdamp.config.checks`, after the plug-ins load), and by the factory lookup in a job."""
    cfg = {k: v for k, v in quick_config["study"].items() if k not in ("cases", "duration_s", "highpass_hz", "figures")}
    with pytest.raises(ValueError, match=r"study.strategies: unknown strategy \['telepathy'\]"):
        checks.validate(deep_update(quick_config, {"study": {"strategies": ["passive", "telepathy"]}}))
    with pytest.raises(ValueError, match=r"unknown strategy 'telepathy'"):
        strategies.build("telepathy", None)
    with pytest.raises(ValueError, match="study.stiffness_n_m: values must be unique"):
        study_options_of({**cfg, "stiffness_n_m": [10.0, 10.0]})


def test_blur_recomputed_from_the_stored_line_of_sight_equals_the_stored_metric(comparison):
    """A user can recompute the image metrics from comparison.nc alone: its LOS series and camera attributes."""
    from uavdamp.camera.image_quality import image_metrics

    attrs = {k.removeprefix("camera_"): v for k, v in comparison.attrs.items() if k.startswith("camera_")}
    camera = camera_of(
        {k: (int(v) if k.endswith("_px") and k.startswith("image") else float(v)) for k, v in attrs.items()}
    )
    for case in comparison.case.values:
        run = comparison.sel(case=case, stiffness=comparison.stiffness[0], strategy="passive")
        again = image_metrics(
            run.time.values, run.camera_displacement.values, run.camera_yaw.values, run.camera_pitch.values, camera
        )
        for name in ("blur_p95", "sharp_fraction", "los_std", "mtf_nyquist_median"):
            assert again[name][0] == float(run[name]), (case, name)
        assert float(run.blur_max) == float(run.frame_blur.max())


def test_the_band_edge_warning_names_each_case_above_five_percent():
    """2 of 40 updates at the edge is 5 %: not above, no warning; 3 of 40 (7.5 %) is, and names its case and axis."""
    share = np.array([[2 / 40, 0.0], [3 / 40, 0.5]])
    text = study.band_edge_warning(share, ["case1", "case2"], ["y", "z"], "[3, 12] Hz")
    assert "case1" not in text and "case2 y: 8 %" in text and "case2 z: 50 %" in text and "[3, 12] Hz" in text
    assert study.band_edge_warning(share[:1], ["case1"], ["y", "z"], "[3, 12] Hz") == ""
