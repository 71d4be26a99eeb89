"""A damper with its own dynamics in the linear plant: its force as an input, advanced one solver step at a time.

The isolator's linear plant at C = 0 takes the damper force F on the base as an input (`damper_input`:
z' = A(K, 0) z + B w + B_f F; the ideal damper is F = -C v_rel). A force damper (`ForceDamper`: e.g. the Spencer
MR damper of `uavdamp.damping.actuation`) gives the force F_d (N, (y, z)) needed to move its stroke, so F = -F_d. Over
one solver step the plant is exact for a force held at its step mean (zero-order hold: gamma_f = the force block of
expm([[A, B_f], [0, 0]] h)); the damper is stepped on the stroke the plant gives:

    predict   z_p = step(z) - gamma_f F_d(start): the stroke x, x' at the step's end from the force at its start;
    evaluate  the damper over the step on the Hermite stroke (x0, x0', x_p, x_p'): its mean force F_m (state restored);
    correct   z = step(z) - gamma_f F_m, and the damper stepped again on that stroke (its state at the step's end).

(choice: PECE with the step mean, as `uavdamp.damping.dampers` recommends over a start-held force, which is 5-21 % off
at 2 ms). A damper whose step mean force is linear in the stroke, F_d = k (x_1 - x_0) with k known at the step's start
(`rate_gain`: the viscous and the lagged damper), is solved for exactly instead: (I + k G) F_d = k (x_free - x_0),
G the stroke's response to a unit force: the fixed point of F_d <- k (x_free - G F_d - x_0), of which PECE takes
two steps (with C = 200 N s m-1 at a 4 ms step PECE diverged, the exact step did not); the exact step runs compiled
over each interval the law's demand is held (`uavdamp.platform.coupling_kernel`). A viscous force damper
converges to the exact plant at second order in the step (both: tests/test_force_coupling.py). The law is asked at
its update times as by `LinearPlant.run` (same Observation); its clipped demand is handed to the damper (`command`).
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np
import xarray as xr
from scipy.linalg import expm

from uavdamp import contract
from uavdamp.platform import coupling_kernel
from uavdamp.platform.linear_plant import OUTPUTS

_STROKE = [OUTPUTS.index("stroke_y"), OUTPUTS.index("stroke_z")]
_RATE = [OUTPUTS.index("stroke_rate_y"), OUTPUTS.index("stroke_rate_z")]


class ForceDamper(Protocol):
    """A damper with state: the force F_d (N, (y, z)) needed to move its stroke x (m) at rate x' (m s-1)."""

    name: str

    def reset(self, stroke: np.ndarray) -> None: ...  # at rest at this stroke, command off

    def command(self, damping: float) -> None: ...  # the law's clipped demand, N s m-1

    def force(self, x: np.ndarray, xd: np.ndarray) -> np.ndarray: ...  # at the present state

    def step(self, h: float, x0, xd0, x1, xd1) -> np.ndarray: ...  # advance over h; the step's mean force

    def save(self): ...

    def restore(self, state) -> None: ...

    # optional: rate_gain(h) -> k (N m-1), the step's mean force k (x_1 - x_0), the damper advanced over h;
    # couple(h, x0, xd0, free_end, g_rows) -> the step's mean force: the predictor-corrector below in one call (the MR
    # damper's compiled one), the damper advanced over h


class Viscous:
    """F_d = C x' with C the last command: the ideal damper as a force damper (the coupling's check)."""

    name = "viscous"

    def reset(self, stroke) -> None:
        self.c = 0.0

    def command(self, damping: float) -> None:
        self.c = float(damping)

    def force(self, x, xd) -> np.ndarray:
        return self.c * np.asarray(xd, float)

    def step(self, h, x0, xd0, x1, xd1) -> np.ndarray:
        return self.c * (np.asarray(x1, float) - np.asarray(x0, float)) / h  # mean of C x' over the step

    def rate_gain(self, h: float) -> float:
        """k, N m-1: the step's mean force is k (x_1 - x_0)."""
        return self.c / h

    def save(self):
        return self.c

    def restore(self, state) -> None:
        self.c = state


def damper_input(model, stiffness: float) -> tuple[np.ndarray, np.ndarray]:
    """(B_f (ns, 2), S_rel (2, ns)): the damper force F (N, on the base, (y, z)) as an input of the state space
    at C = 0, z' = A(K, 0) z + B w + B_f F, and the stroke rate v_rel = S_rel z + (the rate input's share).

    A(K, C) = A(K, 0) + C dA exactly (C enters linearly), and dA = -B_f S_rel; B_f is found by least squares and
    checked (ValueError if the plant's damping does not act through the stroke rate)."""
    a0, a1 = model.state_space(stiffness, 0.0), model.state_space(stiffness, 1.0)
    rows = [OUTPUTS.index("stroke_rate_y"), OUTPUTS.index("stroke_rate_z")]
    s_rel = a0.c[rows]
    d_a = a1.a - a0.a
    b_f = -np.linalg.lstsq(s_rel.T, d_a.T, rcond=None)[0].T
    if not np.allclose(b_f @ s_rel, -d_a, atol=1e-9 * max(1.0, np.abs(d_a).max())):
        raise ValueError("the isolator damping does not act through the stroke rate alone")
    return b_f, s_rel


