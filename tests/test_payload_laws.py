"""Semi-active laws on the six-axis isolator (`uavdamp.study.payload_laws`): the skyhook adapter against the
constant-damping run it must reduce to, Karnopp's rule per element, and the isolator's closed forms it must beat
where skyhook is known to (Karnopp et al. 1974: resonance damped as by c_on, high frequencies passed as by c_off).
"""

from __future__ import annotations

import numpy as np
import pytest
from test_gimbal import _fit
from test_payload import _section, _time

from uavdamp.contract import MountMotion
from uavdamp.damping.laws import Skyhook
from uavdamp.platform.six_axis import strokes_matrix
from uavdamp.platform.six_axis_run import run, run_batch
from uavdamp.settings import ConfigError
from uavdamp.study import payload_laws as laws
from uavdamp.study import payload_runs as runs

SECTION = _section()
K, M = 4 * 500.0, 1.5  # N/m and kg: the four elements' vertical stiffness, the payload (tests/test_payload.py)


def _vertical(f: float, amplitude: float, duration: float = 3.0):
    t = _time(duration)
    translation = np.zeros((3, t.size))
    translation[2] = amplitude * np.sin(2 * np.pi * f * t)
    return t, MountMotion(translation, np.zeros((3, t.size)))


def _sdof(f: float, c_element: float) -> float:
    """|(k + j w c) / (k - m w^2 + j w c)| of the vertical mode, four elements of damping c_element each."""
    w, c = 2 * np.pi * f, 4 * c_element
    return abs((K + 1j * w * c) / (K - M * w**2 + 1j * w * c))


def test_skyhook_between_equal_dampings_is_the_constant_run():
    """c_on = c_off = 10 N s/m: the scheduled run is the isolator's own constant-damping run (`isolated_motion`)
    to rounding, rates included."""
    t = _time(1.0)
    u = np.zeros((6, t.size))
    u[1], u[3] = 1e-3 * np.sin(2 * np.pi * 7 * t), 2e-3 * np.sin(2 * np.pi * 11 * t)
    moved = MountMotion(u[:3], u[3:])
    isolator = runs.six_axis_isolator(SECTION, 10.0)
    ((body, on),) = laws.skyhook_motions(isolator, t, moved, [10.0], 10.0)
    constant = runs.isolated_motion(isolator, t, moved)
    np.testing.assert_allclose(body.coordinates, constant.coordinates, rtol=0, atol=1e-12)
    np.testing.assert_allclose(body.rates, constant.rates, rtol=0, atol=1e-10)
    assert on == 1.0 and body.peak_stroke == pytest.approx(constant.peak_stroke, rel=1e-9)


def test_each_element_follows_karnopps_rule_on_its_own_velocities():
    """Element 0 moving with its stroke along the payload's velocity (v_abs . v_rel > 0): c_on; element 1 against
    it: c_off; the others at rest: c_off (ties)."""
    isolator = runs.six_axis_isolator(SECTION, 1.0)
    n_el, t = isolator.n_elements, np.array([0.0, 1e-3])
    mount_rates = np.zeros((2, 6))
    mount_rates[0, 1] = 0.02  # the mount moves along y at 2 cm/s: at every element, (0, 0.02, 0)
    outputs = np.zeros(6 + 6 * n_el)
    rel = outputs[6 + 3 * n_el :].reshape(n_el, 3)
    rel[0] = (0.0, 0.01, 0.0)  # v_abs = (0, 0.03, 0): same sign as v_rel -> on
    rel[1] = (0.0, -0.01, 0.0)  # v_abs = (0, 0.01, 0): opposite -> off
    decide = laws.skyhook_schedule(isolator, t, mount_rates, Skyhook(100.0, 1.0, 1e-3))
    assert list(decide(0.0, outputs)) == [100.0, 1.0, 1.0, 1.0]
    assert strokes_matrix(isolator).shape == (3 * n_el, 6)


