"""The clairvoyant scheduler: never worse than a fixed candidate C on its own criterion, and its cost is real."""

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
