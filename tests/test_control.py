"""Damping strategies: bounds, the ANFIS decision function, Karnopp's skyhook, the optimal passive search."""

import math

import numpy as np
import pytest
from conftest import load_config

from uavdamp import control, spectrum
from uavdamp.anfis import ANFIS
from uavdamp.platform import PlatformParams, PlatformSimulator, Seen, sine_input

BOUNDS = control.DamperBounds(0.5, 150.0)


@pytest.fixture(scope="module")
def params() -> PlatformParams:
    section = {k: v for k, v in load_config("quick.yaml")["platform"].items() if k != "response"}
    return PlatformParams.from_config(section)


def _seen(t, y, z, t_now, base_velocity=(0.0, 0.0), mount_velocity=(0.0, 0.0)) -> Seen:
    """What the simulator would show at t_now: the input up to and including t_now."""
    n = int(np.searchsorted(t, t_now + 1e-9, side="right"))
    return Seen(t[:n], y[:n], z[:n], np.asarray(base_velocity, float), np.asarray(mount_velocity, float))


class Stub:
    """A model whose output is a known function of (f_y, f_z, K); it records its inputs."""

    def __init__(self, fn):
        self.fn, self.inputs = fn, []

    def predict(self, X):
        X = np.asarray(X, float)
        self.inputs.append(X.copy())
        return np.array([self.fn(*row) for row in X])


# ---------------------------------------------------------------------------- simple strategies


def test_rigid_and_passive():
    r = control.rigid()
    assert (r.mount, r.damping, r.update_period) == ("rigid", None, None)
    p = control.passive(2.0, BOUNDS)
    assert (p.mount, p.damping) == ("isolated", 2.0)
    with pytest.raises(ValueError, match="outside"):
        control.passive(0.1, BOUNDS)
    with pytest.raises(ValueError, match="rigid"):
        control.Strategy("x", "rigid", 1.0)
    with pytest.raises(ValueError, match="bounds"):
        control.DamperBounds(5.0, 1.0)


def test_bounds_from_params(params):
    b = control.DamperBounds.from_params(params)
    assert (b.c_min, b.c_max) == (params.damping_min, params.damping_max)


# ---------------------------------------------------------------------------- optimal passive


def test_optimal_passive_finds_the_minimiser_of_a_convex_criterion():
    c_true = 7.3

    def criterion(c):
        return 1.0 + (math.log(c) - math.log(c_true)) ** 2

    grid = np.geomspace(0.5, 150.0, 12)
    result = control.optimal_passive(criterion, grid, BOUNDS)
    assert result.c == pytest.approx(c_true, rel=0.01)
    assert result.criterion == pytest.approx(1.0, abs=1e-4)
    cs = [c for c, _ in result.evaluations]
    assert cs[:12] == pytest.approx(list(grid))  # the grid first, in order
    assert len(cs) == len(set(cs)) <= 12 + 20  # each C once, refinement within maxiter
    assert all(BOUNDS.contains(c) for c in cs)
    again = control.optimal_passive(criterion, grid, BOUNDS)
    assert again.evaluations == result.evaluations  # deterministic
    assert result.strategy().damping == result.c


def test_optimal_passive_at_the_end_of_the_grid_and_bad_candidates():
    result = control.optimal_passive(lambda c: c, np.geomspace(1.0, 100.0, 5), BOUNDS)  # increasing: best is 1.0
    assert result.c == pytest.approx(1.0, rel=0.02)
    result = control.optimal_passive(lambda c: -c if c < 50 else math.nan, np.geomspace(1.0, 100.0, 5), BOUNDS)
    assert result.c < 50 and math.isfinite(result.criterion)  # NaN criterion treated as +inf
    with pytest.raises(ValueError, match="within"):
        control.optimal_passive(lambda c: c, [0.1, 1.0], BOUNDS)


# ---------------------------------------------------------------------------- ANFIS decision function


def _two_tone(duration=3.0, dt=0.002):
    t = np.arange(int(round(duration / dt)) + 1) * dt
    return t, 1.3e-3 * np.sin(2 * np.pi * 7.01 * t), 1.3e-3 * np.sin(2 * np.pi * 8.05 * t + 0.5)