def test_skyhook_damps_the_resonance_and_passes_high_frequencies_as_its_off_state():
    """The vertical mode (sqrt(k / m) / 2 pi = 5.81 Hz) excited at resonance: skyhook (c_on 100, c_off 1 N s/m per
    element) keeps the payload below the closed form of the constant c_off (whose resonance it damps); at 30 Hz it
    passes less than the closed form of the constant c_on (whose damping force it mostly switches off)."""
    f_n = np.sqrt(K / M) / (2 * np.pi)
    isolator = runs.six_axis_isolator(SECTION, 1.0)
    for f, worse_than in ((f_n, 1.0), (30.0, 100.0)):
        t, moved = _vertical(f, 1e-4)
        ((body, _),) = laws.skyhook_motions(isolator, t, moved, [100.0], 1.0)
        ratio = _fit(t, body.coordinates[2], f, 1.5) / 1e-4
        assert ratio < 0.8 * _sdof(f, worse_than), (f, ratio, _sdof(f, worse_than))


def test_the_law_runs_are_named_by_their_on_damping_above_the_least_candidate():
    assert laws.law_names(SECTION) == [f"skyhook_{c:g}" for c in sorted(SECTION.damping)[1:]]
    assert laws.law_names(_section(mounts=["rigid", "yz"])) == []


class _Step:
    """A law whose demand steps from 1 to 31 N s/m at the 11th sample (each element alike)."""

    def __init__(self):
        self.calls = 0

    def decide_rows(self, v_abs, v_rel) -> np.ndarray:
        self.calls += 1
        return np.full(len(v_abs), 1.0 if self.calls <= 10 else 31.0)


@pytest.mark.parametrize("lag_s", [0.0, 2e-3, 2e-2])
def test_a_lagged_damper_follows_a_step_of_the_demand_as_a_first_order_lag(lag_s):
    """The schedule's C per step is the mean over the step of C(t) = d + (C0 - d) exp(-t / lag) (closed form, the
    demand d held over the step), C0 the value the lag reached at the step's start; lag 0: the demand itself (seen
    failing with the mean replaced by the step's start value: the ideal damper then came one step late)."""
    isolator = runs.six_axis_isolator(SECTION, 1.0)
    t = _time(0.02)
    h = float(t[1] - t[0])
    decide = laws.skyhook_schedule(isolator, t, np.zeros((t.size, 6)), _Step(), lag_s)
    outputs = np.zeros(6 + 6 * isolator.n_elements)
    got = np.array([decide(float(tk), outputs)[0] for tk in t[:30]])
    expected, c = [], 1.0
    for k in range(30):
        d = 1.0 if k < 10 else 31.0
        if lag_s == 0:
            expected.append(d)
            continue
        # mean of d + (c - d) exp(-s / lag) over s in [0, h], then c at the step's end
        expected.append(d + (c - d) * lag_s / h * (1 - np.exp(-h / lag_s)))
        c = d + (c - d) * np.exp(-h / lag_s)
    np.testing.assert_allclose(got, expected, rtol=1e-12)
    if lag_s > 0:  # explicitly: 19 steps after the step the start is 31 - 30 exp(-19 h / lag)
        start_distance = 30.0 * np.exp(-19 * h / lag_s)
        assert got[29] == pytest.approx(31.0 - start_distance * lag_s / h * (1 - np.exp(-h / lag_s)), rel=1e-12)


def test_the_skyhook_runs_off_damping_is_a_key_and_their_c_on_lie_above_it():
    """Default: c_off the least candidate (1 N s/m), c_on the others; skyhook_c_off_n_s_m 3: c_on 10, 30, 100; a
    c_off at or above every candidate leaves no c_on and is refused, naming the key."""
    assert laws.law_c_on(_section()) == [3.0, 10.0, 30.0, 100.0] and _section().c_off == 1.0
    assert laws.law_c_on(_section(skyhook_c_off_n_s_m=3.0)) == [10.0, 30.0, 100.0]
    assert laws.law_names(_section(skyhook_c_off_n_s_m=0.3)) == [f"skyhook_{c:g}" for c in (1, 3, 10, 30, 100)]
    with pytest.raises(ConfigError, match="payload.skyhook_c_off_n_s_m"):
        _section(skyhook_c_off_n_s_m=100.0)


