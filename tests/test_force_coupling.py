"""A force damper in the linear plant (`uavdamp.platform.force_coupling`): a viscous force damper against the exact
plant with that C, and the predictor-corrector's order in the step."""

import dataclasses

import numpy as np
import pytest
from conftest import FunctionLaw, typed_config

from uavdamp.contract import MountMotion
from uavdamp.damping import actuation, laws
from uavdamp.platform import coupling_kernel, force_coupling
from uavdamp.platform.linear_plant import LinearPlant

PARAMS = typed_config("quick.yaml").platform


def _error(h: float, stiffness: float, damping: float) -> float:
    """Largest |camera displacement| difference (m), force-coupled viscous damper vs the plant's own C, 3 s of two
    sines (7 Hz in y, 5 Hz in z), relative to the response's largest value."""
    params = dataclasses.replace(PARAMS, solver=dataclasses.replace(PARAMS.solver, time_step=h))
    plant = LinearPlant.from_params(params)
    t = np.arange(0.0, 3.0 + h / 2, h)
    mount = MountMotion.planar(1e-3 * np.sin(2 * np.pi * 7.0 * t), 0.5e-3 * np.sin(2 * np.pi * 5.0 * t))
    exact = plant.run(t, mount, stiffness=stiffness, law=laws.Constant(damping)).camera_displacement.values
    coupled = force_coupling.run(
        plant, t, mount, stiffness=stiffness, law=laws.Constant(damping), damper=force_coupling.Viscous()
    )
    assert coupled.attrs["damper"] == "viscous"
    return float(np.abs(coupled.camera_displacement.values - exact).max() / np.abs(exact).max())


@pytest.mark.parametrize(("stiffness", "damping"), [(1000.0, 20.0), (10.0, 5.0)])
def test_a_viscous_force_damper_converges_to_the_exact_plant_at_second_order(stiffness, damping):
    """The exact plant with C in A(K, C) is the reference (independent: no force input); the coupling holds the step's
    mean force (zero-order hold, its step solved for exactly: `rate_gain`), a second-order scheme: halving the step
    divides the error by 4. (Measured ratios 1 -> 0.5 -> 0.25 ms: 4.00, 4.00 here and at K = 10, C = 50.)"""
    e1, e2 = _error(1e-3, stiffness, damping), _error(5e-4, stiffness, damping)
    assert e1 / e2 == pytest.approx(4.0, rel=0.15)  # order 2 (asymptotic ratio 2^2)
    assert e2 < 1e-4  # 1.4e-5 measured at K = 1000, C = 20, 0.5 ms: within a tenth of a per mille


def test_the_force_input_is_the_dampers_and_only_the_isolated_mount_takes_one():
    plant = LinearPlant.from_params(PARAMS, mount="rigid")
    t = np.arange(0.0, 0.1, PARAMS.time_step)
    mount = MountMotion.planar(np.zeros_like(t), np.zeros_like(t))
    with pytest.raises(ValueError, match="a force damper needs the isolated mount"):
        force_coupling.run(plant, t, mount, stiffness=10.0, law=laws.Constant(1.0), damper=force_coupling.Viscous())


class _Recording:
    """A viscous damper without `rate_gain` (so the coupling takes its predictor-corrector path), recording the
    stroke and rate at the start of every step it is advanced over."""

    name = "recording"

    def __init__(self):
        self.viscous = force_coupling.Viscous()

    def reset(self, stroke) -> None:
        self.viscous.reset(stroke)
        self.starts = []

    def command(self, damping: float) -> None:
        self.viscous.command(damping)

    def force(self, x, xd):
        return self.viscous.force(x, xd)

    def step(self, h, x0, xd0, x1, xd1):
        self.starts.append(np.concatenate([x0, xd0]))
        return self.viscous.step(h, x0, xd0, x1, xd1)

    def save(self):
        return self.viscous.save()

    def restore(self, state) -> None:
        self.viscous.restore(state)