def test_anfis_decision_uses_initial_c_then_the_tracked_frequencies():
    t, y, z = _two_tone()
    model = Stub(lambda fy, fz, k: fy + fz + k)  # 7.01 + 8.05 + 10 = 25.06
    decide = control.AnfisDamping(model, 10.0, BOUNDS, c_initial=2.0, window=1.0, min_freq_hz=3.0, max_freq_hz=12.0)
    times = np.arange(7) * 0.5
    cs = [decide(tk, _seen(t, y, z, tk)) for tk in times]
    assert cs[:2] == [2.0, 2.0]  # t = 0 and 0.5 s: less than 2 cycles of 3 Hz seen
    assert cs[2:] == pytest.approx([25.06] * 5, rel=0.005)
    assert [d.note for d in decide.decisions] == ["initial: no frequency yet"] * 2 + ["anfis"] * 5
    assert [d.time for d in decide.decisions] == list(times)
    assert all(BOUNDS.contains(c) for c in cs)
    # the model saw exactly the recorded frequencies and K, and they are the tracker's numbers
    np.testing.assert_array_equal(np.vstack(model.inputs)[:, 2], 10.0)
    np.testing.assert_array_equal(np.vstack(model.inputs)[:, 0], [d.freq_y_hz for d in decide.decisions[2:]])
    track_t, track_y = spectrum.track_dominant(t, y, update_period=0.5, window=1.0, min_freq_hz=3.0, max_freq_hz=12.0)
    np.testing.assert_array_equal(track_y[:6], [d.freq_y_hz for d in decide.decisions[1:]])
    # a new run (time back to 0) starts a new record
    decide(0.0, _seen(t, y, z, 0.0))
    assert len(decide.decisions) == 1


def test_anfis_decision_clips_and_never_returns_nan():
    t, y, z = _two_tone()
    huge = control.AnfisDamping(Stub(lambda *a: 1e6), 10.0, BOUNDS, c_initial=2.0)
    assert huge(1.0, _seen(t, y, z, 1.0)) == BOUNDS.c_max and huge.decisions[-1].note == "clipped"
    calls = iter([30.0, math.nan])
    flaky = control.AnfisDamping(Stub(lambda *a: next(calls)), 10.0, BOUNDS, c_initial=2.0)
    assert flaky(1.0, _seen(t, y, z, 1.0)) == 30.0
    assert flaky(1.5, _seen(t, y, z, 1.5)) == 30.0  # NaN from the model: the previous C is held
    assert flaky.decisions[-1].note.startswith("held")
    flat = control.AnfisDamping(Stub(lambda *a: 30.0), 10.0, BOUNDS, c_initial=2.0)
    zeros = np.zeros_like(t)
    assert flat(2.0, _seen(t, zeros, zeros, 2.0)) == 2.0  # no frequency in a still signal: initial C
    with pytest.raises(ValueError, match="c_initial"):
        control.AnfisDamping(Stub(lambda *a: 1.0), 10.0, BOUNDS, c_initial=0.0)


