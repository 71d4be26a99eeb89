"""The benchmark's semi-active laws: each one's defining property."""

import math

import numpy as np
import pytest
import xarray as xr
from conftest import load_config, platform_from, sine_yz
from hypothesis import given, settings
from hypothesis import strategies as st

from uavdamp.contract import DamperBounds, MountMotion, Observation
from uavdamp.damping import laws, semi_active
from uavdamp.platform import PlatformParams
from uavdamp.platform.linear_plant import LinearPlant
from uavdamp.reference_table import TableLookup

BOUNDS = DamperBounds(0.0, 150.0)
speed = st.floats(-1.0, 1.0, allow_nan=False).filter(lambda v: abs(v) > 1e-3)


@pytest.fixture(scope="module")
def params() -> PlatformParams:
    section = {k: v for k, v in load_config("quick.yaml")["platform"].items() if k not in ("response", "stroke")}
    return platform_from(section)


@pytest.fixture(scope="module")
def plant(params) -> LinearPlant:
    return LinearPlant.from_params(params)


def _observation(t_now=0.0, base_velocity=(0.0, 0.0), mount_velocity=(0.0, 0.0)) -> Observation:
    t = np.array([t_now])
    return Observation(
        t_now,
        t,
        np.zeros((1, 6)),
        np.asarray(base_velocity, float),
        np.asarray(mount_velocity, float),
        np.zeros(2),
    )


# ---------------------------------------------------------------- skyhook, groundhook, hybrid (one axis: closed form)


@settings(max_examples=200, deadline=None)
@given(v_abs=speed, v_mount=speed, gain=st.floats(0.1, 100.0))
def test_skyhook_groundhook_hybrid_switching_rules_on_one_axis(v_abs, v_mount, gain):
    """One axis (z at rest): skyhook C = g v_abs / v_rel when v_abs v_rel > 0, else c_min; groundhook
    C = -g v_mnt / v_rel when -v_mnt v_rel > 0, else c_min; hybrid their alpha-weighted sum (Ahmadian & Pare 2000)."""
    v_rel = v_abs - v_mount
    if abs(v_rel) < 1e-3:
        return
    expected_sky = gain * v_abs / v_rel if v_abs * v_rel > 0 else 0.0
    expected_gnd = -gain * v_mount / v_rel if -v_mount * v_rel > 0 else 0.0
    obs = _observation(base_velocity=(v_abs, 0.0), mount_velocity=(v_mount, 0.0))
    unbounded = DamperBounds(0.0, 1e9)  # g v / v_rel <= 1e5 here: the closed form itself
    for alpha, expected in ((1.0, expected_sky), (0.0, expected_gnd), (0.3, 0.3 * expected_sky + 0.7 * expected_gnd)):
        assert semi_active.Hybrid(gain, alpha, unbounded, 1e-3)(obs) == pytest.approx(expected, rel=1e-12, abs=1e-12)


def test_skyhook_reproduces_the_skyhook_force_when_it_can_and_else_asks_for_c_min():
    law = semi_active.Hybrid(10.0, 1.0, DamperBounds(0.5, 150.0), 1e-3)
    obs = _observation(base_velocity=(0.2, 0.1), mount_velocity=(-0.1, 0.3))  # v_rel = (0.3, -0.2)
    c = law(obs)
    v_rel, v_abs = np.array([0.3, -0.2]), np.array([0.2, 0.1])
    assert c == pytest.approx(10.0 * v_abs @ v_rel / (v_rel @ v_rel))  # least squares of -C v_rel = -g v_abs
    assert law(_observation(base_velocity=(0.2, 0.0), mount_velocity=(0.5, 0.0))) == 0.5  # v_abs v_rel < 0: c_min
    assert law(_observation(base_velocity=(0.2, 0.0), mount_velocity=(0.2, 0.0))) == 0.5  # no stroke motion
    with pytest.raises(ValueError, match="alpha: must be in"):
        semi_active.Hybrid(1.0, 1.5, BOUNDS, 1e-3)


@settings(max_examples=300, deadline=None)
@given(fy=speed, fz=speed, vy=speed, vz=speed)
def test_projected_damping_never_injects_energy(fy, fz, vy, vz):
    """C >= 0 always; c_min exactly when the force would push the stroke (F . v_rel >= 0); otherwise the damper
    force -C v_rel is the orthogonal projection of F on the stroke direction (or capped at c_max)."""
    force, v_rel = np.array([fy, fz]), np.array([vy, vz])
    c = semi_active.projected_damping(force, v_rel, 0.0, 1e12)
    assert c >= 0.0
    if force @ v_rel >= 0:
        assert c == 0.0
    else:
        scale = np.linalg.norm(force) * np.linalg.norm(v_rel)
        assert (force + c * v_rel) @ v_rel == pytest.approx(0.0, abs=1e-9 * scale)


# ------------------------------------------------------------------------------------------------- clipped-optimal


class _Recorder:
    """Wraps a ClippedOptimal law; records (desired force, v_rel, C) at every call."""

    def __init__(self, law):
        self.law, self.name, self.update_period, self.rows = law, law.name, law.update_period, []

    def reset(self):
        self.law.reset()

    def __call__(self, obs):
        c = self.law(obs)
        self.rows.append((-self.law.gain @ self.law.z_hat, np.asarray(obs.stroke_rate, float), c))
        return c