def test_skyhooks_rows_are_its_decision_per_damper():
    """`Skyhook.decide_rows` is `decide` of each row (200 random velocity pairs in 3-D, and exact ties: c_off)."""
    rng = np.random.default_rng(7)
    v_abs, v_rel = rng.normal(size=(200, 3)), rng.normal(size=(200, 3))
    v_rel[:5] = 0.0  # ties
    law = Skyhook(30.0, 1.0, 1e-3)
    expected = [law.decide(a, r) for a, r in zip(v_abs, v_rel, strict=True)]
    np.testing.assert_array_equal(law.decide_rows(v_abs, v_rel), expected)
    assert 50 < np.sum(np.asarray(expected) == 30.0) < 150


def test_skyhook_runs_side_by_side_follow_karnopps_rule_and_their_own_held_c():
    """Three c_on (3, 30, 100 N s/m, c_off 1) side by side (`skyhook_motions`, one decision call a sample for all):
    each run's recorded C follows Karnopp's rule on that run's own element velocities (where v_abs . v_rel is clear
    of rounding), the runs differ, and each run's motion is the isolator's run held at its recorded C step by step
    (`six_axis_run.run` with that C as an array: the constant stretches' step maps, propagated), to rounding."""
    t = _time(0.5)
    u = np.zeros((6, t.size))
    u[1], u[2], u[4] = 1e-3 * np.sin(2 * np.pi * 7 * t), 8e-4 * np.sin(2 * np.pi * 9 * t), 2e-3 * np.sin(2 * np.pi * t)
    moved = MountMotion(u[:3], u[3:])
    isolator = runs.six_axis_isolator(SECTION, 1.0)
    h, rows, n_el = float(t[1] - t[0]), strokes_matrix(isolator), isolator.n_elements
    rates = np.vstack([np.diff(u, axis=1).T, np.diff(u, axis=1).T[-1:]]) / h
    decide = laws.skyhook_batch(isolator, t, rates, [Skyhook(c, 1.0, h) for c in (3.0, 30.0, 100.0)])
    found = run_batch(isolator, t, moved.translation, moved.rotation, decide, 3)
    shares = []
    for ds, c_on in zip(found, (3.0, 30.0, 100.0), strict=True):
        applied = ds.damping.values  # (n_semi, n)
        v_rel = ds.element_stroke_rate.values.transpose(2, 0, 1)  # (n, n_el, 3)
        v_abs = v_rel + (rates @ rows.T).reshape(-1, n_el, 3)
        power = np.sum(v_abs * v_rel, axis=2).T  # (n_el, n): every element semi-active
        clear = np.abs(power) > 1e-9 * np.abs(power).max()
        np.testing.assert_array_equal(applied[clear], np.where(power > 0, c_on, 1.0)[clear])
        shares.append(np.mean(applied[:, :-1] == c_on))
        held = run(isolator, t, moved.translation, moved.rotation, applied)
        for name in ("payload_translation", "payload_rotation", "payload_velocity"):
            scale = np.abs(held[name].values).max()
            np.testing.assert_allclose(ds[name].values, held[name].values, rtol=0, atol=1e-9 * scale)
    assert all(0.1 < s < 0.9 for s in shares), shares  # measured 0.88, 0.50, 0.33
    assert not np.array_equal(found[0].payload_rotation.values, found[2].payload_rotation.values)


@pytest.mark.parametrize("lag_s", [0.0, 2e-2])
def test_a_batch_decides_as_each_of_its_laws_alone(lag_s):
    """`skyhook_batch` over laws of different c_on and c_off gives, sample after sample, each law's own decision
    (`skyhook_schedule` of that law alone, itself checked against Karnopp's rule and the lag's closed form above)
    on random element velocities, exactly."""
    isolator = runs.six_axis_isolator(SECTION, 1.0)
    rng = np.random.default_rng(5)
    t = np.arange(200) * 1e-3
    rates = rng.normal(0.0, 0.02, (t.size, 6))
    chosen = [Skyhook(3.0, 1.0, 1e-3), Skyhook(30.0, 0.5, 1e-3), Skyhook(100.0, 2.0, 1e-3)]
    batch = laws.skyhook_batch(isolator, t, rates, chosen, lag_s)
    alone = [laws.skyhook_schedule(isolator, t, rates, law, lag_s) for law in chosen]
    for t_k in t:
        outputs = rng.normal(0.0, 0.02, (3, 6 + 6 * isolator.n_elements))
        got = batch(float(t_k), outputs)
        for b, decide in enumerate(alone):
            np.testing.assert_array_equal(got[b], decide(float(t_k), outputs[b]))
