"""The platform as an exact linear plant, built from the Exudyn model's linearisation.

`linearise(model)` asks Exudyn (`ComputeLinearizedSystem`, at the static equilibrium q = 0 under gravity) for
M, K, D of the kinematic tree twice: isolator K = C = 0 and K = C = 1. Every joint force of the tree is linear in
the joint P and D vectors, so K(k) = K0 + k Kc and D(c) = D0 + c Dc for every isolator (k, c): one
linearisation serves the whole grid (K holds gravity's stiffness: the pitch link's pendulum term and the
weight's turn with the mount). The output map is the central-difference Jacobian of Exudyn's own sensors: the
camera point, the base point and the camera's optical axis (its inertial line of sight).

Coordinates (choice): the tree's coordinates q = (mount u: x, y, z, rx, ry, rz; free x) are relative, so the
mount enters
the free equations through its acceleration (M_xu u''), which a sampled, piecewise-linear input does not
have. With x~ = x + S u, S = M_xx^-1 M_xu, the u'' term vanishes:
    M_xx x~'' + D_xx x~' + K_xx x~ = (K_xx S - K_xu) u + (D_xx S - D_xu) u' - F Ki I,   I' = E x.
For the isolated mount's y and z translation S is the unit vector of the isolator coordinates (the mount links
are massless), so those inputs enter through the isolator spring and damper only; the mount's x translation and
rotation, which the isolator does not isolate, spread over the platform coordinates (as every input of the rigid
mount does). Either way the input enters through K and D, which a first-order hold of the sampled input gives
exactly. The servos' integral
terms (Exudyn's plant integrates them explicitly per step) are states I (rad s) with the force -Ki I.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass

import exudyn as exu
import numpy as np
import xarray as xr
from scipy.linalg import eigh

from uavdamp import contract
from uavdamp.contract import DamperBounds, MountMotion, Observation, line_of_sight, on_grid
from uavdamp.platform.model import MOUNT_LINKS, build, mount_coordinates
from uavdamp.platform.params import PlatformParams
from uavdamp.platform.statespace import (
    Discrete,
    Lifted,
    StateSpace,
    discretise,
    lift,
    propagate,
)

# output rows of the plant: camera y, z m; line of sight yaw, pitch rad (inertial); base y, z m (inertial);
# isolator stroke y, z m and stroke rate y, z m s-1 (isolator frame)
OUTPUTS = (
    "camera_y",
    "camera_z",
    "yaw",
    "pitch",
    "base_y",
    "base_z",
    "stroke_y",
    "stroke_z",
    "stroke_rate_y",
    "stroke_rate_z",
)
_ISOLATOR = ("iso_y", "iso_z")
_CACHE_SIZE = 64  # discretisations kept per plant: an on-off law needs 2, a continuous law one per new C
_BLOCK = 32  # steps per lifted block (`statespace.lift`); segments shorter than 2 blocks step one by one


@dataclass(frozen=True)
class Linearisation:
    """M (kg...), K0, Kc (N m-1 per unit isolator K), D0, Dc over the tree's n coordinates, and the Jacobians at
    rest of the camera point (3, n), the base point (3, n) (m per coordinate unit) and the line of sight (2, n)
    (yaw, pitch rad per coordinate unit)."""

    mass: np.ndarray
    stiffness0: np.ndarray
    stiffness_unit: np.ndarray
    damping0: np.ndarray
    damping_unit: np.ndarray
    camera_jacobian: np.ndarray
    base_jacobian: np.ndarray
    sight_jacobian: np.ndarray
    link_index: dict
    servo_ki: np.ndarray  # N m rad-1 s-1 per coordinate, 0 where none
    mount: str
    body: str


def _at_rest(mbs) -> None:
    zeros = np.zeros(mbs.systemData.ODE2Size())
    for config in (exu.ConfigurationType.Initial, exu.ConfigurationType.Current):
        mbs.systemData.SetODE2Coordinates(zeros, configuration=config)
        mbs.systemData.SetODE2Coordinates_t(zeros, configuration=config)


def _jacobian(model, read, step: float = 1e-6) -> np.ndarray:
    """d read() / dq (rows, n) by central differences, read() a function of the current configuration."""
    mbs = model.mbs
    q = np.zeros(mbs.systemData.ODE2Size())
    columns = []
    try:
        for j in range(model.n):
            values = []
            for sign in (1.0, -1.0):
                q[model.q0 + j] = sign * step
                mbs.systemData.SetODE2Coordinates(q, configuration=exu.ConfigurationType.Current)
                values.append(np.asarray(read(), dtype=float))
            q[model.q0 + j] = 0.0
            columns.append((values[0] - values[1]) / (2 * step))
    finally:
        _at_rest(mbs)
    return np.column_stack(columns)


def _output_jacobians(model) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Jacobians of the camera point, the base point and the line of sight (Exudyn's sensors of the model)."""
    mbs, sensors = model.mbs, model.sensors

    def sight():
        axis = np.asarray(mbs.GetSensorValues(sensors["camera_rotation"]), dtype=float).reshape(3, 3)[:, 0]
        return np.array(line_of_sight(axis))

    camera = _jacobian(model, lambda: mbs.GetSensorValues(sensors["camera"]))
    base = _jacobian(model, lambda: mbs.GetSensorValues(sensors["base"]))
    return camera, base, _jacobian(model, sight)


