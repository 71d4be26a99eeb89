"""Bouc-Wen hysteresis: the lateral force of a wire-rope isolator element under a prescribed stroke history.

    F = alpha k x + (1 - alpha) k z
    z' = A x' - beta |x'| |z|^(n - 1) z - gamma x' |z|^n

x the stroke (m), z the hysteretic displacement (m), k the initial stiffness (N m-1), alpha the post-yield to
initial stiffness ratio, A (1), beta and gamma (m^-n) the loop's shape and n its smoothness. Under a monotonic
stroke z tends to z_max = (A / (beta + gamma))^(1/n) (for beta + gamma > 0). The model is rate-independent; for
sharp loops (large beta, gamma or n) the z equation is stiff, so it is integrated by scipy's LSODA (switching
to a stiff method where needed) on the stroke's time grid, with the stroke rate interpolated between samples.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class BoucWen:
    """Parameters of one Bouc-Wen element (see the module docstring for the symbols and units)."""

    stiffness: float  # k, N m-1
    alpha: float  # 1, post-yield stiffness ratio, in [0, 1]
    a: float = 1.0  # A, 1
    beta: float = 0.0  # m^-n
    gamma: float = 0.0  # m^-n
    n: float = 1.0  # 1, >= 1

    def __post_init__(self):
        where = "platform.six_axis.bouc_wen."
        for name, value in vars(self).items():
            if not math.isfinite(value):
                raise ValueError(f"{where}{name}: must be finite, got {value}")
        if self.stiffness <= 0:
            raise ValueError(f"{where}stiffness_n_m: must be > 0, got {self.stiffness}")
        if not 0 <= self.alpha <= 1:
            raise ValueError(f"{where}alpha: must lie in [0, 1], got {self.alpha}")
        if self.a <= 0 or self.n < 1:
            raise ValueError(f"{where}a, n: need A > 0 and n >= 1, got {self.a}, {self.n}")
        if not (self.beta > 0 and -self.beta < self.gamma <= self.beta):
            raise ValueError(
                f"{where}beta, gamma: need beta > 0 and -beta < gamma <= beta (a bounded, dissipative loop), "
                f"got {self.beta}, {self.gamma}"
            )

    @property
    def z_max(self) -> float:
        """The hysteretic displacement's limit under a monotonic stroke, m: (A / (beta + gamma))^(1/n)."""
        return (self.a / (self.beta + self.gamma)) ** (1.0 / self.n)

    def z_rate(self, z: float, x_rate: float) -> float:
        """z' (m s-1) at hysteretic displacement z (m) and stroke rate x' (m s-1)."""
        az = abs(z)
        return self.a * x_rate - (self.beta * abs(x_rate) * az ** (self.n - 1) * z + self.gamma * x_rate * az**self.n)

    def force(self, x, z) -> np.ndarray:
        """F (N) at stroke x and hysteretic displacement z (m)."""
        return self.alpha * self.stiffness * np.asarray(x) + (1 - self.alpha) * self.stiffness * np.asarray(z)


def hysteresis(
    params: BoucWen,
    time,
    stroke,
    stroke_rate: Callable[[float], float] | None = None,
    z0: float = 0.0,
    rtol: float = 1e-8,
) -> tuple[np.ndarray, np.ndarray]:
    """(F N, z m) on `time` (s) for the stroke samples (m) there, from z(time[0]) = z0. The stroke rate is a
    callable of t (m s-1) when given (exact), otherwise the slope of the stroke's linear interpolation."""
    from scipy.integrate import solve_ivp

    t = np.asarray(time, dtype=float)
    x = np.asarray(stroke, dtype=float)
    if t.ndim != 1 or t.shape != x.shape or t.size < 2 or np.any(np.diff(t) <= 0):
        raise ValueError("time, stroke: must be 1-D arrays of one shape, time increasing, at least 2 samples")
    if stroke_rate is None:
        slopes = np.diff(x) / np.diff(t)

        def stroke_rate(s: float) -> float:
            return float(slopes[min(max(np.searchsorted(t, s, side="right") - 1, 0), slopes.size - 1)])

    scale = params.z_max
    solution = solve_ivp(
        lambda s, z: [params.z_rate(z[0], stroke_rate(s))],
        (t[0], t[-1]),
        [z0],
        method="LSODA",
        t_eval=t,
        rtol=rtol,
        atol=rtol * scale,
        max_step=float(np.min(np.diff(t))),  # a step never jumps over a sample (a kink of the interpolated rate)
    )
    if not solution.success:
        raise RuntimeError(f"Bouc-Wen integration failed: {solution.message}")
    z = solution.y[0]
    return params.force(x, z), z
