"""`uavdamp.damping.dampers.SpencerMR`, stepped by the compiled scheme (`uavdamp.damping.spencer_kernel`), against the
same scheme written out here in plain Python floats, one damper at a time (the scheme itself is checked against
Radau in tests/test_dampers.py): many dampers on the same strokes give the same states and forces to rounding,
whatever each damper's voltage, and its Newton fails loudly."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from uavdamp.contract import SolverFailed
from uavdamp.damping.dampers import V_MAX, SpencerMR, SpencerParams

PARAMS = SpencerParams.for_platform(1.0, 6.0)  # a payload element's damper (choice of the payload stage)
H = 5e-4  # s
GAMMA = 1.0 - math.sqrt(0.5)  # Alexander's two-stage L-stable SDIRK (Alexander 1977): abscissae gamma and 1


def _hermite(s: float, h: float, x0: float, xd0: float, x1: float, xd1: float) -> tuple[float, float]:
    """(x, x') of the cubic Hermite interpolant at the fraction s of the step h."""
    h00, h10, h01, h11 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
    d00, d10, d01, d11 = 6 * s**2 - 6 * s, 3 * s**2 - 4 * s + 1, -6 * s**2 + 6 * s, 3 * s**2 - 2 * s
    return h00 * x0 + h10 * h * xd0 + h01 * x1 + h11 * h * xd1, (d00 * x0 + d01 * x1) / h + d10 * xd0 + d11 * xd1


def _rates(p: SpencerParams, y: float, z: float, x: float, xd: float, u: float) -> tuple[float, float]:
    """(y', z') of Spencer et al.'s equations (the module docstring of `uavdamp.damping.dampers`)."""
    alpha, c0, c1 = p.alpha_a + p.alpha_b * u, p.c0a + p.c0b * u, p.c1a + p.c1b * u
    yd = (alpha * z + c0 * xd + p.k0 * (x - y)) / (c0 + c1)
    w = xd - yd
    return yd, -p.gamma * abs(w) * z * abs(z) ** (p.n - 1) - p.beta * w * abs(z) ** p.n + p.A * w


def _implicit(p, r_y: float, r_z: float, a: float, x: float, xd: float, u: float) -> tuple[float, float]:
    """(y, z) = (r_y, r_z) + a (y', z')(y, z): Newton on both unknowns with a finite-difference-free 2x2 Jacobian
    (the other route than the kernel's elimination of y), to 1e-15 of z_max."""
    y, z = r_y, r_z
    alpha, c0, c1 = p.alpha_a + p.alpha_b * u, p.c0a + p.c0b * u, p.c1a + p.c1b * u
    for _ in range(60):
        yd, zd = _rates(p, y, z, x, xd, u)
        w = xd - yd
        dyd_dy, dyd_dz = -p.k0 / (c0 + c1), alpha / (c0 + c1)
        dzd_dw = -p.gamma * math.copysign(1.0, w) * z * abs(z) ** (p.n - 1) - p.beta * abs(z) ** p.n + p.A
        dzd_dz = -p.n * abs(z) ** (p.n - 1) * (p.gamma * abs(w) + p.beta * w * math.copysign(1.0, z))
        jac = np.array([[1 - a * dyd_dy, -a * dyd_dz], [a * dzd_dw * dyd_dy, 1 - a * (dzd_dz - dzd_dw * dyd_dz)]])
        dy, dz = np.linalg.solve(jac, [y - r_y - a * yd, z - r_z - a * zd])
        y, z = y - dy, z - dz
        if abs(dz) < 1e-15 * p.z_max and abs(dy) < 1e-15 * max(abs(y), 1e-9):
            break
    return y, z


def _reference_step(p, state, v: float, h: float, n_sub: int, stroke) -> tuple[tuple, float, float]:
    """One damper over h: ((y, z, u) at the end, F at the end, the trapezoidal mean of F on the sub-steps)."""
    y, z, u = state
    dt = h / n_sub

    def force(y, z, u, x, xd):
        return (p.c1a + p.c1b * u) * _rates(p, y, z, x, xd, u)[0] + p.k1 * (x - p.x0)

    forces = [force(y, z, u, stroke[0], stroke[1])]
    for k in range(n_sub):
        u_stage = v + (u - v) * math.exp(-p.eta * GAMMA * dt)  # the command filter, exact at the stage's time
        y1, z1 = _implicit(p, y, z, GAMMA * dt, *_hermite((k + GAMMA) / n_sub, h, *stroke), u_stage)
        ky, kz = (y1 - y) / (GAMMA * dt), (z1 - z) / (GAMMA * dt)
        u = v + (u - v) * math.exp(-p.eta * dt)
        x, xd = _hermite((k + 1) / n_sub, h, *stroke)
        y, z = _implicit(p, y + (1 - GAMMA) * dt * ky, z + (1 - GAMMA) * dt * kz, GAMMA * dt, x, xd, u)
        forces.append(force(y, z, u, x, xd))
    return (y, z, u), forces[-1], (sum(forces) - 0.5 * (forces[0] + forces[-1])) / n_sub


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
@pytest.mark.parametrize("n_sub", [1, 3])
def test_the_compiled_dampers_are_the_scheme_written_out_damper_by_damper(n_sub, variant):
    """Six dampers in one `SpencerMR`, each at its own voltage (0 to V_MAX, one switching every 20 steps), 150 steps
    of 0.5 ms in 1 or 3 sub-steps, for the published damper scaled, the same with its preload and with exponent 3
    (`VARIANTS`): the end forces, step means and states equal the plain-Python scheme's within 1e-11 of their
    ranges (Newton's stopping steps, 1e-13 z_max, carried over 150 steps). Seen failing with the filtered command's
    decay taken over the whole sub-step at the first stage, and with the first stage at the sub-step's start."""
    n, steps = 6, 150
    x, xd = _strokes(n, steps)
    volts = np.linspace(0.0, V_MAX, n)
    params = VARIANTS[variant]
    dampers = SpencerMR(params, n_axes=n, max_substep=H / n_sub)
    states = [(0.0, 0.0, 0.0)] * n
    got, expected = np.empty((steps, 3, n)), np.empty((steps, 3, n))
    for k in range(steps):
        v = volts.copy()
        v[0] = V_MAX if (k // 20) % 2 else 0.0
        got[k, 0] = dampers.step(H, v, x[k], xd[k], x[k + 1], xd[k + 1])
        got[k, 1], got[k, 2] = dampers.force_mean, dampers.z
        for i in range(n):
            stroke = (x[k, i], xd[k, i], x[k + 1, i], xd[k + 1, i])
            states[i], expected[k, 0, i], expected[k, 1, i] = _reference_step(params, states[i], v[i], H, n_sub, stroke)
            expected[k, 2, i] = states[i][1]
    span = np.abs(expected).max(axis=(0, 2))
    assert np.abs(expected[:, 2]).max() > 0.9 * params.z_max  # the dampers yield
    for j, name in enumerate(("end force", "mean force", "z")):
        assert np.abs(got[:, j] - expected[:, j]).max() <= 1e-11 * span[j], name
    y = np.array([s[0] for s in states])
    np.testing.assert_allclose(dampers.y, y, rtol=0, atol=1e-11 * np.abs(y).max())
    np.testing.assert_allclose(dampers.u, [s[2] for s in states], rtol=0, atol=1e-15)


def test_a_newton_that_cannot_converge_fails_naming_the_damper():
    from uavdamp.damping import spencer_kernel

    x, xd = _strokes(2, 1)
    dampers = SpencerMR(PARAMS, 2)
    stroke = (x[0], xd[0] * 1e3, x[1], xd[1] * 1e3)
    rule = r"Spencer MR damper: Newton did not converge in 1 iterations on damper [01] of 2 \(\|dz\| = "
    with pytest.raises(SolverFailed, match=rule):
        spencer_kernel.step(dampers._packed, (dampers.y, dampers.z, dampers.u), V_MAX, H, H, stroke, max_iter=1)


def test_the_coupled_step_fails_naming_the_damper_too():
    from uavdamp.damping import spencer_kernel

    x, xd = _strokes(2, 1)
    dampers = SpencerMR(PARAMS, 2)
    free_end, g_rows = np.concatenate([x[1], xd[1] * 1e3]), np.zeros((4, 2))  # the plant moves the strokes alone
    rule = r"Spencer MR damper: Newton did not converge in 1 iterations on damper [01] of 2 \(\|dz\| = "
    with pytest.raises(SolverFailed, match=rule):
        spencer_kernel.coupled_step(
            dampers._packed, (dampers.y, dampers.z, dampers.u), V_MAX, H, H, (x[0], xd[0] * 1e3), free_end, g_rows, 1
        )
    with pytest.raises(ValueError, match="time step: must be > 0"):
        dampers.coupled_step(0.0, 0.0, (x[0], xd[0]), free_end, g_rows)


@pytest.mark.parametrize(("build", "rule"), [
    (lambda: SpencerMR(PARAMS, 2, max_substep=0.0), "max_substep: must be > 0"),
    (lambda: SpencerMR(PARAMS, 2).step(0.0, 0.0, 0.0, 0.0, 0.0, 0.0), "time step: must be > 0"),
])  # fmt: skip
def test_a_bad_step_is_refused_naming_it(build, rule):
    with pytest.raises(ValueError, match=rule):
        build()