@pytest.mark.parametrize("stiffness", [10.0, 1000.0])
def test_clipped_optimal_asks_only_for_forces_a_damper_can_give(plant, params, stiffness):
    bounds = DamperBounds.from_params(params)
    law = _Recorder(
        semi_active.ClippedOptimal(plant.model, stiffness, bounds, params.time_step, q_scale=1e-3, r_scale=0.1)
    )
    time, y, z = sine_yz(7.0, 8.0, 1.3e-3, 1.0, params.time_step)
    response = plant.run(time, MountMotion.planar(y, z), stiffness=stiffness, law=law)
    desired, v_rel, c = (np.array(x) for x in zip(*law.rows, strict=True))
    power = np.einsum("ij,ij->i", desired, v_rel)
    assert np.all(c >= 0) and np.all(c[power >= 0] == bounds.c_min)  # no energy injection: c_min there
    pushed = (power < 0) & (np.einsum("ij,ij->i", v_rel, v_rel) > 1e-12)
    assert pushed.any() and np.all(c[pushed] > 0)  # and it acts where it can
    applied = response.damping.values[:-1]
    np.testing.assert_array_equal(applied, c)  # what it asked is what the plant applied (within the bounds)
    force = -applied[:, None] * response.isolator_velocity.values[:, :-1].T
    assert np.all(np.einsum("ij,ij->i", force, response.isolator_velocity.values[:, :-1].T) <= 0)


def test_clipped_optimal_observer_tracks_the_plant(plant, params):
    """The observer's camera displacement follows the plant's (its state is not measured: observed)."""
    from uavdamp.platform.linear_plant import OUTPUTS

    bounds = DamperBounds.from_params(params)
    law = semi_active.ClippedOptimal(plant.model, 10.0, bounds, params.time_step, q_scale=1e-3, r_scale=0.1)
    estimates = []

    class Spy(_Recorder):
        def __call__(self, obs):
            c = self.law(obs)
            rows = [OUTPUTS.index("camera_y"), OUTPUTS.index("camera_z")]
            estimates.append(self.law.plant.c[rows] @ self.law.z_hat + self.law.plant.du[rows] @ obs.mount[-1])
            return c

    time, y, z = sine_yz(7.0, 8.0, 1.3e-3, 1.0, params.time_step)
    response = plant.run(time, MountMotion.planar(y, z), stiffness=10.0, law=Spy(law))
    true = response.camera_displacement.values[:, :-1].T
    error = np.abs(np.array(estimates) - true)[time[:-1] > 0.5]
    assert error.max() < 1e-3 * np.abs(true).max()  # measured 1.3e-5


def test_clipped_optimal_estimate_is_the_kalman_recursion_written_out(plant, params):
    """Each step's estimate replayed from the law's recorded observations and forces by the textbook predictor-
    corrector on the law's own matrices, term by term: z = phi z_hat + gamma_u u_prev + gamma_v u' + gamma_f F,
    z_hat = z + L (y - [h_pos z + du_pos u; h_vel z + dv_vel u'])."""
    law = semi_active.ClippedOptimal(
        plant.model, 10.0, DamperBounds.from_params(params), params.time_step, q_scale=1e-3, r_scale=0.1
    )
    seen = []

    class Spy(_Recorder):
        def __call__(self, obs):
            force = self.law._force.copy()
            c = self.law(obs)
            seen.append((obs.mount[-2:].copy(), obs.time[-2:].copy(), obs, force, self.law.z_hat.copy()))
            return c

    time, y, z = sine_yz(7.0, 8.0, 1.3e-3, 0.2, params.time_step)
    roll = 0.01 * np.sin(2 * np.pi * 5.0 * time)  # rad: the mount's roll reaches the measurement through du, dv
    motion = MountMotion(np.stack([np.zeros_like(y), y, z]), np.stack([roll, np.zeros_like(y), np.zeros_like(y)]))
    plant.run(time, motion, stiffness=10.0, law=Spy(law))
    for (mount, t, obs, force, z_hat), (_, _, _, _, previous) in zip(seen[1:], seen[:-1], strict=True):
        slope = (mount[1] - mount[0]) / (t[1] - t[0])
        step = law.step
        z_pred = step.phi @ previous + step.gamma_u @ mount[0] + step.gamma_v @ slope + law.gamma_f @ force
        measured = np.concatenate([obs.stroke + mount[1][1:3], obs.base_velocity])
        predicted = np.concatenate(
            [law.h_pos @ z_pred + law.du_pos @ mount[1], law.h_vel @ z_pred + law.dv_vel @ slope]
        )
        expected = z_pred + law.kalman @ (measured - predicted)
        np.testing.assert_allclose(z_hat, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())


# --------------------------------------------------------------------------------------------------- table lookup


def test_table_lookup_reproduces_the_table_at_its_grid_points():
    rng = np.random.default_rng(3)
    fy, fz, k = np.linspace(3, 12, 4), np.linspace(3, 12, 5), np.array([10.0, 100.0, 1000.0])
    values = rng.uniform(0.5, 100.0, (4, 5, 3))
    table = xr.Dataset(
        {"damping_opt": (("freq_y", "freq_z", "stiffness"), values)},
        coords={"freq_y": fy, "freq_z": fz, "stiffness": k},
    )
    model = TableLookup(table)
    grid = np.array(np.meshgrid(fy, fz, k, indexing="ij")).reshape(3, -1).T
    np.testing.assert_allclose(model.predict(grid), values.ravel(), rtol=1e-12)
    # between grid points: linear in f and log10 K; outside: the edge
    mid = model.predict([[fy[0], fz[0], math.sqrt(10.0 * 100.0)]])[0]
    assert mid == pytest.approx(0.5 * (values[0, 0, 0] + values[0, 0, 1]))
    assert model.predict([[1.0, 20.0, 5000.0]])[0] == pytest.approx(values[0, -1, -1])
    law = laws.AnfisLaw(model, 100.0, 7.0, lambda t, s, now: 12.0)  # the ANFIS law's plumbing takes it as is
    assert law(_observation()) == pytest.approx(values[-1, -1, 1])