def linearise(model) -> Linearisation:
    """M, K0 + k Kc, D0 + c Dc and the output Jacobians of the Exudyn platform model at rest (q = 0, the static
    equilibrium: its static forces hold it there, so the residual is zero).

    The tree's control and force vectors are restored afterwards; coordinates are left at rest.
    """
    mbs, tree, n, q0 = model.mbs, model.tree, model.n, model.q0
    names = ("jointPControlVector", "jointDControlVector", "jointForceVector")
    saved = {name: np.array(mbs.GetObjectParameter(tree, name), dtype=float) for name in names}
    iso = [model.link_index[k] for k in _ISOLATOR if k in model.link_index]
    _at_rest(mbs)
    block = slice(q0, q0 + n)
    found = []
    try:
        for unit in (0.0, 1.0):
            pvec, dvec = np.array(model.pvec, dtype=float), np.array(model.dvec, dtype=float)
            pvec[iso] = dvec[iso] = unit
            mbs.SetObjectParameter(tree, "jointPControlVector", pvec)
            mbs.SetObjectParameter(tree, "jointDControlVector", dvec)
            mbs.SetObjectParameter(tree, "jointForceVector", model.static_forces)
            m, k, d = (np.asarray(x)[block, block] for x in mbs.ComputeLinearizedSystem())
            found.append((m, k, d))
    finally:
        for name, value in saved.items():
            mbs.SetObjectParameter(tree, name, value)
    (m, k0, d0), (_, k1, d1) = found
    camera, base, sight = _output_jacobians(model)
    return Linearisation(
        mass=m,
        stiffness0=k0,
        stiffness_unit=k1 - k0,
        damping0=d0,
        damping_unit=d1 - d0,
        camera_jacobian=camera,
        base_jacobian=base,
        sight_jacobian=sight,
        link_index=dict(model.link_index),
        servo_ki=np.array(model.servo_ki, dtype=float),
        mount=model.mount,
        body=model.body,
    )


