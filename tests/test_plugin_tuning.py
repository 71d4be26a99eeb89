"""A plug-in law's own tuned parameter (`uavdamp.benchmark.tuning.register_tuned`): tuned on the tuning scenarios
exactly as a built-in one (in a benchmark.tuning range or its own), run once per tuning criterion, counted in the
budget, and refused when taken or badly ranged.

The expected values come from the built-in passive_tuned: the test's plug-in is the same law (a constant C read
from ``ctx.tuned``) under another name, so its search must land where the built-in one does."""

import re
from dataclasses import replace

import pytest
from conftest import typed_config

from uavdamp.benchmark import loop as benchmark
from uavdamp.benchmark import scenarios, tuning
from uavdamp.config import budget
from uavdamp.damping import laws
from uavdamp.study import strategies

CONFIG = typed_config("quick.yaml")
BENCH = CONFIG.benchmark
OWN_RANGE = (0.5, 3.0)  # N s m-1, a plug-in's own range, narrower than the quick config's damping_range (0.1, 200)


@pytest.fixture
def my_passive(request):
    """The plug-in "my_passive" (C = ctx.tuned["my_passive_damping"]) registered for one test, then removed; searched
    in benchmark.tuning.damping_range by name (the default), or in its own OWN_RANGE (indirect parameter "own").
    Yields the range it is searched in."""
    saved = dict(tuning.TUNED), dict(tuning._UNITS), set(tuning.TUNED_CONTROLLERS)

    @strategies.register("my_passive")
    def factory(ctx):
        return strategies.Strategy("my_passive", "isolated", laws.Constant(float(ctx.tuned["my_passive_damping"])))

    own = getattr(request, "param", "damping_range") == "own"
    tuning.register_tuned("my_passive_damping", "my_passive", OWN_RANGE if own else "damping_range", "N s m-1")
    yield OWN_RANGE if own else BENCH.tuning.damping_range
    strategies.REGISTRY.pop("my_passive")
    for table, old in zip((tuning.TUNED, tuning._UNITS, tuning.TUNED_CONTROLLERS), saved, strict=True):
        table.clear()
        table.update(old)


@pytest.mark.parametrize("my_passive", ["damping_range", "own"], indirect=True)
def test_the_plugin_parameter_is_tuned_like_the_built_in_one(my_passive):
    """Tuned with the config's ranges, the plug-in lands where passive_tuned lands when its own damping_range is set to
    the plug-in's range: the same search in the same range, run apart."""
    names = sorted(scenarios.scenario_specs(BENCH))
    split = scenarios.split(names, BENCH.split.tuning_fraction, BENCH.split.seed)
    name = next(n for n in names if split[n] == "tuning")
    params = CONFIG.platform
    inputs = {name: scenarios.scenario_input(name, BENCH, CONFIG.helicopter, params.time_step)}
    options = replace(BENCH, tracking=CONFIG.study.tracking, camera=CONFIG.camera)
    plugin = benchmark.tune(inputs, params, replace(options, controllers=("my_passive",)))
    builtin = benchmark.tune(
        inputs,
        params,
        replace(options, controllers=("passive_tuned",), tuning=replace(BENCH.tuning, damping_range=my_passive)),
    )
    assert plugin.my_passive_damping.attrs["units"] == "N s m-1"
    assert plugin.my_passive_damping.sizes == builtin.passive_damping.sizes
    assert (plugin.my_passive_damping.values == builtin.passive_damping.values).all()
    assert (plugin.my_passive_damping_cost.values == builtin.passive_damping_cost.values).all()
    assert ((my_passive[0] <= plugin.my_passive_damping) & (plugin.my_passive_damping <= my_passive[1])).all()
    at = tuning.tuned_at(plugin, BENCH.stiffness[0], BENCH.tuning.criteria[0])
    assert at["my_passive_damping"] == float(builtin.passive_damping.sel(tuned_for=BENCH.tuning.criteria[0])[0])


def test_the_plugin_law_runs_once_per_tuning_criterion(my_passive):
    options = replace(BENCH, controllers=("passive_tuned", "my_passive"))
    runs = benchmark._runs("my_passive", options)
    assert runs == benchmark._runs("passive_tuned", options)
    assert [criterion for criterion, _ in runs] == list(BENCH.tuning.criteria)


def test_the_budget_counts_the_plugin_search(my_passive):
    """One more parameter adds tuning scenarios x K x criteria x (n_candidates + max_refine) runs (budget docstring)."""
    base = replace(CONFIG, benchmark=replace(BENCH, controllers=("rigid", "passive_tuned")))
    more = replace(CONFIG, benchmark=replace(BENCH, controllers=("rigid", "passive_tuned", "my_passive")))
    names = sorted(scenarios.scenario_specs(BENCH))
    n_tuning = sum(
        role == "tuning" for role in scenarios.split(names, BENCH.split.tuning_fraction, BENCH.split.seed).values()
    )
    t = BENCH.tuning
    search = n_tuning * len(BENCH.stiffness) * len(t.criteria) * (t.n_candidates + t.max_refine)
    assert budget.benchmark_runs(more)["tuning_runs"] - budget.benchmark_runs(base)["tuning_runs"] == search


@pytest.mark.parametrize(
    ("key", "range_field", "message"),
    [
        ("passive_damping", "damping_range", "registered twice"),
        ("my_gain", "speed_range", "not one of benchmark.tuning's"),
        ("my gain", "gain_range", "must match"),
        ("my_gain", (0.0, 1.0), "0 < min < max"),
        ("my_gain", (2.0, 1.0), "0 < min < max"),
        ("my_gain", (1.0, 2.0, 3.0), "0 < min < max"),
    ],
)
def test_a_taken_key_an_unknown_range_or_an_unsafe_name_is_refused(my_passive, key, range_field, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        tuning.register_tuned(key, "my_passive", range_field, "N s m-1")
    assert key not in tuning.TUNED or key == "passive_damping"
