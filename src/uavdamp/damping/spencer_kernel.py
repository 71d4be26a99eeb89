"""The Spencer MR damper's step, compiled with numba: the scheme of `uavdamp.damping.dampers` (module docstring:
two-stage L-stable SDIRK per sub-step on the stroke's cubic Hermite interpolant, y eliminated, Newton in z, the
filtered command exact for a held voltage) for many independent dampers in one call.

`dampers.SpencerMR` steps its dampers through `step` (the platform's two axes in the benchmark, every damper of the
payload's runs side by side in `uavdamp.platform.six_axis_force`); `tests/test_spencer_kernel.py` checks it against
the scheme written out in plain Python, and `tests/test_dampers.py` the scheme against Radau. Compiled once per
machine (``cache=True``: numba keeps the machine code beside this file; 1.5 s the first time, imports included),
a stage solve of 96 dampers took 7 us against 110 us for the numpy arrays it replaced (measured at c9e4420; a
whole step now: `benchmarks/bench_spencer.py`).
"""

from __future__ import annotations

import math

import numpy as np

from uavdamp import compiled
from uavdamp.contract import SolverFailed

# the parameters' order in the packed array (`packed`): `dampers.SpencerParams`' fields
PARAMETERS = ("c0a", "c0b", "k0", "c1a", "c1b", "k1", "x0", "alpha_a", "alpha_b", "gamma", "beta", "A", "n", "eta")
SDIRK_GAMMA = 1.0 - math.sqrt(0.5)  # Alexander's two-stage L-stable SDIRK: stage abscissae gamma and 1
# numba on first use (`uavdamp.compiled`), callees first
COMPILED = ("force", "forces", "_hermite", "_sign", "_stage", "advance", "_stroke_end", "couple")


def packed(params) -> np.ndarray:
    """A `SpencerParams` as the float array (`PARAMETERS`' order) the compiled functions take."""
    return np.array([float(getattr(params, k)) for k in PARAMETERS])


def force(par, y, z, u, x, xd):
    """F (N) to move the stroke x (m) at x' (m s-1) at the states y (m), z (m), u (V); par: `packed`."""
    alpha, c0, c1 = par[7] + par[8] * u, par[0] + par[1] * u, par[3] + par[4] * u
    return c1 * (alpha * z + c0 * xd + par[2] * (x - y)) / (c0 + c1) + par[5] * (x - par[6])


def forces(par, y, z, u, x, xd, out):
    """F (N) of every damper i at its states (y, z, u)[i] for the stroke x[i] (m) and rate xd[i] (m s-1), into out."""
    for i in range(y.size):
        out[i] = force(par, y[i], z[i], u[i], x[i], xd[i])


def _hermite(s, h, x0, xd0, x1, xd1):
    """(x, x') at the fraction s of a step h of the cubic with those end values and slopes."""
    s2, s3 = s * s, s * s * s
    x = (2 * s3 - 3 * s2 + 1) * x0 + (s3 - 2 * s2 + s) * h * xd0 + (3 * s2 - 2 * s3) * x1 + (s3 - s2) * h * xd1
    xd = ((6 * s2 - 6 * s) * (x0 - x1)) / h + (3 * s2 - 4 * s + 1) * xd0 + (3 * s2 - 2 * s) * xd1
    return x, xd


def _sign(value):
    return 1.0 if value > 0 else (-1.0 if value < 0 else 0.0)


def _stage(par, r_y, r_z, a, x, xd, u, scale, max_iter):
    """(y, z, |last Newton step|) with (y, z) = (r_y, r_z) + a (y', z') at the filtered command u (V): y = q + a m z
    eliminated, Newton in z until a step is within `scale` (m); the last step's size tells a failure (> scale)."""
    alpha, c0, c1 = par[7] + par[8] * u, par[0] + par[1] * u, par[3] + par[4] * u
    den = c0 + c1 + a * par[2]
    m = alpha / den
    q = ((c0 + c1) * r_y + a * (c0 * xd + par[2] * x)) / den
    w0 = xd - (q - r_y) / a  # x' - y' = w0 - m z
    gam, bet, big_a, n = par[9], par[10], par[11], par[12]
    z, step = r_z, math.inf
    for _ in range(max_iter):
        w = w0 - m * z
        az, aw = abs(z), abs(w)
        zn1 = az if n == 2.0 else az ** (n - 1.0)
        g = big_a * w - (gam * aw * z + bet * w * az) * zn1
        dg_dz = -n * zn1 * (gam * aw + bet * w * _sign(z))
        dg_dw = big_a - (gam * _sign(w) * z + bet * az) * zn1
        step = (z - r_z - a * g) / (1.0 - a * (dg_dz - m * dg_dw))
        z -= step
        if abs(step) <= scale:
            break
    return q + a * m * z, z, abs(step)


