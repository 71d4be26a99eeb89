"""The clairvoyant scheduler: never worse than a fixed candidate C on its own criterion, and its cost is real."""

import itertools

import numpy as np
import pytest
from conftest import load_config, platform_from, sine_yz

from uavdamp.contract import MountMotion
from uavdamp.damping import clairvoyant, laws
from uavdamp.damping.laws import Constant
from uavdamp.platform.linear_plant import LinearPlant


@pytest.fixture(scope="module")
def plant() -> LinearPlant:
    section = {k: v for k, v in load_config("quick.yaml")["platform"].items() if k not in ("response", "stroke")}
    return LinearPlant.from_params(platform_from(section))


def _criterion(response, criterion: str) -> float:
    """The criteria from the response dataset (independent of the search's running sums)."""
    if criterion == "displacement_std":
        return float(np.sqrt((response.camera_displacement.var("time")).sum()))
    return float(np.hypot(response.camera_yaw.std(), response.camera_pitch.std()))


@pytest.mark.parametrize(
    ("stiffness", "criterion", "beam"),
    [
        (10.0, "displacement_std", 3),
        (1000.0, "los_std", 3),
        (10.0, "displacement_std", 1),
        (1000.0, "displacement_std", 1),
    ],
)
def test_clairvoyant_is_never_worse_than_any_fixed_candidate(plant, stiffness, criterion, beam):
    h = plant.params.time_step
    time, y, z = sine_yz(5.0, 8.0, 1.3e-3, 2.0, h)
    y = y * np.where(time < 1.0, 1.0, 0.3)  # a change half-way: a schedule has something to gain
    candidates = [0.5, 3.0, 20.0, 150.0]
    found = clairvoyant.schedule(
        plant,
        time,
        MountMotion.planar(y, z),
        stiffness=stiffness,
        candidates=candidates,
        update_period=0.4,
        beam_width=beam,
        criterion=criterion,
    )
    assert found.values.shape == (5,)
    replay = plant.run(
        time, MountMotion.planar(y, z), stiffness=stiffness, law=laws.Schedule(found.values, update_period=0.4)
    )
    assert found.cost == pytest.approx(_criterion(replay, criterion), rel=1e-9)  # the cost is the schedule's
    for c in candidates:
        fixed = _criterion(
            plant.run(time, MountMotion.planar(y, z), stiffness=stiffness, law=laws.Constant(c)), criterion
        )
        assert found.cost <= fixed * (1 + 1e-9)
    np.testing.assert_allclose(
        found.constant_costs,
        [
            _criterion(plant.run(time, MountMotion.planar(y, z), stiffness=stiffness, law=Constant(c)), criterion)
            for c in candidates
        ],
        rtol=1e-9,
    )


def test_clairvoyant_refuses_bad_options(plant):
    time, y, z = sine_yz(5.0, 8.0, 1.3e-3, 0.5, plant.params.time_step)
    with pytest.raises(ValueError, match="criterion: unknown 'blur'"):
        clairvoyant.schedule(
            plant,
            time,
            MountMotion.planar(y, z),
            stiffness=10.0,
            candidates=[1.0],
            update_period=0.1,
            beam_width=2,
            criterion="blur",
        )
    with pytest.raises(ValueError, match="candidates: need values within"):
        clairvoyant.schedule(
            plant, time, MountMotion.planar(y, z), stiffness=10.0, candidates=[1e6], update_period=0.1, beam_width=2
        )


def test_a_beam_as_wide_as_every_schedule_finds_the_best_of_them(plant):
    """With the beam as wide as the schedules (3 candidates over 3 periods: 27), the search is exhaustive: its
    schedule and cost are the best of the 27 schedules, each run on its own by the plant (independent of the
    search's sums and of its superposition of each period's free and forced response)."""
    h = plant.params.time_step
    time, y, z = sine_yz(4.0, 4.0, 1.3e-3, 1.2, h)
    _, y_high, z_high = sine_yz(15.0, 15.0, 1.3e-3, 1.2, h)
    first = time < 0.4  # 4 Hz (near the platform's modes) in the first period, then 15 Hz at a fifth of it
    motion = MountMotion.planar(np.where(first, y, 0.2 * y_high), np.where(first, z, 0.2 * z_high))
    candidates = [0.5, 8.0, 150.0]
    costs = {
        values: _criterion(
            plant.run(time, motion, stiffness=10.0, law=laws.Schedule(np.array(values), update_period=0.4)),
            "displacement_std",
        )
        for values in itertools.product(candidates, repeat=3)
    }
    best = min(costs, key=costs.get)
    found = clairvoyant.schedule(
        plant, time, motion, stiffness=10.0, candidates=candidates, update_period=0.4, beam_width=27
    )
    assert len(set(best)) > 1, "the best schedule changes C (else the test shows only the constant search)"
    assert tuple(found.values) == best
    assert found.cost == pytest.approx(costs[best], rel=1e-9)


def test_a_beam_of_one_is_the_greedy_schedule(plant):
    """Beam width 1 keeps, after each period, the one schedule whose output so far has the least criterion: the
    greedy schedule, rebuilt here period by period from runs of the plant (the prefix's samples: those before the
    next period's start). A beam that kept the wrong end of its ranking would leave it."""
    h = plant.params.time_step
    time, y, z = sine_yz(4.0, 4.0, 1.3e-3, 1.2, h)
    _, y_high, z_high = sine_yz(15.0, 15.0, 1.3e-3, 1.2, h)
    first = time < 0.4
    motion = MountMotion.planar(np.where(first, y, 0.2 * y_high), np.where(first, z, 0.2 * z_high))
    candidates, per_update = [0.5, 8.0, 150.0], int(round(0.4 / h))

    def prefix_cost(values: list, end: int) -> float:  # the criterion over samples [0, end) of a 3-period schedule
        values = np.array(values + [values[-1]] * (3 - len(values)))
        run = plant.run(time, motion, stiffness=10.0, law=laws.Schedule(values, update_period=0.4))
        return float(np.sqrt(run.camera_displacement.isel(time=slice(0, end)).var("time").sum()))

    greedy = []
    for period in range(3):
        end = (period + 1) * per_update if period < 2 else time.size
        greedy.append(min(candidates, key=lambda c, end=end: prefix_cost([*greedy, c], end)))
    found = clairvoyant.schedule(
        plant, time, motion, stiffness=10.0, candidates=candidates, update_period=0.4, beam_width=1
    )
    assert len(set(greedy)) > 1, "the greedy schedule changes C (else a constant schedule could stand in for it)"
    assert tuple(found.values) == tuple(greedy), (found.values, greedy)
