"""The controller benchmark on the payload: tuning on the tuning set, the controllers picked from the runs, J and its
evaluation mean and worst against hand sums; the section; a still scenario through the real plants."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from conftest import load_config, platform_from

from uavdamp.benchmark import payload as bench
from uavdamp.config import checks
from uavdamp.config.load import load
from uavdamp.contract import MountMotion
from uavdamp.settings import ConfigError, parse
from uavdamp.study.payload import PayloadSection
from uavdamp.study.payload_runs import METRICS

DAMPING = (1.0, 3.0, 10.0)


def checks_of_the_benchmark_on_the_payload(config: dict) -> None:
    """The config checks of the benchmark on the payload on a typed config (`uavdamp.config.checks`; that
    `check_config` calls it: tests/test_config.py's refusals run the whole check)."""
    checks._check_benchmark_payload(load(config))


LAWS = ("skyhook_3", "skyhook_10", "scheduled")


def fake_run(name: str, rigid: float, constants, laws) -> xr.Dataset:
    """A payload run of one scenario as `compare_inputs` writes it, the gimbal on rigid and six_axis: los_std
    `rigid` on the rigid mount, `constants` (per C of DAMPING) and `laws` (per law of LAWS) on six_axis; every other
    metric is 2 x los_std + 1 (so that a pick from the wrong run shows)."""
    los = np.array([[np.full(len(DAMPING), rigid), constants]], dtype=float)[None]  # (input, payload, mount, damping)
    law = np.array([[np.full(len(LAWS), np.nan), laws]], dtype=float)  # (input, mount, law)
    data = {}
    for metric in METRICS:
        scale = (1.0, 0.0) if metric == "los_std" else (2.0, 1.0)
        data[metric] = (("input", "payload", "mount", "damping"), scale[0] * los + scale[1])
        data[f"law_{metric}"] = (("input", "mount", "law"), scale[0] * law + scale[1])
    data["floor_los_std"] = (("payload",), [5.0], {"units": "rad", "long_name": "floor"})
    data["input_description"] = (("input",), [f"scenario {name}"], {"units": "1", "long_name": "the input"})
    coords = {
        "input": [name],
        "payload": ["gimbal"],
        "mount": ["rigid", "six_axis"],
        "damping": list(DAMPING),
        "law": list(LAWS),
    }
    return xr.Dataset(data, coords=coords, attrs={"duration_s": 10.0, "settle_s": 1.0, "coupling": "one-way"})


# rigid, constants at C = 1, 3, 10, laws skyhook_3, skyhook_10, scheduled; A and B tune, C and D evaluate
RUNS = {
    "A": (100.0, [50.0, 80.0, 90.0], [60.0, 70.0, 100.0]),
    "B": (200.0, [300.0, 100.0, 180.0], [200.0, 100.0, 100.0]),
    "C": (100.0, [40.0, 120.0, 60.0], [50.0, 90.0, 30.0]),
    "D": (50.0, [10.0, 60.0, 25.0], [5.0, 40.0, 50.0]),
}
SPLIT = {"A": "tuning", "B": "tuning", "C": "evaluation", "D": "evaluation"}


@pytest.fixture  # per test: mutmut maps a mutated function to the tests that call it, fixtures' setup included
def gathered() -> xr.Dataset:
    return bench.gather([fake_run(n, *v) for n, v in RUNS.items()], SPLIT, "los_std")


def test_tuning_picks_the_least_tuning_mean_j(gathered):
    """Tuning-set mean J of the constants: (0.5 + 1.5) / 2, (0.8 + 0.5) / 2, (0.9 + 0.9) / 2 = 1, 0.65, 0.9: C = 3;
    of skyhook: (0.6 + 1) / 2, (0.7 + 0.5) / 2 = 0.8, 0.6: c_on = 10. The evaluation set does not vote (on C and D
    C = 1 is best)."""
    assert float(gathered.tuned_damping.sel(mount="six_axis")) == 3.0
    assert float(gathered.tuned_c_on.sel(mount="six_axis")) == 10.0


def test_controllers_and_j_against_hand_sums(gathered):
    """Evaluation J on C and D (rigid 100, 50): passive_tuned 120/100, 60/50; the oracle 40/100, 10/50; skyhook at
    10: 90/100, 40/50; scheduled 30/100, 50/50; rigid 1."""
    expected = {
        "rigid": (1.0, 1.0),
        "passive_tuned": (1.2, 1.2),
        "passive_oracle": (0.4, 0.2),
        "skyhook_tuned": (0.9, 0.8),
        "scheduled": (0.3, 1.0),
    }
    assert list(gathered.controller.values) == list(expected)
    j = gathered.J.sel(mount="six_axis")
    for name, (c, d) in expected.items():
        assert j.sel(controller=name, scenario=["C", "D"]).values == pytest.approx([c, d], rel=1e-12), name
        assert float(gathered.J_mean.sel(mount="six_axis", controller=name)) == pytest.approx((c + d) / 2, rel=1e-12)
        assert float(gathered.J_worst.sel(mount="six_axis", controller=name)) == pytest.approx(max(c, d), rel=1e-12)
    # the tuning set's own mean: the oracle's 0.5 and 0.5 on A and B
    assert float(gathered.J_tuning_mean.sel(mount="six_axis", controller="passive_oracle")) == pytest.approx(0.5)
    assert float(gathered.los_std_mean.sel(mount="six_axis", controller="scheduled")) == pytest.approx(40.0)


def test_every_metric_comes_from_the_controllers_own_run(gathered):
    """The other metrics (2 los + 1 in `fake_run`) follow the run each controller picked: passive_tuned's on D is
    the C = 3 run's, 2 x 60 + 1; the oracle's on C the C = 1 run's, 2 x 40 + 1."""
    on = gathered.sel(mount="six_axis")
    assert float(on.mtf_nyquist.sel(controller="passive_tuned", scenario="D")) == 121.0
    assert float(on.los_peak_to_peak.sel(controller="passive_oracle", scenario="C")) == 81.0
    assert float(on.drift_frame_to_frame.sel(controller="skyhook_tuned", scenario="A")) == 141.0
    assert gathered.los_std.attrs["units"] == "rad" and gathered.J.attrs["units"] == "1"
    assert float(gathered.floor_los_std) == 5.0


def test_a_tie_goes_to_the_lesser_damping():
    runs = [
        fake_run("A", 100.0, [80.0, 80.0, 90.0], [70.0, 70.0, 1.0]),
        fake_run("C", 100.0, [1.0, 2.0, 3.0], [1, 2, 3]),
    ]
    ds = bench.gather(runs, {"A": "tuning", "C": "evaluation"}, "los_std")
    assert float(ds.tuned_damping.sel(mount="six_axis")) == 1.0
    assert float(ds.tuned_c_on.sel(mount="six_axis")) == 3.0


def test_a_scenario_outside_the_split_is_refused():
    with pytest.raises(ValueError, match=r"benchmark.payload: scenarios \['E'\] are in no set of the split"):
        bench.gather([fake_run("E", *RUNS["A"])], SPLIT, "los_std")


def test_the_section_is_checked_by_key():
    with pytest.raises(ConfigError, match=r"benchmark.payload.mounts: must be distinct names of"):
        parse(bench.PayloadBenchmark, {"mounts": ["yz"]}, "benchmark.payload")
    with pytest.raises(ConfigError, match=r"benchmark.payload.criterion: must be one of"):
        parse(bench.PayloadBenchmark, {"criterion": "mtf_nyquist"}, "benchmark.payload")  # higher is better


def test_scenarios_no_longer_than_the_settling_are_refused_before_any_job():
    config = load_config("config.yaml")
    config["benchmark"]["duration_s"] = config["payload"]["settle_s"]
    with pytest.raises(ConfigError, match=r"benchmark.duration_s: \(1.0 s\) must exceed payload.settle_s"):
        checks_of_the_benchmark_on_the_payload(config)


def test_a_still_scenario_leaves_every_law_at_the_gimbals_floor():
    """A mount that does not move: the isolator stays at rest whatever its damping or law, so every run of the
    benchmark's section (rigid, each C, skyhook, the MR damper) sees only the gimbal's IMU noise, the same draw in
    every run: the floor, which `compare_inputs` computes on its own still rigid mount."""
    config = load_config("quick.yaml")
    platform = platform_from(config["platform"])
    section = parse(PayloadSection, config["payload"], "payload").with_camera(platform.structure)
    section = bench.benchmark_section(section, bench.PayloadBenchmark(), 1.0)
    assert section.payloads == ("gimbal",) and section.mounts == ("rigid", "six_axis") and section.sources == ()
    t = np.arange(0.0, 1.0 + 1e-9, 2e-3)
    still = MountMotion(np.zeros((3, t.size)), np.zeros((3, t.size)))
    from uavdamp.camera.optics import CameraModel

    camera = parse(CameraModel, config["camera"], "camera")
    ds = bench.run_scenario("still", "a still mount", t, still, section, platform, camera, None, None)
    assert list(ds.input.values) == ["still"] and list(ds.input_description.values) == ["a still mount"]
    floor = float(ds.floor_los_std.sel(payload="gimbal"))
    assert floor > 0
    assert ds.los_std.values == pytest.approx(floor, rel=1e-9)
    assert list(ds.law.values) == ["skyhook_30", "mr_off", "mr_on", "mr_skyhook"]  # quick: C 3 and 30; no table
    assert ds.law_los_std.sel(mount="six_axis").values == pytest.approx(floor, rel=1e-9)
    assert math.isnan(float(ds.law_los_std.sel(mount="rigid").max()))


def test_the_quick_runs_benchmark_on_the_payload(quick_run):
    """What the quick run's gather wrote against what its run jobs wrote, recomputed here with numpy alone: the
    scenarios and their split, the tuned constant C (the least tuning-set mean of los_std over the rigid mount's),
    J of passive_tuned and of the scheduled law per scenario; the results page with the benchmark carries its
    table and finding."""
    from uavdamp import io
    from uavdamp.benchmark import scenarios

    out = quick_run / "reports-quick"
    ds = io.open_dataset(out / "benchmark/payload/criteria.nc")
    runs = {p.stem: io.open_dataset(p) for p in (out / "benchmark/payload/runs").glob("*.nc")}
    typed = load(load_config("quick.yaml")).benchmark
    fraction, seed = typed.split.tuning_fraction, typed.split.seed
    split = bench.split(
        scenarios.split(scenarios.scenario_specs(typed), fraction, seed), typed.payload.sources, fraction, seed
    )
    assert typed.payload.sources and set(typed.payload.sources) < set(split)  # quick: multirotor_30 besides
    assert sorted(runs) == sorted(split) == sorted(ds.scenario.values)
    assert [split[str(s)] for s in ds.scenario.values] == list(ds.set.values)
    names = [str(s) for s in ds.scenario.values]
    mounts = [str(m) for m in runs[names[0]].mount.values]
    rigid = np.array([runs[n].los_std.values[0, 0, mounts.index("rigid"), 0] for n in names])
    const = np.array([runs[n].los_std.values[0, 0, mounts.index("six_axis"), :] for n in names])
    j = const / rigid[:, None]
    tuning = np.array([split[n] == "tuning" for n in names])
    best = int(np.argmin(j[tuning].mean(axis=0)))
    damping = runs[names[0]].damping.values
    assert float(ds.tuned_damping.sel(mount="six_axis")) == damping[best]
    on = ds.J.sel(mount="six_axis")
    np.testing.assert_allclose(on.sel(controller="passive_tuned").values, j[:, best], rtol=1e-12)
    np.testing.assert_allclose(on.sel(controller="passive_oracle").values, j.min(axis=1), rtol=1e-12)
    laws = [str(n) for n in runs[names[0]].law.values]
    scheduled = np.array(
        [runs[n].law_los_std.values[0, mounts.index("six_axis"), laws.index("scheduled")] for n in names]
    )
    np.testing.assert_allclose(on.sel(controller="scheduled").values, scheduled / rigid, rtol=1e-12)
    np.testing.assert_allclose(on.sel(controller="rigid").values, 1.0)
    page = (out / "benchmark/summary.md").read_text()
    assert "Controller benchmark on the payload" in page and "benchmark_payload.png" in page


def test_the_results_page_states_the_best_law_against_the_tuned_and_the_oracle_constant(gathered):
    """Evaluation means (hand sums above): scheduled 0.65, skyhook_tuned 0.85, passive_tuned 1.2, the oracle 0.3;
    rigid and the oracle are no controllers, so the scheduled law is named; where the tuned constant is best, it is."""
    from uavdamp.results import payload_page

    text = payload_page.benchmark_payload_finding(gathered)
    assert "the six-axis isolator the least mean J over the evaluation set is scheduled's, 0.65, against 1.2 " in text
    assert "and 0.3 for each scenario's own best constant C" in text
    table = payload_page.benchmark_payload_table(gathered).frame.set_index("controller")
    assert table.loc["passive_tuned", "tuned (N s/m)"] == "3" and table.loc["skyhook_tuned", "tuned (N s/m)"] == "10"
    assert table.loc["scheduled", "J mean / worst"] == "0.65 / 1"
    assert table.loc["scheduled", "los_std (µrad)"] == "4.00e+07"  # 40 rad in the fake runs
    runs = [fake_run(n, v[0], v[1], [500.0, 500.0, 500.0]) for n, v in RUNS.items()]
    ds = bench.gather(runs, SPLIT, "los_std")
    assert "is the tuned constant C's, 1.2: no law beats it" in payload_page.benchmark_payload_finding(ds)


def test_sources_are_split_apart_and_keep_the_scenarios_sets():
    base = {"a": "tuning", "b": "evaluation"}
    assert bench.split(base, ["s1"], 0.3, 2014) == base | {"s1": "evaluation"}
    two = bench.split(base, ["s2", "s1"], 0.5, 2014)
    assert {k: two[k] for k in base} == base and sorted(two[k] for k in ("s1", "s2")) == ["evaluation", "tuning"]
    with pytest.raises(ValueError, match=r"benchmark.payload.sources: \['a'\] are names of the benchmark's scenarios"):
        bench.split(base, ["a", "s1"], 0.5, 2014)


def test_a_source_the_config_lacks_or_a_scenarios_name_is_refused_by_key():
    config = load_config("config.yaml")
    config["benchmark"]["payload"]["sources"] = ["nothing"]
    with pytest.raises(ConfigError, match=r"benchmark.payload.sources\[0\]: 'nothing' is not a stated source"):
        checks_of_the_benchmark_on_the_payload(config)
    config["benchmark"]["payload"]["sources"] = ["multirotor_30"]
    config["benchmark"]["sources"] = ["multirotor_30"]
    with pytest.raises(ConfigError, match=r"benchmark.payload.sources\[0\]: 'multirotor_30' is the name of a bench"):
        checks_of_the_benchmark_on_the_payload(config)


def test_a_criterion_the_rigid_mount_does_not_show_tunes_nothing():
    """J is undefined where the rigid mount's criterion is 0 (a skew on a global shutter): no C is tuned, the tuned
    controllers' values are NaN, and the gather still writes every other controller."""
    runs = [fake_run(n, 0.0, v[1], v[2]) for n, v in RUNS.items()]
    ds = bench.gather(runs, SPLIT, "los_std")
    assert math.isnan(float(ds.tuned_damping.sel(mount="six_axis")))
    assert math.isnan(float(ds.tuned_c_on.sel(mount="six_axis")))
    assert np.all(np.isnan(ds.los_std.sel(controller=["passive_tuned", "skyhook_tuned"])))
    assert float(ds.los_std.sel(mount="six_axis", controller="scheduled", scenario="C")) == 30.0


def test_a_multirotor_source_needs_its_vibe_settling_only_when_the_benchmark_on_the_payload_runs():
    config = load_config("config.yaml")
    config["benchmark"]["duration_s"] = 1.5  # the VIBE filter's ten time constants: 10 / (2 pi 2 Hz) = 0.80 s, twice
    with pytest.raises(ConfigError, match=r"benchmark.duration_s: \(1.5 s\) must exceed 1.59 s for benchmark.payload"):
        checks_of_the_benchmark_on_the_payload(config)
    config["benchmark"]["payload"]["enabled"] = False
    checks_of_the_benchmark_on_the_payload(config)


def test_the_markdown_table_against_hand_sums(gathered):
    """One row per controller of the six-axis isolator: the tuned settings, mean / worst / tuning-mean J (hand sums
    of `test_controllers_and_j_against_hand_sums`), the criterion's evaluation mean, here in rad x 1e6 (40 rad:
    4e+07), and the mean MTF at Nyquist (2 x los + 1 in `fake_run`); the floor line (5 rad)."""
    text = bench.markdown_table(gathered)
    lines = text.splitlines()
    assert lines[0] == "**six_axis**: J = los_std over the rigid mount's, 2 evaluation scenarios (lower is better)"
    head = "| controller | setting | mean J | worst J | tuning mean J | mean los_std (µrad) | mean MTF |"
    assert lines[2] == head and lines[3] == "|---|---|---:|---:|---:|---:|---:|" and lines[-2] == ""
    rows = {line.split(" | ")[0].strip("| "): line for line in lines[4:] if line.startswith("| ")}
    assert list(rows) == list(gathered.controller.values)
    assert rows["passive_tuned"] == "| passive_tuned | C = 3 N s/m | 1.2 | 1.2 | 0.65 | 9e+07 | 181 |"
    assert rows["skyhook_tuned"] == "| skyhook_tuned | c_on = 10 N s/m | 0.85 | 0.9 | 0.6 | 6.5e+07 | 131 |"
    assert rows["passive_oracle"] == "| passive_oracle | best C per scenario | 0.3 | 0.4 | 0.5 | 2.5e+07 | 51 |"
    assert rows["scheduled"] == "| scheduled |  | 0.65 | 1 | 0.75 | 4e+07 | 81 |"
    assert lines[-1] == "The gimbal on a still mount (its sensor floor): line of sight 5e+06 µrad rms."


def test_every_variable_and_coordinate_carries_its_units_and_long_name(gathered):
    """CF attributes of what the gather writes: the J family dimensionless, the tuned settings in N s m-1, the
    metrics in their own units (los_std rad), the floor rad, every coordinate '1'."""
    for name, var in {**gathered.data_vars, **gathered.coords}.items():
        assert var.attrs.get("units") and var.attrs.get("long_name"), name
    units = {k: gathered[k].attrs["units"] for k in gathered.variables}
    assert {
        units[k] for k in ("J", "J_mean", "J_worst", "J_tuning_mean", "scenario", "set", "mount", "controller")
    } == {"1"}
    assert units["tuned_damping"] == units["tuned_c_on"] == "N s m-1"
    assert units["los_std"] == units["los_std_mean"] == units["floor_los_std"] == "rad"
    assert gathered.attrs["criterion"] == "los_std" and gathered.attrs["duration_s"] == 10.0
    assert gathered.attrs["settle_s"] == 1.0 and gathered.attrs["coupling"] == "one-way"  # the runs' own
    assert gathered.attrs["title"].startswith("Controller benchmark on the payload")
    long = {k: gathered[k].attrs["long_name"] for k in gathered.variables}
    assert long["J"] == "los_std over the rigid mount's on the same scenario"  # what J divides, by name
    assert long["J_mean"] == "mean J, evaluation set" and long["J_worst"] == "worst J, evaluation set"
    assert long["J_tuning_mean"] == "mean J, tuning set" and long["los_std_mean"] == "mean los_std, evaluation set"
    assert "constant C" in long["tuned_damping"] and "c_on" in long["tuned_c_on"] and "set" in long["set"]
    assert gathered.J.dims == ("scenario", "mount", "controller") and "payload" not in gathered.dims
    assert list(gathered.scenario_description.values) == [f"scenario {n}" for n in RUNS]
    assert gathered.scenario_description.attrs == {"units": "1", "long_name": "the scenario"}
    assert list(gathered.set.values) == [SPLIT[n] for n in RUNS]
