"""The linear plant's outputs and the state-space helpers against closed forms (issue 17 survivors).

- feedthrough: a one-state plant with c = 0, du = I and dv = I outputs u + v = a sin(w t) + a w cos(w t) exactly;
- the response's bookkeeping rows: mount_displacement is the prescribed input, isolator_velocity the derivative
  of base - mount (a central difference, O(h^2)), and the isolator K acts only on the isolated mount.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_platform import CONFIG

from uavdamp.excitation import sine_input
from uavdamp.linear_plant import LinearPlant
from uavdamp.platform import ExudynPlant
from uavdamp.statespace import StateSpace, free_response_rows, sine_outputs


def test_sine_outputs_carry_the_feedthrough_of_u_and_v():
    plant = StateSpace(a=np.array([[-1.0]]), b=np.zeros((1, 4)), c=np.zeros((2, 1)), du=np.eye(2), dv=np.eye(2))
    h, steps = 0.01, np.arange(50)
    free = free_response_rows(plant.c, np.exp(-h) * np.ones((1, 1)), steps.size)
    freq = np.array([2.0, 3.5])
    out = sine_outputs(plant, free, freq, 1, 1e-3, np.zeros((1, 2)), steps, h, [0, 1])
    t = steps * h
    w = 2 * np.pi * freq
    np.testing.assert_allclose(out[:, 0, :], 0.0, atol=1e-18)  # y row: the input is on z
    expected = 1e-3 * (np.sin(np.outer(t, w)) + w * np.cos(np.outer(t, w)))
    np.testing.assert_allclose(out[:, 1, :], expected, rtol=1e-12, atol=1e-15)


def test_free_response_rows_of_one_sample_and_of_a_block_boundary():
    phi = np.array([[0.9, 0.1], [-0.2, 0.95]])
    c = np.array([[1.0, 0.0], [0.5, -1.0]])
    expected = [c @ np.linalg.matrix_power(phi, k) for k in range(70)]
    np.testing.assert_allclose(free_response_rows(c, phi, 70, block=8), expected, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(free_response_rows(c, phi, 1), [c], rtol=0, atol=0)


@pytest.fixture(scope="module")
def plants():
    return (
        LinearPlant(ExudynPlant(CONFIG, mount="isolated").model),
        LinearPlant(ExudynPlant(CONFIG, mount="rigid").model),
    )


def test_response_rows_are_the_input_and_the_stroke_rate(plants):
    isolated, _ = plants
    time, y, z = sine_input(7.0, 3.0, 1e-3, 0.6, 0.002)
    ds = isolated.run(time, y, 0.5 * z, stiffness=200.0, law=5.0)
    np.testing.assert_allclose(ds.mount_displacement.sel(axis="y"), y, rtol=0, atol=1e-15)
    np.testing.assert_allclose(ds.mount_displacement.sel(axis="z"), 0.5 * z, rtol=0, atol=1e-15)
    stroke = (ds.base_displacement - ds.mount_displacement).values
    rate = ds.isolator_velocity.values
    central = (stroke[:, 2:] - stroke[:, :-2]) / (2 * 0.002)
    scale = np.abs(rate).max()
    assert np.abs(central - rate[:, 1:-1]).max() < 0.02 * scale  # O(h^2 w^2) = (0.002 * 44)^2 / 6 = 0.13 %
    assert np.abs(ds.base_displacement.sel(axis="y") - y).max() > 1e-4  # the base moves on its isolator


def test_the_isolator_stiffness_acts_only_on_the_isolated_mount(plants):
    isolated, rigid = plants
    np.testing.assert_allclose(
        rigid.model.undamped_frequencies(500.0), rigid.model.undamped_frequencies(0.0), rtol=1e-12
    )
    assert not np.allclose(isolated.model.undamped_frequencies(500.0), isolated.model.undamped_frequencies(10.0))
    time, y, z = sine_input(5.0, 6.0, 1e-3, 0.4, 0.002)
    a = rigid.run(time, y, z, stiffness=10.0, law=1.0)
    b = rigid.run(time, y, z, stiffness=900.0, law=1.0)
    np.testing.assert_array_equal(a.camera_displacement.values, b.camera_displacement.values)
    assert np.all(np.isnan(a.damping))


def test_camera_angles_match_exudyn_time_stepping(plants):
    """Yaw and pitch rows of the output map: the linear plant against Exudyn's run (its time-step error apart)."""
    isolated, _ = plants
    sim = ExudynPlant(CONFIG, mount="isolated")
    time, y, z = sine_input(5.3, 6.1, 1e-4, 0.6, 0.002)
    lin = isolated.run(time, y, z, stiffness=300.0, law=5.0)
    ref = sim.run(time, y, z, stiffness=300.0, law=5.0)
    for name in ("camera_yaw", "camera_pitch"):
        scale = np.abs(ref[name].values).max()
        assert scale > 0, name
        assert np.abs(lin[name].values - ref[name].values).max() < 0.02 * scale, name  # measured 0.4 %
