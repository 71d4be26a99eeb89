"""Bouc-Wen hysteresis against its closed forms: the virgin loading curve (n = 1: exponential, n = 2: tanh), the
limit z_max = (A / (beta + gamma))^(1/n), the steady loop's dissipated energy for n = 1, and alpha = 1 a spring."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import trapezoid
from scipy.optimize import brentq

from uavdamp.platform.bouc_wen import BoucWen, hysteresis

# a wire-rope-like element (choice): 2 kN/m initial, 20 % post-yield, z_max = 1 / 400 m = 2.5 mm
K, ALPHA, BETA, GAMMA = 2000.0, 0.2, 300.0, 100.0


def ramp(params: BoucWen, stop: float, n: int = 2001):
    """A monotonic stroke 0 -> stop (m) in 1 s at constant rate."""
    time = np.linspace(0.0, 1.0, n)
    return time, stop * time, hysteresis(params, time, stop * time, stroke_rate=lambda t: stop)


def test_virgin_loading_n1_is_the_exponential_closed_form():
    """n = 1, z >= 0, x' > 0: dz/dx = A - (beta + gamma) z, so z = z_max (1 - exp(-(beta + gamma) x))."""
    bw = BoucWen(K, ALPHA, 1.0, BETA, GAMMA, 1.0)
    _, x, (force, z) = ramp(bw, 0.02)
    want = bw.z_max * (1 - np.exp(-(BETA + GAMMA) * x))
    np.testing.assert_allclose(z, want, rtol=0, atol=1e-6 * bw.z_max)
    np.testing.assert_allclose(force, ALPHA * K * x + (1 - ALPHA) * K * want, rtol=0, atol=1e-6 * K * bw.z_max)
    assert bw.z_max == pytest.approx(1 / (BETA + GAMMA), rel=1e-15)


def test_virgin_loading_n2_is_tanh_and_tends_to_z_max():
    """n = 2: dz/dx = A - (beta + gamma) z^2, so z = z_max tanh(sqrt(A (beta + gamma)) x), z_max = sqrt(A /
    (beta + gamma)); after a long stroke z sits at z_max (the skeleton's limiting force (1 - alpha) k z_max above
    the alpha k x line)."""
    beta, gamma, a = 3e5, 1e5, 1.0
    bw = BoucWen(K, ALPHA, a, beta, gamma, 2.0)
    _, x, (force, z) = ramp(bw, 0.02)
    z_max = math.sqrt(a / (beta + gamma))
    np.testing.assert_allclose(z, z_max * np.tanh(math.sqrt(a * (beta + gamma)) * x), rtol=0, atol=1e-6 * z_max)
    assert z[-1] == pytest.approx(z_max, rel=1e-6)
    assert bw.z_max == pytest.approx(z_max, rel=1e-15)
    assert force[-1] - ALPHA * K * x[-1] == pytest.approx((1 - ALPHA) * K * z_max, rel=1e-6)


def steady_loop_energy_n1(params: BoucWen, amplitude: float) -> float:
    """∮ F dx (J) of the steady loop between +-amplitude for n = 1, by hand. Loading from (-X, -z0) to (X, z0):
    dz/dx = A - b z with b = beta - gamma for z < 0 and beta + gamma for z > 0, so x(z) and ∫ z dx have closed
    forms; z0 makes the branch 2 X long; ∮ F dx = (1 - alpha) k ∮ z dx = 2 (1 - alpha) k ∫_branch z dx."""
    a, bm, bp = params.a, params.beta - params.gamma, params.beta + params.gamma

    def length_neg(z0):  # ∫_{-z0}^0 dz / (A - bm z)
        return math.log((a + bm * z0) / a) / bm if bm > 0 else z0 / a

    def length_pos(z0):  # ∫_0^{z0} dz / (A - bp z)
        return -math.log(1 - bp * z0 / a) / bp

    z0 = brentq(lambda z: length_neg(z) + length_pos(z) - 2 * amplitude, 1e-12, params.z_max * (1 - 1e-15))
    area_neg = -z0 / bm + a / bm**2 * math.log((a + bm * z0) / a) if bm > 0 else -(z0**2) / (2 * a)
    area_pos = -z0 / bp - a / bp**2 * math.log(1 - bp * z0 / a)
    return 2 * (1 - params.alpha) * params.stiffness * (area_neg + area_pos)


@pytest.mark.parametrize("amplitude", [1e-3, 5e-3])
def test_steady_loop_energy_n1_matches_the_closed_form(amplitude):
    """A slow cyclic stroke X sin(2 pi t), ten cycles (the start's offset from the steady loop decays by
    exp(-2 X (2 beta)) a cycle: < 1e-5 by then at X = 1 mm); the last loop's ∮ F x' dt (trapezoid on 2000 samples
    a cycle: error ~ (2 pi / 2000)^2 / 12 ~ 1e-6) against the closed form within 1e-5 (measured: 1.2e-7, 1.3e-8)."""
    bw = BoucWen(K, ALPHA, 1.0, BETA, GAMMA, 1.0)
    time = np.linspace(0.0, 10.0, 20001)
    x = amplitude * np.sin(2 * np.pi * time)
    rate = amplitude * 2 * np.pi * np.cos(2 * np.pi * time)
    force, _ = hysteresis(bw, time, x, stroke_rate=lambda t: amplitude * 2 * np.pi * math.cos(2 * np.pi * t))
    last = time >= 9.0
    energy = trapezoid(force[last] * rate[last], time[last])
    assert energy == pytest.approx(steady_loop_energy_n1(bw, amplitude), rel=1e-5)
    assert energy > 0  # dissipative


def test_alpha_one_is_a_linear_spring():
    bw = BoucWen(K, 1.0, 1.0, BETA, GAMMA, 1.5)
    time = np.linspace(0.0, 1.0, 501)
    x = 3e-3 * np.sin(2 * np.pi * 2 * time) + 1e-3 * time
    force, _ = hysteresis(bw, time, x)  # the rate from the samples' linear interpolation
    np.testing.assert_allclose(force, K * x, rtol=1e-14, atol=0)


def test_sampled_rate_converges_to_the_exact_rate():
    """Without a rate callable, the piecewise-linear stroke's slope: second order in the step, close to the exact
    loop at 2000 samples a cycle."""
    bw = BoucWen(K, ALPHA, 1.0, BETA, GAMMA, 1.0)
    time = np.linspace(0.0, 1.0, 2001)
    x = 4e-3 * np.sin(2 * np.pi * time)
    exact, _ = hysteresis(bw, time, x, stroke_rate=lambda t: 4e-3 * 2 * np.pi * math.cos(2 * np.pi * t))
    sampled, _ = hysteresis(bw, time, x)
    assert np.abs(sampled - exact).max() < 1e-3 * np.abs(exact).max()


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"stiffness": -1.0, "alpha": 0.5}, "stiffness_n_m"),
        ({"stiffness": 1.0, "alpha": 1.5}, "alpha"),
        ({"stiffness": 1.0, "alpha": 0.5, "beta": 1.0, "gamma": -2.0}, "beta, gamma"),
        ({"stiffness": 1.0, "alpha": 0.5, "beta": 1.0, "n": 0.5}, "a, n"),
    ],
)
def test_bad_parameters_are_refused_naming_the_key(kwargs, key):
    with pytest.raises(ValueError, match=key):
        BoucWen(**kwargs)