def advance(par, y, z, u, v, h, n_sub, x0, xd0, x1, xd1, tolerance, max_iter, f_end, f_mean):
    """Advance every damper i over h (s) in n_sub sub-steps at its held voltage v[i] (V) on the Hermite stroke of
    (x0, xd0) to (x1, xd1) (m, m s-1): y, z, u (arrays, m, m, V) in place, the force at the step's end into f_end
    and its step mean (trapezoidal rule on the sub-steps) into f_mean (N). Returns (-1, 0.0), or (the first damper
    whose Newton did not converge within `tolerance` of z_max in max_iter iterations, its last step's size, m)."""
    scale = tolerance * (par[11] / (par[9] + par[10])) ** (1.0 / par[12])  # z_max = (A / (gamma + beta))^(1/n), m
    g, dt = SDIRK_GAMMA, h / n_sub
    a, decay, decay_g = g * dt, math.exp(-par[13] * dt), math.exp(-par[13] * g * dt)
    for i in range(y.size):
        yi, zi, ui, vi = y[i], z[i], u[i], v[i]
        total = 0.5 * force(par, yi, zi, ui, x0[i], xd0[i])
        f = 0.0
        for k in range(n_sub):
            x, xd = _hermite((k + g) / n_sub, h, x0[i], xd0[i], x1[i], xd1[i])
            y1, z1, miss = _stage(par, yi, zi, a, x, xd, vi + (ui - vi) * decay_g, scale, max_iter)
            if miss > scale:
                return i, miss
            ky, kz = (y1 - yi) / a, (z1 - zi) / a
            if k < n_sub - 1:
                x, xd = _hermite((k + 1.0) / n_sub, h, x0[i], xd0[i], x1[i], xd1[i])
            else:
                x, xd = x1[i], xd1[i]
            ui = vi + (ui - vi) * decay
            yi, zi, miss = _stage(par, yi + (1 - g) * dt * ky, zi + (1 - g) * dt * kz, a, x, xd, ui, scale, max_iter)
            if miss > scale:
                return i, miss
            f = force(par, yi, zi, ui, x, xd)
            total += f if k < n_sub - 1 else 0.5 * f
        y[i], z[i], u[i], f_end[i], f_mean[i] = yi, zi, ui, f, total / n_sub
    return -1, 0.0


def _stroke_end(free_end, g_rows, f, x1, xd1):
    """The stroke x1 (m) and rate xd1 (m s-1) at a step's end under the forces f (N): free_end - g_rows f, its first
    half the strokes, its second the rates."""
    n = f.size
    for r in range(n):
        s, sd = 0.0, 0.0
        for c in range(n):
            s += g_rows[r, c] * f[c]
            sd += g_rows[n + r, c] * f[c]
        x1[r], xd1[r] = free_end[r] - s, free_end[n + r] - sd


def couple(par, y, z, u, v, h, n_sub, x0, xd0, free_end, g_rows, tolerance, max_iter, f_end, f_mean):
    """`uavdamp.platform.force_coupling`'s predictor-corrector step of these dampers in one call: the stroke at the
    step's end predicted from the forces at its start (free_end - g_rows F), the dampers stepped on it from a copy of
    their states (`advance`) for their step mean, the stroke corrected with that mean, and the dampers stepped on it
    in place. free_end (2n,): the plant's strokes then rates at the step's end without a damper force; g_rows (2n, n):
    their response to a unit force held over the step. f_end, f_mean as `advance`'s; returns what it returns."""
    n = y.size
    x1, xd1 = np.empty(n), np.empty(n)
    for i in range(n):
        f_end[i] = force(par, y[i], z[i], u[i], x0[i], xd0[i])
    _stroke_end(free_end, g_rows, f_end, x1, xd1)
    ys, zs, us = y.copy(), z.copy(), u.copy()
    bad, miss = advance(par, ys, zs, us, v, h, n_sub, x0, xd0, x1, xd1, tolerance, max_iter, f_end, f_mean)
    if bad >= 0:
        return bad, miss
    _stroke_end(free_end, g_rows, f_mean, x1, xd1)
    return advance(par, y, z, u, v, h, n_sub, x0, xd0, x1, xd1, tolerance, max_iter, f_end, f_mean)