def test_each_step_starts_from_the_stroke_of_the_plants_state():
    # the damper is stepped twice per solver step (predict, correct), both from the state the plant reached: the
    # stroke and rate of the response at t_n (computed afterwards from the stored states, an independent path)
    plant = LinearPlant.from_params(PARAMS)
    h = PARAMS.time_step
    t = np.arange(0.0, 0.5 + h / 2, h)
    mount = MountMotion.planar(1e-3 * np.sin(2 * np.pi * 7.0 * t), 0.5e-3 * np.sin(2 * np.pi * 5.0 * t))
    damper = _Recording()
    out = force_coupling.run(plant, t, mount, stiffness=10.0, law=laws.Constant(20.0), damper=damper)
    starts = np.array(damper.starts)
    assert starts.shape == (2 * (t.size - 1), 4)
    np.testing.assert_array_equal(starts[0::2], starts[1::2])
    want = np.concatenate([out.isolator_stroke.values, out.isolator_velocity.values])
    scale = np.abs(want).max(axis=1, keepdims=True)
    np.testing.assert_allclose((starts[0::2].T - want[:, :-1]) / scale, 0.0, atol=1e-12)


def test_a_linear_damper_is_solved_exactly_where_the_predictor_corrector_diverges():
    # C = 200 N s/m at a 4 ms step: k |G| > 1, the predictor-corrector's iteration diverges (the scene leaves the
    # camera's view); the viscous damper's step is solved for exactly and stays second order in the step
    assert _error(4e-3, 10.0, 200.0) < 5e-3  # 2.7e-3 measured (6.6e-4 at 2 ms, 1.65e-4 at 1 ms)
    h = 4e-3
    params = dataclasses.replace(PARAMS, solver=dataclasses.replace(PARAMS.solver, time_step=h))
    plant = LinearPlant.from_params(params)
    t = np.arange(0.0, 1.0 + h / 2, h)
    mount = MountMotion.planar(1e-3 * np.sin(2 * np.pi * 7.0 * t), 0.5e-3 * np.sin(2 * np.pi * 5.0 * t))
    with np.errstate(all="ignore"):
        pece = force_coupling.run(plant, t, mount, stiffness=10.0, law=laws.Constant(200.0), damper=_Recording())
    assert not np.abs(pece.camera_displacement.values[:, -1]).max() < 1.0  # m: diverged (or NaN)


class _Generic:
    """The MR damper without its compiled `couple`: the coupling takes its Python predictor-corrector path."""

    name = "mr"

    def __init__(self, damper):
        self.damper = damper

    def __getattr__(self, key):
        if key == "couple":
            raise AttributeError(key)
        return getattr(self.damper, key)


def test_the_mr_dampers_compiled_coupling_is_the_predictor_corrector_written_out():
    """The MR damper (`actuation.MRDamper`, its step `couple` compiled) against the same damper stepped by the
    coupling's Python predictor-corrector (save, force, step, restore, step), 2 s of two sines at K = 1000 N/m with a
    demand switching 2 -> 60 -> 20 N s/m (0, full and a middle voltage): the same damper forces and camera motion to
    1e-12 of their largest values (the same arithmetic; the compiled sums may fuse)."""
    spec = actuation.MRSpec.build((10.0, 50.0), 5e-4)
    plant = LinearPlant.from_params(PARAMS)
    h = PARAMS.time_step
    t = np.arange(0.0, 2.0 + h / 2, h)
    mount = MountMotion.planar(2e-3 * np.sin(2 * np.pi * 7.0 * t), 1e-3 * np.sin(2 * np.pi * 5.0 * t))
    law = FunctionLaw(lambda o: (2.0, 60.0, 20.0)[int(o.t_now / 0.7) % 3], update_period=0.1)
    runs = [
        force_coupling.run(plant, t, mount, stiffness=1000.0, law=law, damper=damper)
        for damper in (actuation.MRDamper(spec), _Generic(actuation.MRDamper(spec)))
    ]
    assert hasattr(actuation.MRDamper(spec), "couple")
    for name in ("damper_force", "camera_displacement"):
        compiled, generic = (run[name].values for run in runs)
        assert np.abs(generic).max() > 0
        np.testing.assert_allclose(compiled, generic, rtol=0, atol=1e-12 * np.abs(generic).max(), err_msg=name)


