"""Semi-active damping laws of the benchmark: the `uavdamp.contract.DampingLaw` protocol, plant clips.

    Hybrid(gain, alpha, ...)       continuous clipped skyhook (alpha 1), groundhook (alpha 0) and Ahmadian's
                                   hybrid skyhook-groundhook (0 < alpha < 1), as a damping coefficient
    ClippedOptimal(...)            Dyke et al. (1996): an LQR force demand on the linear plant's state space from an
                                   observer, asked of the damper only where a damper can give it

One C serves both axes (as in the paper): with v_rel = base - mount velocity (y, z) the damper force on the base
is F = -C v_rel, so a desired force F_d is reproduced in the least-squares sense by C = -F_d . v_rel / |v_rel|^2,
which is >= 0 exactly when F_d does not push energy into the damper's stroke (F_d . v_rel <= 0). Every law below
demands that C where it is >= 0 and c_min elsewhere (the "clipped" forms); the plant clips to [c_min, c_max].
Karnopp's on-off skyhook with a tunable C_max is `uavdamp.damping.laws.Skyhook(c_max, c_min, step)`.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy.linalg import block_diag, expm, solve_continuous_are, solve_discrete_are

from uavdamp.contract import DamperBounds, Observation, clip
from uavdamp.platform.force_coupling import damper_input
from uavdamp.platform.linear_plant import OUTPUTS
from uavdamp.platform.statespace import discretise

_TINY_RATE = 1e-12  # m2 s-2: |v_rel|^2 below this counts as no stroke motion (the projection is undefined)


def projected_damping(force, v_rel, c_min: float, c_max: float) -> float:
    """C >= 0 (N s m-1) whose force -C v_rel is closest to `force` (N, (y, z)), c_min where that C is < 0 or
    undefined; capped at c_max so that the demand stays finite when v_rel is nearly zero. On floats: the laws call
    it every solver step with two-component vectors."""
    v_y, v_z = float(v_rel[0]), float(v_rel[1])
    rate2 = v_y * v_y + v_z * v_z
    if rate2 < _TINY_RATE:
        return c_min
    c = -(float(force[0]) * v_y + float(force[1]) * v_z) / rate2
    return clip(c, _capped(c_max), math.nan) if c > 0.0 else c_min


@functools.lru_cache(maxsize=16)
def _capped(c_max: float) -> DamperBounds:
    """[0, c_max], built once per c_max (the projection runs every solver step)."""
    return DamperBounds(0.0, c_max)


class Hybrid:
    """Ahmadian's hybrid skyhook-groundhook control (Ahmadian & Pare 2000, J. Intell. Mater. Syst. Struct. 11(8),
    604-612) in its continuous, clipped form, as a damping coefficient (N s m-1):

        C = alpha C_sky + (1 - alpha) C_gnd,   C_sky = g v_abs . v_rel / |v_rel|^2 where > 0, else 0,
                                               C_gnd = -g v_mnt . v_rel / |v_rel|^2 where > 0, else 0,

    g the gain (N s m-1), v_abs the base's absolute velocity, v_mnt the mount's (the fuselage: the "ground" side).
    alpha = 1 is the continuous clipped skyhook (the damper gives the skyhook force -g v_abs whenever it can,
    Karnopp et al. 1974), alpha = 0 the groundhook (force +g v_mnt on the mount side, Valasek et al. 1997).
    Where both parts are 0 the law asks for c_min. Decided every `update_period` s (the solver step for the
    classical form).
    """

    def __init__(self, gain: float, alpha: float, bounds: DamperBounds, update_period: float, name: str = "hybrid"):
        if not (math.isfinite(gain) and gain >= 0):
            raise ValueError(f"gain: must be finite and >= 0, got {gain}")
        if not 0.0 <= alpha <= 1.0:
            raise ValueError(f"alpha: must be in [0, 1], got {alpha}")
        self.gain, self.alpha, self.bounds = float(gain), float(alpha), bounds
        self.update_period, self.name = float(update_period), name

    def reset(self) -> None:
        pass

    def decide(self, v_abs: np.ndarray, v_mount: np.ndarray) -> float:
        """C, N s m-1, for the base's and the mount's absolute velocities, m s-1, (y, z)."""
        a_y, a_z, m_y, m_z = float(v_abs[0]), float(v_abs[1]), float(v_mount[0]), float(v_mount[1])  # floats
        v_rel, g, b = (a_y - m_y, a_z - m_z), self.gain, self.bounds
        sky = projected_damping((-g * a_y, -g * a_z), v_rel, 0.0, b.c_max)
        ground = projected_damping((g * m_y, g * m_z), v_rel, 0.0, b.c_max)
        c = self.alpha * sky + (1.0 - self.alpha) * ground
        return c if c > 0.0 else b.c_min

    def __call__(self, observation: Observation) -> float:
        return self.decide(observation.base_velocity, observation.mount_velocity)


class ClippedOptimal:
    """Clipped-optimal control (Dyke, Spencer, Sain & Carlson 1996, Smart Mater. Struct. 5, 565-575).

    An LQR on the linear plant at (K, C = 0) with the damper force F (N, (y, z)) as input, minimising
    the integral of |camera displacement|^2 / q_scale^2 + |F|^2 / r_scale^2 (q_scale m, r_scale N): F_d = -G z_hat.
    The state estimate z_hat comes from a steady-state Kalman filter on the same model discretised at the solver
    step, driven by the mount input the Observation carries and the damper force the law itself asked for
    (-C v_rel), corrected every step with the measured base displacement (stroke + mount) and base velocity.
    The damper is asked for F_d only where it can give it (`projected_damping`: F_d . v_rel < 0), else c_min:
    mode "continuous" demands the least-squares C; mode "on_off" is Dyke's rule for a damper whose force can only
    be raised or lowered, c_max when (F_d - F) . F > 0 (F = -C_prev v_rel the present force), else c_min.
    """

    name = "clipped_optimal"

    def __init__(
        self,
        model,
        stiffness: float,
        bounds: DamperBounds,
        time_step: float,
        *,
        q_scale: float,
        r_scale: float,
        mode: str = "continuous",
    ):

        if mode not in ("continuous", "on_off"):
            raise ValueError(f"clipped_optimal mode: must be continuous or on_off, got {mode!r}")
        if not (q_scale > 0 and r_scale > 0):
            raise ValueError(f"q_scale and r_scale must be > 0, got {q_scale}, {r_scale}")
        self.bounds, self.mode, self.update_period = bounds, mode, float(time_step)
        plant = model.state_space(stiffness, 0.0)
        self.b_f, self.s_rel = damper_input(model, stiffness)
        cam = plant.c[[OUTPUTS.index("camera_y"), OUTPUTS.index("camera_z")]]
        q = cam.T @ cam / q_scale**2 + 1e-12 * np.eye(plant.n_states) / q_scale**2
        r = np.eye(2) / r_scale**2
        p = solve_continuous_are(plant.a, self.b_f, q, r)
        self.gain = np.linalg.solve(r, self.b_f.T @ p)  # F_d = -gain z
        self.model, self.plant = model, plant
        self._observer(plant, time_step, OUTPUTS)
        self.reset()

    def _observer(self, plant, h: float, outputs) -> None:
        """Step map, the force's zero-order-hold input map and the steady-state Kalman gain (choice of covariances:
        process noise through the force input, 1 N2, plus 1e-18 on every state; measurement noise 1e-12, i.e.
        1 um and 1 um/s standard deviations)."""
        ns = plant.n_states
        self.step = discretise(plant, h)
        big = np.zeros((ns + 2, ns + 2))  # the force held over the step: exact zero-order hold
        big[:ns, :ns], big[:ns, ns:] = plant.a, self.b_f
        self.gamma_f = expm(big * h)[:ns, ns:]
        rows = [outputs.index(k) for k in ("base_y", "base_z")]
        self.h_pos = plant.c[rows]
        self.du_pos = plant.du[rows]
        nx = len(self.model.free)
        self.h_vel = np.zeros((2, ns))
        iso = [self.model.free.index(self.model.lin.link_index[k]) for k in ("iso_y", "iso_z")]
        self.h_vel[[0, 1], [nx + iso[0], nx + iso[1]]] = 1.0  # x~' of the isolator coordinates
        # the Observation's base velocity is x' + u' (y, z) = x~' - S u' + u' (y, z) on the isolator coordinates
        self.dv_vel = -self.model.s[iso]
        self.dv_vel[:, 1:3] += np.eye(2)
        h_meas = np.vstack([self.h_pos, self.h_vel])
        w = self.gamma_f @ self.gamma_f.T + 1e-18 * np.eye(ns)
        v = np.diag([1e-12, 1e-12, 1e-12, 1e-12])
        p = solve_discrete_are(self.step.phi.T, h_meas.T, w, v)
        self.kalman = p @ h_meas.T @ np.linalg.inv(h_meas @ p @ h_meas.T + v)
        self.h_meas = h_meas
        # one product a step each: the prediction on (z_hat, u_prev, slope, force), the inputs' share of the
        # measurement on (u, slope)
        self._predict = np.hstack([self.step.phi, self.step.gamma_u, self.step.gamma_v, self.gamma_f])
        self._measure_inputs = block_diag(self.du_pos, self.dv_vel)

    def reset(self) -> None:
        self.z_hat, self._force, self._c_prev = None, np.zeros(2), self.bounds.c_min

    def _estimate(self, obs: Observation) -> np.ndarray:
        u = np.asarray(obs.mount[-1], float)  # the mount links' coordinates (6,)
        if self.z_hat is None:
            slope = np.zeros_like(u)
            slope[1:3] = obs.mount_velocity
            z = self.model.initial_state(u, slope)
        else:
            u_prev = np.asarray(obs.mount[-2], float)
            slope = (u - u_prev) / (obs.time[-1] - obs.time[-2])
            z = self._predict @ np.concatenate([self.z_hat, u_prev, slope, self._force])
        measured = np.concatenate([np.asarray(obs.stroke, float) + u[1:3], np.asarray(obs.base_velocity, float)])
        predicted = self.h_meas @ z + self._measure_inputs @ np.concatenate([u, slope])
        return z + self.kalman @ (measured - predicted)

    def __call__(self, observation: Observation) -> float:
        self.z_hat = self._estimate(observation)
        v_rel = np.asarray(observation.stroke_rate, float)
        desired = -self.gain @ self.z_hat
        b = self.bounds
        if self.mode == "continuous":
            c = projected_damping(desired, v_rel, b.c_min, b.c_max)
        else:
            present = -self._c_prev * v_rel
            c = (
                b.c_max
                if float(np.dot(desired - present, present)) > 0.0
                or (not np.any(present) and float(np.dot(desired, v_rel)) < 0.0)
                else b.c_min
            )
        c = clip(c, b, observation.t_now)  # the law's own record of the force it gets (the plant clips the same)
        self._c_prev, self._force = c, -c * v_rel
        return c