class LinearModel:
    """State-space plants z = (x~, x~', I) of a linearisation for any isolator (K, C); see the module doc."""

    def __init__(self, lin: Linearisation):
        self.lin = lin
        idx = lin.link_index
        n = lin.mass.shape[0]
        self.mount_cols = [idx[k] for k in MOUNT_LINKS]
        self.free = [j for j in range(n) if j not in self.mount_cols]
        if not self.free:
            raise ValueError("the model has no free coordinates (rigid mount, lumped body): nothing to linearise")
        self.isolated = all(k in idx for k in _ISOLATOR)
        f, u = self.free, self.mount_cols
        self.m_xx = lin.mass[np.ix_(f, f)]
        self.s = np.linalg.solve(self.m_xx, lin.mass[np.ix_(f, u)])  # x~ = x + S u
        self.servo = [i for i, j in enumerate(f) if lin.servo_ki[j] > 0]  # positions within x
        nx, ni = len(f), len(self.servo)
        self.n_states = 2 * nx + ni
        # q = tq z + pq u, q' = tv z + pq v
        self.tq, self.tv = np.zeros((n, self.n_states)), np.zeros((n, self.n_states))
        self.tq[f, :nx] = np.eye(nx)
        self.tv[f, nx : 2 * nx] = np.eye(nx)
        m = len(u)
        self.pq = np.zeros((n, m))
        self.pq[u, :] = np.eye(m)
        self.pq[f, :] -= self.s
        self.hq, self.hv = self._output_maps(n)
        self._affine: dict = {}  # K -> (plant at C = 0, its a and b per unit C): `state_space`

    def _output_maps(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """Output rows (OUTPUTS) as hq q + hv q'."""
        idx, lin = self.lin.link_index, self.lin
        hq, hv = np.zeros((len(OUTPUTS), n)), np.zeros((len(OUTPUTS), n))
        hq[0:2] = lin.camera_jacobian[1:3]
        hq[2:4] = lin.sight_jacobian
        hq[4:6] = lin.base_jacobian[1:3]
        if self.isolated:
            for a, iso in enumerate(_ISOLATOR):
                hq[6 + a, idx[iso]] = 1.0
                hv[8 + a, idx[iso]] = 1.0
        return hq, hv

    def state_space(self, stiffness: float, damping: float) -> StateSpace:
        """The continuous plant at isolator K (N m-1) and C (N s m-1); both ignored for the rigid mount.

        C enters a and b affinely: a(C) = a(0) + C (a(1) - a(0)), likewise b, from the two plants at C = 0 and 1
        kept per K (c, du, dv do not depend on C)."""
        if not self.isolated:
            return self._state_space(0.0, 0.0)
        key = float(stiffness)
        if key not in self._affine:
            if len(self._affine) >= _CACHE_SIZE:
                self._affine.pop(next(iter(self._affine)))
            zero, one = self._state_space(key, 0.0), self._state_space(key, 1.0)
            self._affine[key] = (zero, one.a - zero.a, one.b - zero.b)
        zero, d_a, d_b = self._affine[key]
        c = float(damping)
        return StateSpace(a=zero.a + c * d_a, b=zero.b + c * d_b, c=zero.c, du=zero.du, dv=zero.dv)

    def _state_space(self, stiffness: float, damping: float) -> StateSpace:
        """The continuous plant at (K, C), assembled from the mass, stiffness and damping matrices."""
        lin, f, u = self.lin, self.free, self.mount_cols
        k_full = lin.stiffness0 + (stiffness if self.isolated else 0.0) * lin.stiffness_unit
        d_full = lin.damping0 + (damping if self.isolated else 0.0) * lin.damping_unit
        k_xx, k_xu = k_full[np.ix_(f, f)], k_full[np.ix_(f, u)]
        d_xx, d_xu = d_full[np.ix_(f, f)], d_full[np.ix_(f, u)]
        nx, ni, ns = len(f), len(self.servo), self.n_states
        ki = lin.servo_ki[[f[i] for i in self.servo]]
        select = np.zeros((ni, nx))
        select[np.arange(ni), self.servo] = 1.0
        m_inv = np.linalg.inv(self.m_xx)
        a = np.zeros((ns, ns))
        a[:nx, nx : 2 * nx] = np.eye(nx)
        a[nx : 2 * nx, :nx] = -m_inv @ k_xx
        a[nx : 2 * nx, nx : 2 * nx] = -m_inv @ d_xx
        a[nx : 2 * nx, 2 * nx :] = -m_inv @ select.T * ki  # joint force -Ki I on the servo joints
        a[2 * nx :, :nx] = select  # I' = x = x~ - S u
        m = len(u)
        b = np.zeros((ns, 2 * m))
        b[nx : 2 * nx, :m] = m_inv @ (k_xx @ self.s - k_xu)
        b[nx : 2 * nx, m:] = m_inv @ (d_xx @ self.s - d_xu)
        b[2 * nx :, :m] = -select @ self.s
        c = self.hq @ self.tq + self.hv @ self.tv
        return StateSpace(a=a, b=b, c=c, du=self.hq @ self.pq, dv=self.hv @ self.pq)

    def initial_state(self, u0: np.ndarray, v0: np.ndarray) -> np.ndarray:
        """State for the Exudyn plant's start: platform undeformed and at rest relative to the base; the base
        at rest (isolated: isolator stroke rate minus the mount's y and z rate) or moving with the mount (rigid);
        mount links at u0 with rates v0 (`model.mount_coordinates`). u0, v0: (6,) or (6, nf); returns (ns,) or
        (ns, nf)."""
        u0, v0 = np.asarray(u0, float), np.asarray(v0, float)
        nx = len(self.free)
        x_rate = np.zeros((nx, *v0.shape[1:]))
        if self.isolated:  # isolator stroke rate -v0 in y and z: the base at rest
            for axis, iso in zip((1, 2), _ISOLATOR, strict=True):
                x_rate[self.free.index(self.lin.link_index[iso])] = -v0[axis]
        z = np.zeros((self.n_states, *u0.shape[1:]))
        z[:nx] = self.s @ u0
        z[nx : 2 * nx] = x_rate + self.s @ v0
        return z

    def undamped_frequencies(self, stiffness: float) -> np.ndarray:
        """Undamped natural frequencies (Hz, ascending) with the mount held: eig(K_xx, M_xx)."""

        lin, f = self.lin, self.free
        k_full = lin.stiffness0 + (stiffness if self.isolated else 0.0) * lin.stiffness_unit
        values = eigh(k_full[np.ix_(f, f)], self.m_xx, eigvals_only=True)
        return np.sqrt(np.abs(values)) / (2 * np.pi)


class LinearPlant:
    """The linear plant behind the `uavdamp.contract.Plant` contract: the Exudyn plant's arguments and response.

    Exact for the model's linearisation: the input is linear between its samples on the solver grid (what
    the Exudyn plant's per-step constraint offsets impose) and C is constant between update times. One
    matrix exponential per (K, C), cached (the last `_CACHE_SIZE`): an on-off law that switches between two
    levels costs two; a continuous law one per new value, about 0.1 ms each at this size (choice: cheaper
    and simpler than integrating the continuous system per step, and exact).
    """

    name = "linear"

    def __init__(self, model):
        self.params = model.params
        self.mount, self.body = model.mount, model.body
        self.bounds = DamperBounds.from_params(self.params)
        self.model = LinearModel(linearise(model))
        self._cache: OrderedDict = OrderedDict()
        self._lifts: dict = {}

    @classmethod
    def from_params(cls, params: PlatformParams, *, mount: str = "isolated", body: str = "full") -> LinearPlant:
        """The linear plant of the platform `params`."""
        return cls(build(params, mount=mount, body=body))

    def step_map(self, stiffness: float, damping: float) -> tuple[StateSpace, Discrete]:
        """Continuous plant and its exact step map at (K, C), from the cache when seen recently."""
        key = (float(stiffness), float(damping)) if self.model.isolated else (0.0, 0.0)
        if key in self._cache:
            self._cache.move_to_end(key)
            return self._cache[key]
        plant = self.model.state_space(*key)
        value = (plant, discretise(plant, self.params.time_step))
        self._cache[key] = value
        if len(self._cache) > _CACHE_SIZE:
            self._cache.popitem(last=False)
        return value

    def _lifted(self, stiffness: float, damping: float) -> Lifted:
        """The step map at (K, C) lifted to blocks (built on first use, cached with it)."""
        key = ("lifted", float(stiffness), float(damping))
        if key not in self._lifts:
            if len(self._lifts) >= _CACHE_SIZE:
                self._lifts.pop(next(iter(self._lifts)))
            self._lifts[key] = lift(self.step_map(stiffness, damping)[1].phi, _BLOCK)
        return self._lifts[key]

    def _demand(self, law, n: int, run: dict, z: np.ndarray, isolator: np.ndarray | None = None) -> float:
        """The law's demand at grid point n (state z at t_n), clipped, with the Observation the Exudyn plant gives;
        `isolator` (4,): the stroke (y, z) m and its rate m s-1 at t_n where the caller has them (else from z)."""
        if isolator is None:
            if "isolator" not in run:  # the isolator rows of tq and tv stacked, and the inputs' share, once per run
                model, iso = self.model, [self.model.lin.link_index[k] for k in _ISOLATOR]
                pq = model.pq[iso]
                share = np.hstack([run["u"] @ pq.T, run["rate"] @ pq.T])
                run["isolator"] = (np.vstack([model.tq[iso], model.tv[iso]]), share)
            rows, share = run["isolator"]
            isolator = rows @ z + share[n]  # stroke (y, z), then its rate
        mount_v = run["rate"][n][1:3].copy()
        observation = Observation(
            t_now=float(run["time"][n]),
            time=run["time"][: n + 1],
            mount=run["u"][: n + 1],
            base_velocity=mount_v + isolator[2:],
            mount_velocity=mount_v,
            stroke=isolator[:2],
        )
        return contract.counted_clip(law, observation, self.bounds, run["clips"])

    def prepare(self, time, mount: MountMotion) -> dict:
        """The run's input on the solver grid: time, the motion, the mount links' coordinates u (n, 6), their slope
        on each step (n - 1, 6) and rate at each point (n, 6): the central difference (at the ends: the adjacent
        step's slope), within 0.4 % of its peak of the Exudyn plant's solved mount rate (7 Hz sine, 2 ms step;
        measured), closer than the backward slope (4.5 %)."""
        h = self.params.time_step
        grid, motion = on_grid(time, mount, h)
        u = mount_coordinates(motion)
        u.flags.writeable = False  # a law sees views of these
        slope = np.diff(u, axis=0) / h
        rate = np.concatenate([slope[:1], 0.5 * (slope[:-1] + slope[1:]), slope[-1:]])
        clips = contract.new_clip_count()  # the run's demands made and clipped (`uavdamp.contract.counted_clip`)
        return {"time": grid, "motion": motion, "u": u, "slope": slope, "rate": rate, "clips": clips}

    def run(self, time, mount: MountMotion, *, stiffness: float | None = None, law=None) -> xr.Dataset:
        """One run; arguments, clipping, update times, initial state and response as `ExudynPlant.run`."""
        run = self.prepare(time, mount)
        isolated = self.mount == "isolated"
        stiffness, law, per_update = contract.prepare_run(self, stiffness, law)
        per_update = per_update or run["time"].size - 1
        states, applied = self._propagate(run, run["slope"], stiffness, law if isolated else None, per_update)
        plant, _ = self.step_map(stiffness, applied[0] if isolated else 0.0)
        out = states @ plant.c.T + run["u"] @ plant.du.T + run["rate"] @ plant.dv.T  # c, du, dv do not depend on C
        return self._response(run, out, applied, stiffness if isolated else math.nan)

    def _propagate(self, run: dict, slope: np.ndarray, stiffness: float, law, per_update: int):
        """States (time, n_states) and applied damping (time,) of a run, one update period at a time."""
        u, steps = run["u"], run["time"].size - 1
        states = np.empty((steps + 1, self.model.n_states))
        states[0] = self.model.initial_state(u[0], slope[0])
        applied = np.full(steps + 1, math.nan)
        for start in range(0, steps, per_update):
            end = min(start + per_update, steps)
            c = self._demand(law, start, run, states[start]) if law is not None else 0.0
            _, step = self.step_map(stiffness, c)
            lifted = self._lifted(stiffness, c) if end - start >= 2 * _BLOCK else None
            states[start : end + 1] = propagate(step, states[start], u[start:end], slope[start:end], lifted)
            applied[start:end] = c
        applied[-1] = applied[-2]
        if law is None:
            applied[:] = math.nan
        return states, applied

    def _response(self, run: dict, out, applied, stiffness: float) -> xr.Dataset:
        """The response dataset (`uavdamp.contract.RESPONSE_VARIABLES`) from the output rows (time, OUTPUTS)."""
        row = {name: k for k, name in enumerate(OUTPUTS)}

        def pair(prefix):
            return out[:, [row[f"{prefix}_y"], row[f"{prefix}_z"]]].T

        values = {
            "camera_displacement": pair("camera"),
            "camera_yaw": out[:, row["yaw"]],
            "camera_pitch": out[:, row["pitch"]],
            "damping": applied,
            "mount_displacement": run["motion"].translation,
            "mount_rotation": run["motion"].rotation,
            "base_displacement": pair("base"),
            "isolator_stroke": pair("stroke"),
            "isolator_velocity": pair("stroke_rate"),
        }
        attrs = contract.response_attrs(self, stiffness)
        return contract.response_dataset(run["time"], values, attrs, run["clips"])