def _numpy_steps(z0, end, free_map, free_drive, force_rows, gains):
    """The exact linear step written with numpy (`coupling_kernel`'s docstring): states, stroke ends, forces."""
    ns, z, forces = z0.size, [z0], []
    g = force_rows[ns : ns + 2]
    for n, k in enumerate(gains):
        free = free_map @ z[-1] + free_drive[n]
        f = np.linalg.solve(np.eye(2) + k * g, k * (free[ns : ns + 2] - end[:2]))
        state = free - force_rows @ f
        z.append(state[:ns])
        end = state[ns:]
        forces.append(f)
    return np.array(z), end, np.array(forces)


def test_the_compiled_exact_step_is_numpys_solution_of_the_two_by_two_system():
    """`coupling_kernel.linear_steps` against the same steps in numpy (`numpy.linalg.solve` for the force) on seeded
    systems: G with either sign and asymmetric, k over six decades, 1 and 40 steps from a given start; to the
    round-off of the products and of the 2 x 2 solve (its condition number)."""
    rng = np.random.default_rng(7)
    for steps in (1, 1, 40):
        for _ in range(60):
            ns = 6
            free_map = rng.normal(size=(ns + 4, ns)) * 0.3
            force_rows = rng.normal(size=(ns + 4, 2)) * 10 ** rng.uniform(-8, -2)
            gains = 10 ** rng.uniform(-3, 3, size=steps)
            start = int(rng.integers(0, 3))
            free_drive = rng.normal(size=(start + steps, ns + 4))
            z = np.zeros((start + steps + 1, ns))
            z[start] = rng.normal(size=ns)
            end0 = rng.normal(size=4)
            want_z, want_end, want_f = _numpy_steps(z[start], end0, free_map, free_drive[start:], force_rows, gains)
            end, force = end0.copy(), np.zeros((start + steps + 1, 2))
            coupling_kernel.linear_steps(z, end, free_map, free_drive, force_rows, gains, start, force)
            cond = max(np.linalg.cond(np.eye(2) + k * force_rows[ns : ns + 2]) for k in gains)
            tol = 1e-13 * cond * steps
            np.testing.assert_allclose(force[start : start + steps], want_f, rtol=0, atol=tol * np.abs(want_f).max())
            np.testing.assert_allclose(z[start:], want_z, rtol=0, atol=tol * np.abs(want_z).max())
            np.testing.assert_allclose(end, want_end, rtol=0, atol=tol * np.abs(want_end).max())


@pytest.mark.parametrize("damper", ["lagged", "mr"])
def test_the_law_observes_the_isolator_state_the_run_reports(damper):
    """Every step a law decided every step sees the stroke, the stroke rate, the mount's velocity and the base's
    absolute velocity of the state the run reached, as the response reports them afterwards (computed from the
    stored states: an independent path), to rounding; its demand switching with the stroke rate's sign (so that the
    damper's force moves the state)."""
    seen = []

    def record(observation):
        seen.append(np.concatenate([observation.stroke, observation.stroke_rate, observation.mount_velocity]))
        return 80.0 if observation.stroke_rate[0] > 0 else 5.0

    plant = LinearPlant.from_params(PARAMS)
    h = PARAMS.time_step
    t = np.arange(0.0, 0.6 + h / 2, h)
    mount = MountMotion.planar(1e-3 * np.sin(2 * np.pi * 7.0 * t), 0.5e-3 * np.sin(2 * np.pi * 5.0 * t))
    make = {
        "lagged": lambda: actuation.Lag(0.02),
        "mr": lambda: actuation.MRDamper(actuation.MRSpec.build((5.0, 30.0), 1e-3)),
    }
    law = FunctionLaw(record, update_period=h)
    out = force_coupling.run(plant, t, mount, stiffness=1000.0, law=law, damper=make[damper]())
    seen = np.array(seen)
    assert seen.shape == (t.size - 1, 6)
    stroke, rate = out.isolator_stroke.values[:, :-1], out.isolator_velocity.values[:, :-1]
    for got, want in ((seen[:, :2].T, stroke), (seen[:, 2:4].T, rate)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * np.abs(want).max())
    mount_rate = np.gradient(out.mount_displacement.values[1:3], h, axis=1)[:, :-1]
    np.testing.assert_allclose(seen[:, 4:].T, mount_rate, rtol=0, atol=1e-9 * np.abs(mount_rate).max())
    assert {80.0, 5.0} <= set(out.damping.values[:-1].tolist())  # the law switched: the state was moved by it
