"""The six-axis isolator with a force damper (a damper with its own states: the Spencer MR damper of
`uavdamp.damping.dampers.SpencerMR`, one axis per damper) along each damper axis of its semi-active elements, in time.

The payload obeys the six-axis model (`uavdamp.platform.six_axis`) with the semi-active elements' damping at 0
along their damper axes, plus the dampers' forces: M q'' + C_0 (q' - u') + K (q - u) = -D^T F, D the damper axes'
rows of `six_axis.strokes_matrix` and F (N) the force each damper needs to move its stroke x = D (q - u) at
x' = D (q' - u'), from a batch of dampers (`BatchDamper`, built by the caller: this module knows no damper
model). Over a step the model is exact for the mount's
first-order hold and for F held at its step mean (zero-order hold); the dampers are stepped once a step (choice:
PEC): predict the step's end with the force at its start, step the dampers over the step on the Hermite stroke to
that predicted end, and correct the model with their mean force. `uavdamp.platform.force_coupling` (the paper's
platform) steps its damper twice (PECE: evaluate, restore, step again on the corrected stroke); here that second
pass changed nothing measurable (the payload within 1.72e-4 of an adaptive integration either way, 4.1e-5 at half
the step: tests/test_six_axis_force.py) at twice the cost. It relies on h c / m << 1 (c the dampers' damping, m the
payload: 0.01 for the default 1-6 N s/m dampers on 1.5 kg at 0.5 ms).

Each element's dampers share one command voltage, held over the step from its sample and given per run by a
schedule: an array of voltages (n_semi,) or (n_semi, n), or a callable (t_k, outputs_k) -> (n_semi,) V with the
outputs of `six_axis.output_names` (the protocol of `uavdamp.platform.six_axis_run.run`). The runs of a call step
side by side (every damper of every run in one batch). A run starts with the payload moving with the mount and
each damper at rest (z = 0, u = 0 V, y at its stroke).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np

from uavdamp.platform.six_axis import AXES, SixAxisIsolator, mass_matrix, state_space, strokes_matrix
from uavdamp.platform.six_axis_run import mount_grid, schedule_array
from uavdamp.platform.statespace import StateSpace, discretise


class BatchDamper(Protocol):
    """n dampers advanced together (`uavdamp.damping.dampers.SpencerMR` with n axes): each needs the force F (N) to
    move its stroke x (m) at rate x' (m s-1) and takes a command (here a voltage, V)."""

    force_mean: np.ndarray  # N (n,), the last step's mean force

    def reset(self, x0) -> None: ...  # at rest at the strokes x0 (m)

    def force(self, x, xd) -> np.ndarray: ...  # F (n,) at the present state

    # advance over h at the held commands on the Hermite stroke: F at the end, N (n,); the step's mean: force_mean
    def step(self, h: float, command, x0, xd0, x1, xd1) -> np.ndarray: ...


def damper_axes(isolator: SixAxisIsolator) -> list[tuple[int, int]]:
    """(semi-active element's index among the semi-active ones, axis index) of every damper, element-major."""
    return [
        (j, AXES.index(a))
        for j, i in enumerate(isolator.semi_active)
        for a in isolator.elements[i].damper_axes
    ]  # fmt: skip


def _step_map(isolator: SixAxisIsolator, h: float):
    """(phi (12, 12), the mount's gamma_u and gamma_v (12, 6) each, the held forces' gamma (12, n_f), D (n_f, 6))
    of the model with the semi-active dampers' axes undamped and their forces F as held inputs."""
    semi = isolator.semi_active
    d = strokes_matrix(isolator)[[3 * semi[j] + a for j, a in damper_axes(isolator)]]
    plant = state_space(isolator, np.zeros(len(semi)))
    n_f = d.shape[0]
    b_f = np.vstack([np.zeros((6, n_f)), -np.linalg.solve(mass_matrix(isolator.payload), d.T)])
    b = np.hstack([plant.b[:, :6], b_f, plant.b[:, 6:], np.zeros((12, n_f))])  # u = (mount, F), v = (rates, 0)
    zeros = np.zeros((1, 6 + n_f))
    step = discretise(StateSpace(plant.a, b, np.zeros((1, 12)), zeros, zeros), h)
    return step.phi, step.gamma_u[:, :6], step.gamma_v[:, :6], step.gamma_u[:, 6:], d


def integrate(
    isolator: SixAxisIsolator,
    dampers_of: Callable[[int], BatchDamper],
    time,
    translation,
    rotation,
    schedules: list,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """States (B, n, 12) (q, q') of the payload under the mount motion (translation (3, n) m, rotation (3, n) rad
    on a uniform `time`, s) for each of the B `schedules` of voltages (module docstring), side by side, on the
    dampers `dampers_of(count)` gives (every damper of every run, run-major, `damper_axes` within a run); the mount's
    coordinates (n, 6); the applied voltages (B, n, n_semi) V; each damper's step-mean force (B, n - 1, n_f) N
    (`damper_axes`' order)."""
    t, h, u = mount_grid(time, translation, rotation)
    n, n_semi, n_runs = t.size, len(isolator.semi_active), len(schedules)
    plans = [None if callable(s) else schedule_array(isolator, s, n) for s in schedules]
    phi, g_u, g_v, g_f, d = _step_map(isolator, h)
    owner = np.array([j for j, _ in damper_axes(isolator)])
    outputs = state_space(isolator)
    slopes = np.diff(u, axis=0) / h
    rates = np.vstack([slopes, slopes[-1:]])
    dampers = dampers_of(n_runs * d.shape[0])
    w = np.zeros((n_runs, n, 12))
    w[:, 0, :6], w[:, 0, 6:] = u[0], rates[0]
    applied = np.zeros((n_runs, n, n_semi))
    forces = np.zeros((n_runs, n - 1, d.shape[0]))

    # the inputs' shares, every sample at once: of the outputs, of the free step, of the strokes and their rates
    driven = u @ outputs.du.T + rates @ outputs.dv.T
    drive = u[:-1] @ g_u.T + slopes @ g_v.T
    mount_strokes, mount_rates = u @ d.T, slopes @ d.T

    def strokes(states: np.ndarray, k: int, j: int) -> tuple[np.ndarray, np.ndarray]:
        """The strokes at sample k and their rates on step j of the states (B, 12), flat (B n_f,)."""
        return (states[:, :6] @ d.T - mount_strokes[k]).ravel(), (states[:, 6:] @ d.T - mount_rates[j]).ravel()

    dampers.reset(strokes(w[:, 0], 0, 0)[0])
    for k in range(n):
        y = w[:, k] @ outputs.c.T + driven[k]
        for b, (schedule, plan) in enumerate(zip(schedules, plans, strict=True)):
            applied[b, k] = plan[k] if plan is not None else np.asarray(schedule(float(t[k]), y[b]), dtype=float)
        if k == n - 1:
            break
        volts = applied[:, k][:, owner].ravel()
        free = w[:, k] @ phi.T + drive[k]
        x0, xd0 = strokes(w[:, k], k, k)
        start = dampers.force(x0, xd0)
        predicted = free + start.reshape(n_runs, -1) @ g_f.T
        dampers.step(h, volts, x0, xd0, *strokes(predicted, k + 1, k))
        mean = dampers.force_mean
        w[:, k + 1] = free + mean.reshape(n_runs, -1) @ g_f.T
        forces[:, k] = mean.reshape(n_runs, -1)
    return w, u, applied, forces