MAX_NEWTON = 30  # Newton iterations per stage before giving up
NEWTON_TOL = 1e-13  # of z_max: the Newton step at which a stage stops (its root to rounding)


def _per_damper(voltage, stroke, n: int) -> np.ndarray:
    """The voltage and the stroke (x0, xd0, x1, xd1), scalars or (n,) each, as the rows of one new contiguous float
    (5, n) array (a read-only or strided row would be another signature for numba: another compilation)."""
    rows = np.empty((5, n))
    rows[0] = voltage
    rows[1], rows[2], rows[3], rows[4] = stroke
    return rows


def _sub_steps(h: float, max_substep: float) -> int:
    """ceil(h / max_substep) sub-steps of a step h (s), kernels compiled (`uavdamp.compiled`); ValueError if h <= 0."""
    if not h > 0:
        raise ValueError(f"time step: must be > 0, got {h}")
    compiled.jit(globals(), COMPILED)
    return max(1, math.ceil(h / max_substep - 1e-9))


def _not_converged(bad: int, n: int, miss: float, max_iter: int, stroke: str) -> SolverFailed:
    """The error naming damper `bad` of n whose Newton stopped |dz| = miss (m) short after max_iter iterations."""
    return SolverFailed(
        f"Spencer MR damper: Newton did not converge in {max_iter} iterations on damper {bad} of {n} "
        f"(|dz| = {miss:.3g} m, {stroke})"
    )


def force_at(par: np.ndarray, states, x, xd) -> np.ndarray:
    """F (N), (n,), of n dampers at their states (y m, z m, u V: (n,) arrays each) for the stroke x (m) and rate xd
    (m s-1), scalars or (n,) each."""
    y, z, u = states
    rows = np.empty((2, y.size))
    rows[0], rows[1] = x, xd
    compiled.jit(globals(), COMPILED)
    out = np.empty(y.size)
    forces(par, y, z, u, rows[0], rows[1], out)
    return out


def coupled_step(
    par: np.ndarray, states, voltage: float, h: float, max_substep: float, start, free_end, g_rows, max_iter=MAX_NEWTON
):
    """`couple` for n dampers of one `SpencerParams` (par: `packed`) at their held `voltage` (V) from the stroke
    `start` = (x0 m, xd0 m s-1), (n,) each, over h (s) in ceil(h / max_substep) sub-steps: states (y, z, u) in place.
    Returns (F at the end, F averaged over the step), N, (n,) each. SolverFailed as `step`."""
    n_sub = _sub_steps(h, max_substep)
    y, z, u = states
    n = y.size
    x0, xd0 = start
    v = np.full(n, float(voltage))
    f_end, f_mean = np.empty(n), np.empty(n)
    bad, miss = couple(par, y, z, u, v, h, n_sub, x0, xd0, free_end, g_rows, NEWTON_TOL, max_iter, f_end, f_mean)
    if bad >= 0:
        raise _not_converged(
            bad, n, miss, max_iter, f"stroke rate {xd0[bad]:.3g} m/s at the step's start, at {voltage:.3g} V"
        )
    return f_end, f_mean


def step(par: np.ndarray, states, voltage, h: float, max_substep: float, stroke, max_iter: int = MAX_NEWTON):
    """Advance n dampers of one `SpencerParams` (par: `packed`) over h (s) in ceil(h / max_substep) equal sub-steps
    (choice) at their held `voltage` (V, scalar or (n,)): states (y m, z m, u V), (n,) arrays each, in place;
    stroke (x0, xd0, x1, xd1) m and m s-1 at the step's start and end (scalars or (n,)). Returns (F at the end, F
    averaged over the step), N, (n,) each. SolverFailed when a Newton does not converge (states partly advanced)."""
    n_sub = _sub_steps(h, max_substep)
    y, z, u = states
    n = y.size
    v, x0, xd0, x1, xd1 = _per_damper(voltage, stroke, n)
    f_end, f_mean = np.empty(n), np.empty(n)
    bad, miss = advance(par, y, z, u, v, h, n_sub, x0, xd0, x1, xd1, NEWTON_TOL, max_iter, f_end, f_mean)
    if bad >= 0:
        raise _not_converged(
            bad, n, miss, max_iter, f"stroke rate {xd0[bad]:.3g} to {xd1[bad]:.3g} m/s at {v[bad]:.3g} V"
        )
    return f_end, f_mean