def force_map(plant, b_f: np.ndarray, h: float) -> np.ndarray:
    """gamma_f (ns, 2): the state change over a step h (s) of a unit force held on it (exact zero-order hold)."""
    ns = plant.n_states
    big = np.zeros((ns + 2, ns + 2))
    big[:ns, :ns], big[:ns, ns:] = plant.a, b_f
    return expm(big * h)[:ns, ns:]


def _damper_step(damper: ForceDamper, h: float, end, free_end, g_rows) -> np.ndarray:
    """The step's mean damper force F_d (N, (y, z)) from the stroke and rate at its start (end (4,)) and the free
    plant's at its end (free_end (4,)), the damper advanced over h: its compiled `couple`, else PECE (module
    docstring)."""
    x0, xd0 = end[:2], end[2:]
    couple = getattr(damper, "couple", None)
    if couple is not None:
        return couple(h, x0, xd0, free_end, g_rows)
    saved = damper.save()
    predicted = free_end - g_rows @ damper.force(x0, xd0)
    mean = damper.step(h, x0, xd0, predicted[:2], predicted[2:])
    damper.restore(saved)
    corrected = free_end - g_rows @ mean
    return damper.step(h, x0, xd0, corrected[:2], corrected[2:])


def run(plant, time, mount, *, stiffness: float, law, damper: ForceDamper) -> xr.Dataset:
    """One run of the isolated linear plant (`LinearPlant`) with `damper` between base and mount, the law's clipped
    demand commanding it; the response as `LinearPlant.run` plus `damper_force` (axis, time), N: the force on the
    stroke, each step's mean (the last point repeats the last step's)."""
    if plant.mount != "isolated":
        raise ValueError("a force damper needs the isolated mount")
    data = plant.prepare(time, mount)
    stiffness, law, per_update = contract.prepare_run(plant, stiffness, law)
    u, slope, rate = data["u"], data["slope"], data["rate"]
    cont, step = plant.step_map(stiffness, 0.0)
    h = plant.params.time_step
    gamma_f = force_map(cont, damper_input(plant.model, stiffness)[0], h)
    steps = data["time"].size - 1
    z = np.empty((steps + 1, cont.n_states))
    z[0] = plant.model.initial_state(u[0], slope[0])
    applied, force = np.full(steps + 1, math.nan), np.zeros((steps + 1, 2))
    rows = _STROKE + _RATE
    c_rows, ns = cont.c[rows], cont.n_states
    # one product per step gives the free state (the step with no damper force) and its stroke and rate (4,) at the
    # step's end: rows [phi; c_rows phi] on the state, plus the input's part of both, all steps at once; a force F
    # held over the step takes [gamma_f; c_rows gamma_f] F off both
    drive = u[:-1] @ step.gamma_u.T + slope @ step.gamma_v.T  # (steps, ns)
    share = u @ cont.du[rows].T + rate @ cont.dv[rows].T  # (steps + 1, 4): the input's part of the stroke rows
    free_map = np.vstack([step.phi, c_rows @ step.phi])
    free_drive = np.hstack([drive, drive @ c_rows.T + share[1:]])
    force_rows = np.vstack([gamma_f, c_rows @ gamma_f])
    g_rows = force_rows[ns:]  # the stroke's and rate's response to a unit force (G: its first two rows)
    linear = hasattr(damper, "rate_gain")  # module docstring
    end = c_rows @ z[0] + share[0]
    damper.reset(end[:2])
    for start in range(0, steps, per_update):  # the law's update times; its demand held until the next
        stop = min(start + per_update, steps)
        applied[start:stop] = plant._demand(law, start, data, z[start], end.copy())  # end: the stroke and rate now
        damper.command(applied[start])
        if linear:  # the exact step, compiled over the held interval
            gains = [damper.rate_gain(h) for _ in range(start, stop)]
            coupling_kernel.linear_steps(z, end, free_map, free_drive, force_rows, gains, start, force)
            continue
        for n in range(start, stop):
            free = free_map @ z[n] + free_drive[n]  # (ns + 4,): the free state, then its stroke and rate
            force[n] = _damper_step(damper, h, end, free[ns:], g_rows)
            state = free - force_rows @ force[n]
            z[n + 1], end = state[:ns], state[ns:]
    applied[-1], force[-1] = applied[-2], force[-2]
    out = z @ cont.c.T + u @ cont.du.T + rate @ cont.dv.T
    response = plant._response(data, out, applied, stiffness)
    response["damper_force"] = (("axis", "time"), force.T, {"units": "N", "long_name": f"{damper.name} damper force"})
    response.attrs["damper"] = damper.name
    return response
