"""The plan's budget counts the benchmark when its target is requested (1607 planned jobs were once "about
0.272 CPU min"): its counts against a count made here from the config's own lists."""

from __future__ import annotations

import itertools

import pytest
from conftest import deep_update, load_config

from uavdamp.benchmark.scenarios import scenario_specs, split
from uavdamp.config import budget
from uavdamp.config.load import load

# the controllers the benchmark tunes (docs/benchmark: one parameter each; hybrid's gain once per hybrid_alpha)
TUNED = ("passive_tuned", "skyhook_on_off", "skyhook_clipped", "groundhook", "hybrid", "clipped_optimal")


def _count(section: dict) -> tuple[int, int, int, int]:
    """(runs without the MR damper, runs with it, tuned searches per criterion, scenarios) of a benchmark section."""
    heli = section["helicopter"]
    n_heli = len(list(itertools.product(heli["imbalance_mass_factor"], heli["rotor_speed_ratio"], heli["mount"])))
    n_heli *= sum(len(heli["tail_rotor"]) if f == "vacuum" else 1 for f in heli["flight"])
    n_scenarios = n_heli + len(section["synthetic"]) + len(section.get("flight_logs", []))
    per_damper = n_scenarios * len(section["controllers"]) * len(section["stiffness_n_m"])
    plain = per_damper * len([d for d in section["dampers"] if d != "mr"])
    mr = per_damper if "mr" in section["dampers"] else 0
    t = section["tuning"]
    searches = sum(len(t["hybrid_alpha"]) if c == "hybrid" else 1 for c in TUNED if c in section["controllers"])
    return plain, mr, searches, n_scenarios


@pytest.mark.parametrize("name", ["config.yaml", "quick.yaml"])
def test_the_benchmark_runs_are_counted_from_the_config(name):
    raw = load_config(name)
    config = load(raw)
    plain, mr, searches, n_scenarios = _count(raw["benchmark"])
    names = sorted(scenario_specs(config.benchmark))
    assert len(names) == n_scenarios
    split_of = split(names, raw["benchmark"]["split"]["tuning_fraction"], raw["benchmark"]["split"]["seed"])
    n_tuning = sum(v == "tuning" for v in split_of.values())
    t = raw["benchmark"]["tuning"]
    tuning = (
        n_tuning
        * len(raw["benchmark"]["stiffness_n_m"])
        * (1 + len(t["criteria"]) * searches * (t["n_candidates"] + t["max_refine"]))
    )
    assert budget.benchmark_runs(config) == {"runs": plain, "mr_runs": mr, "tuning_runs": tuning}
    with_bench, without = budget.estimate(config, benchmark=True), budget.estimate(config)
    assert with_bench["benchmark_runs"] == plain + mr + tuning and without["benchmark_runs"] == 0
    b = raw["budget"]["platform_cpu_per_simulated_s"] * raw["benchmark"]["duration_s"]
    expected = (plain + budget.MR_COST * mr + tuning) * b
    assert with_bench["cpu_s_benchmark"] == pytest.approx(expected, rel=1e-12)
    assert with_bench["cpu_s"] == pytest.approx(without["cpu_s"] + expected, rel=1e-12)


def test_a_benchmark_over_the_budget_is_refused_only_when_requested():
    quick = load_config("quick.yaml")
    config = load(deep_update(quick, {"budget": {"max_cpu_hours": 0.02}}))  # 1.2 min: the study fits, not both
    assert budget.check(config)["cpu_s"] < 72.0
    with pytest.raises(ValueError, match=r"^budget.max_cpu_hours: .* benchmark 181 runs: "):
        budget.check(config, benchmark=True)