def test_anfis_decision_with_a_trained_anfis_in_the_simulator(params):
    # tiny ANFIS fitted to C = 1 + 2 f_y on a 3 x 3 x 2 grid; the platform runs with it as its decision function
    fy, fz, k = np.meshgrid([3.0, 7.5, 12.0], [3.0, 7.5, 12.0], [10.0, 1000.0], indexing="ij")
    X = np.column_stack([fy.ravel(), fz.ravel(), k.ravel()])
    model = ANFIS(n_mfs=2, epochs=5).fit(X, 1.0 + 2.0 * X[:, 0])
    bounds = control.DamperBounds.from_params(params)
    decide = control.AnfisDamping(model, 10.0, bounds, c_initial=2.0, window=1.0, min_freq_hz=3.0, max_freq_hz=12.0)
    t, y, z = sine_input(7.01, 8.05, 1.3e-3, 3.0, params.time_step)
    ds = PlatformSimulator(params).run(t, y, z, stiffness=10.0, damping=decide.strategy().damping)
    applied = ds.damping.values
    changes = ds.time.values[1:][np.diff(applied) != 0]
    period = params.update_period
    assert np.all(np.abs(changes / period - np.round(changes / period)) < 1e-9)  # only at update times
    assert np.all((applied >= bounds.c_min) & (applied <= bounds.c_max))
    # called at 0, 0.5, ... 2.5 s (the value set at the end time, 3.0 s, would act on no step)
    assert [d.time for d in decide.decisions] == pytest.approx(list(np.arange(6) * period))
    assert applied[ds.time.values < 1.0] == pytest.approx(2.0)  # initial C until the first tracked frequency
    last = decide.decisions[-1]
    assert (last.freq_y_hz, last.freq_z_hz) == pytest.approx((7.01, 8.05), rel=0.01)
    assert applied[-1] == model.predict([[last.freq_y_hz, last.freq_z_hz, 10.0]])[0]
    expected = [d.damping for d in decide.decisions]
    np.testing.assert_allclose(applied[np.searchsorted(ds.time.values, np.arange(6) * period)], expected)


# ---------------------------------------------------------------------------- skyhook


@pytest.mark.parametrize(
    ("v_abs", "v_rel", "on"),
    [
        ((1.0, 0.0), (0.5, 0.0), True),  # one axis: same sign, the damper pulls against the base's motion
        ((-1.0, 0.0), (-0.5, 0.0), True),
        ((1.0, 0.0), (-0.5, 0.0), False),
        ((1.0, 1.0), (2.0, -1.0), True),  # two axes: the power sum v_abs . v_rel = 1 > 0
        ((1.0, 1.0), (1.0, -2.0), False),  # -1 < 0
        ((0.0, 0.0), (1.0, 1.0), False),  # base still: nothing to oppose (ties: c_min)
    ],
)
def test_skyhook_sign_logic(v_abs, v_rel, on):
    sky = control.Skyhook(BOUNDS, 0.002)
    mount = np.subtract(v_abs, v_rel)  # v_rel = base - mount
    c = sky(0.0, Seen(np.zeros(1), np.zeros(1), np.zeros(1), np.asarray(v_abs, float), mount))
    assert c == (BOUNDS.c_max if on else BOUNDS.c_min)
    assert sky.update_period == 0.002 and sky.strategy().update_period == 0.002


def _camera_criterion(ds) -> float:
    """sqrt(sigma_y^2 + sigma_z^2) of the camera displacement, m (the reference table's criterion)."""
    return float(np.sqrt((ds.camera_displacement.std("time") ** 2).sum()))


def test_skyhook_in_the_simulator(params):
    # K = 10 N/m, 1.3 mm at 7 Hz (y) and 8 Hz (z), 3 s. Far above the 0.4 Hz isolator resonance the
    # undamped isolator already isolates, so no damping beats c_min here; what on-off skyhook must do is
    # beat its own "on" state: passive c_max. Measured (quick config, 4 ms step): skyhook 0.89 mm,
    # passive c_max 1.44 mm, passive c_min 0.067 mm.
    bounds = control.DamperBounds.from_params(params)
    t, y, z = sine_input(7.0, 8.0, 1.3e-3, 3.0, params.time_step)
    sim = PlatformSimulator(params)
    sky = control.Skyhook(bounds, params.time_step)
    strategy = sky.strategy()
    ds = sim.run(t, y, z, stiffness=10.0, damping=strategy.damping, update_period=strategy.update_period)
    applied = ds.damping.values
    assert set(np.unique(applied)) == {bounds.c_min, bounds.c_max}
    assert sky.switches == np.count_nonzero(np.diff(applied)) > 10
    on_max = _camera_criterion(sim.run(t, y, z, stiffness=10.0, damping=bounds.c_max))
    on_min = _camera_criterion(sim.run(t, y, z, stiffness=10.0, damping=bounds.c_min))
    skyhook = _camera_criterion(ds)
    assert skyhook < 0.8 * on_max
    assert on_min < skyhook  # documented limitation: at these frequencies switching damping on costs isolation
