"""`uavdamp.damping.mr_batch.SpencerBatch` against `uavdamp.damping.dampers.SpencerMR` (the scalar scheme, itself
checked against Radau in tests/test_dampers.py): the same dampers on the same strokes give the same states and
forces to rounding, whatever each damper's voltage, and its Newton fails loudly as the scalar one does."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from uavdamp.contract import SolverFailed
from uavdamp.damping.dampers import V_MAX, SpencerMR, SpencerParams
from uavdamp.damping.mr_batch import SpencerBatch

PARAMS = SpencerParams.for_platform(1.0, 6.0)  # a payload element's damper (choice of the payload stage)
H = 5e-4  # s


def _strokes(n_axes: int, n_steps: int):
    """Strokes (m) and rates (m s-1) at the samples: each axis a 7 Hz sine of its own amplitude (0.05-2 mm, past
    the damper's yield) and phase, plus a 95 Hz line."""
    rng = np.random.default_rng(11)
    t = np.arange(n_steps + 1) * H
    amp, phase = rng.uniform(5e-5, 2e-3, n_axes), rng.uniform(0, 2 * np.pi, n_axes)
    w1, w2 = 2 * np.pi * 7.0, 2 * np.pi * 95.0
    x = amp * np.sin(w1 * t[:, None] + phase) + 2e-5 * np.sin(w2 * t[:, None])
    xd = amp * w1 * np.cos(w1 * t[:, None] + phase) + 2e-5 * w2 * np.cos(w2 * t[:, None])
    return x, xd


def _exponent(params: SpencerParams, n: float) -> SpencerParams:
    """The damper with Bouc-Wen exponent n, gamma and beta rescaled to keep its z_max."""
    share = params.gamma / (params.gamma + params.beta)
    total = params.A / params.z_max**n
    return dataclasses.replace(params, n=n, gamma=share * total, beta=(1 - share) * total)


VARIANTS = {
    "published": PARAMS,  # n = 2, no preload (x0 = 0)
    "preloaded": SpencerParams.for_platform(1.0, 6.0, preload=True),  # x0 != 0: the accumulator's offset
    "exponent 3": _exponent(PARAMS, 3.0),  # the general |z|^(n - 1) branch
}


@pytest.mark.parametrize("variant", list(VARIANTS))
@pytest.mark.parametrize("max_substep", [H, H / 3])
def test_the_batch_is_the_scalar_damper_axis_by_axis(max_substep, variant):
    """Six dampers, each at its own voltage (0 to V_MAX, one switching every 20 steps), 400 steps of 0.5 ms, for the
    published damper scaled, the same with its preload and with exponent 3 (`VARIANTS`): the
    end forces, step means and states equal `SpencerMR`'s, one axis at a time, within 1e-12 of their ranges
    (measured 1.3e-14 at worst; seen failing with the filtered command's decay taken over the whole step at the first
    stage)."""
    n, steps = 6, 400
    x, xd = _strokes(n, steps)
    volts = np.linspace(0.0, V_MAX, n)
    params = VARIANTS[variant]
    batch = SpencerBatch(params, n, max_substep)
    scalar = [SpencerMR(params, n_axes=1, max_substep=max_substep) for _ in range(n)]
    got = np.empty((steps, 3, n))
    expected = np.empty_like(got)
    for k in range(steps):
        v = volts.copy()
        v[0] = V_MAX if (k // 20) % 2 else 0.0
        end, mean = batch.step(H, v, x[k], xd[k], x[k + 1], xd[k + 1])
        got[k] = end, mean, batch.z
        for i, d in enumerate(scalar):
            expected[k, 0, i] = d.step(H, v[i], x[k, i], xd[k, i], x[k + 1, i], xd[k + 1, i])[0]
            expected[k, 1, i], expected[k, 2, i] = d.force_mean[0], d.z[0]
    span = np.abs(expected).max(axis=(0, 2))
    assert np.abs(expected[:, 2]).max() > 0.9 * params.z_max  # the dampers yield
    for j, name in enumerate(("end force", "mean force", "z")):
        assert np.abs(got[:, j] - expected[:, j]).max() <= 1e-12 * span[j], name
    np.testing.assert_allclose(batch.y, [d.y[0] for d in scalar], rtol=0, atol=1e-12 * np.abs(batch.y).max())
    np.testing.assert_allclose(batch.u, [d.u[0] for d in scalar], rtol=0, atol=1e-15)


def test_a_newton_that_cannot_converge_fails_naming_the_damper(monkeypatch):
    monkeypatch.setattr("uavdamp.damping.mr_batch.MAX_NEWTON", 1)
    x, xd = _strokes(2, 1)
    with pytest.raises(SolverFailed, match="Spencer MR damper: Newton did not converge"):
        SpencerBatch(PARAMS, 2).step(H, V_MAX, x[0], xd[0] * 1e3, x[1], xd[1] * 1e3)


@pytest.mark.parametrize(("build", "rule"), [
    (lambda: SpencerBatch(PARAMS, 2, max_substep=0.0), "max_substep: must be > 0"),
    (lambda: SpencerBatch(PARAMS, 2).step(0.0, 0.0, 0.0, 0.0, 0.0, 0.0), "time step: must be > 0"),
])  # fmt: skip
def test_a_bad_step_is_refused_naming_it(build, rule):
    with pytest.raises(ValueError, match=rule):
        build()
