"""Linear time-invariant plant in state space: exact discretisation and exact sine responses.

The plant is z' = A z + B w, y = C z + Du u + Dv v with the input w = (u, v): u the prescribed mount
coordinates (m inputs: m or rad) and v their rates. Two exact solutions are provided:

- `discretise`: the input on a time grid of step h with u piecewise linear between samples (first-order
  hold) and v = its slope (piecewise constant). The augmented system `[z; u; v]' = [[A, Bu, Bv], [0, 0, I],
  [0, 0, 0]] [z; u; v]` is exact for such an input, so one matrix exponential gives the step map.
- `sine_outputs`: u = a sin(omega t) e_axis, v = a omega cos(omega t) e_axis exactly (not sampled): the
  particular solution Im(G exp(i omega t)) with G = (i omega I - A)^-1 B w_hat plus the free response
  exp(A t)(z0 - Im G), sampled at t = k h by powers of exp(A h). Vectorised over frequencies.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm


@dataclass(frozen=True)
class StateSpace:
    """Continuous plant: a (ns, ns) 1/s, b (ns, 2 m) over (u_1 .. u_m, v_1 .. v_m), outputs c (no, ns),
    du (no, m), dv (no, m); the output units are those of the rows (m, rad, m s-1)."""

    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    du: np.ndarray
    dv: np.ndarray

    @property
    def n_states(self) -> int:
        return self.a.shape[0]


@dataclass(frozen=True)
class Discrete:
    """Step map of one time step h: z_{k+1} = phi z_k + gamma_u u_k + gamma_v v_k (v_k: slope on the step)."""

    phi: np.ndarray
    gamma_u: np.ndarray
    gamma_v: np.ndarray


def discretise(plant: StateSpace, h: float) -> Discrete:
    """Exact step map for a first-order-hold displacement u and its piecewise-constant slope v (step h, s)."""
    ns, m = plant.n_states, plant.du.shape[1]
    big = np.zeros((ns + 2 * m, ns + 2 * m))
    big[:ns, :ns] = plant.a
    big[:ns, ns:] = plant.b
    big[ns : ns + m, ns + m :] = np.eye(m)  # u' = v, v' = 0 on a step
    e = expm(big * h)
    return Discrete(phi=e[:ns, :ns], gamma_u=e[:ns, ns : ns + m], gamma_v=e[:ns, ns + m :])


@dataclass(frozen=True)
class Lifted:
    """A step map lifted to blocks of m steps: powers phi^0..phi^m (m + 1, ns, ns) and the block Toeplitz
    matrix (m ns, m ns) from a block's forcing (step l, state t) to its states' forced part (i-th state, s)."""

    powers: np.ndarray
    toeplitz: np.ndarray


def lift(phi: np.ndarray, m: int = 32) -> Lifted:
    """Lift a step map phi to blocks of m steps (see `propagate`)."""
    ns = phi.shape[0]
    powers = np.empty((m + 1, ns, ns))
    powers[0] = np.eye(ns)
    for i in range(1, m + 1):
        powers[i] = powers[i - 1] @ phi
    state, force = np.meshgrid(np.arange(1, m + 1), np.arange(m), indexing="ij")
    lag = state - 1 - force  # the i-th state after a block's start gets phi^lag of its forcing l, for lag >= 0
    blocks = np.where((lag >= 0)[..., None, None], powers[np.maximum(lag, 0)], 0.0)  # (i, l, s, t)
    return Lifted(powers=powers, toeplitz=blocks.transpose(0, 2, 1, 3).reshape(m * ns, m * ns))


def propagate(step: Discrete, z0: np.ndarray, u: np.ndarray, v: np.ndarray, lifted: Lifted | None = None) -> np.ndarray:
    """States (len(u) + 1, ns) from z0 over len(u) steps; u (steps, m) at the step starts, v (steps, m) slopes.

    With `lifted` (of step.phi), blocks of m steps cost one matrix product each instead of m Python steps.
    """
    forcing = u @ step.gamma_u.T + v @ step.gamma_v.T
    n, ns = forcing.shape[0], z0.size
    z = np.empty((n + 1, ns))
    z[0] = z0
    if lifted is None:
        phi_t = step.phi.T
        for k in range(n):
            z[k + 1] = z[k] @ phi_t + forcing[k]
        return z
    m = lifted.powers.shape[0] - 1
    n_blocks = -(-n // m)
    padded = np.zeros((n_blocks * m, ns))  # forcing after the end changes no state before it
    padded[:n] = forcing
    forced = (padded.reshape(n_blocks, m * ns) @ lifted.toeplitz.T).reshape(n_blocks, m, ns)
    heads = np.empty((n_blocks, ns))  # the state at each block's start
    heads[0] = z0
    for j in range(1, n_blocks):
        heads[j] = lifted.powers[m] @ heads[j - 1] + forced[j - 1, -1]
    states = np.einsum("ist,jt->jis", lifted.powers[1:], heads) + forced
    z[1:] = states.reshape(-1, ns)[:n]
    return z


def free_response_rows(c: np.ndarray, phi: np.ndarray, n_samples: int, block: int = 64) -> np.ndarray:
    """c phi^k for k = 0 .. n_samples - 1: (n_samples, no, ns); blocks of powers keep the Python loop short."""
    block = max(1, min(block, n_samples))
    powers = np.empty((block, *phi.shape))
    powers[0] = np.eye(phi.shape[0])
    for i in range(1, block):
        powers[i] = powers[i - 1] @ phi
    jump = powers[-1] @ phi  # phi^block
    heads = np.empty((-(-n_samples // block), *c.shape))
    heads[0] = c
    for j in range(1, heads.shape[0]):
        heads[j] = heads[j - 1] @ jump
    rows = np.einsum("jrs,ist->jirt", heads, powers).reshape(-1, *c.shape)
    return rows[:n_samples]


def sine_outputs(
    plant: StateSpace,
    free: np.ndarray,
    freq_hz: np.ndarray,
    axis: int,
    amplitude: float,
    z0: np.ndarray,
    steps: np.ndarray,
    h: float,
    rows: list[int],
) -> np.ndarray:
    """Outputs `rows` at t = k h (s), k in `steps`, for u = amplitude sin(2 pi f t) on input `axis` (an index).

    Each frequency alone; free = `free_response_rows(c[rows], exp(A h), ...)[steps]`; z0 (ns, nf): the
    initial state per frequency. Returns (steps, rows, freq). Raises numpy.linalg.LinAlgError if
    i omega is an eigenvalue of A (an undamped resonance).
    """
    omega = 2 * np.pi * np.asarray(freq_hz, dtype=float)
    nf, ns, m = omega.size, plant.n_states, plant.du.shape[1]
    w_hat = np.zeros((nf, 2 * m), dtype=complex)
    w_hat[:, axis] = amplitude  # u = Im(a e^{i w t})
    w_hat[:, m + axis] = 1j * omega * amplitude  # v = u' = Im(i w a e^{i w t})
    lhs = 1j * omega[:, None, None] * np.eye(ns) - plant.a
    g = np.linalg.solve(lhs, (w_hat @ plant.b.T)[..., None])[..., 0]  # (nf, ns)
    c, du, dv = plant.c[rows], plant.du[rows], plant.dv[rows]
    y_hat = g @ c.T + w_hat[:, :m] @ du.T + w_hat[:, m:] @ dv.T  # (nf, nr)
    phase = np.outer(np.asarray(steps) * h, omega)  # (time, freq), rad
    # Im(y_hat e^{i w t}) = Re(y_hat) sin(w t) + Im(y_hat) cos(w t)
    out = np.sin(phase)[:, None, :] * y_hat.real.T + np.cos(phase)[:, None, :] * y_hat.imag.T
    nt, nr = free.shape[:2]
    out += (free.reshape(nt * nr, ns) @ (z0 - g.imag.T)).reshape(nt, nr, nf)
    return out
