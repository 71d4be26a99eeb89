"""Wire-rope elements on the six-axis isolator: Bouc-Wen hysteresis along chosen axes, run in the time domain.

Along each hysteretic axis of an element the spring force on the payload is -(alpha k s + (1 - alpha) k z)
(`uavdamp.platform.bouc_wen`: s the element's stroke, z its hysteretic displacement, k the element's stiffness
along that axis) = -k s + (1 - alpha) k e with e = s - z; the element's damping (viscous, semi-active) and its
stiffness along the other axes are those of `uavdamp.platform.six_axis`. So the payload obeys the six-axis model
(full stiffness, with the weight's geometric stiffness) plus the generalised force H^T diag((1 - alpha) k) e, H
the hysteretic strokes' rows of `six_axis.strokes_matrix`. At the loaded rest position z = s (assumption: no
residual set from an earlier load).

While |z| << z_max (the yield stroke, `WireRope.yield_stroke`) e = 0 and the element is the linear spring k: the
six-axis isolator's modes and transmissibility are the wire rope's small-amplitude limit. Beyond it the element
softens towards alpha k (`post_yield`) and dissipates its loop's area each cycle.

Integration (`integrate`): each step h, the payload's states are exact for the mount's first-order hold and for
e's (`statespace.discretise` of the model with e among the held inputs; e = 0 below yield, so that limit is the
six-axis run's exact step map). z is advanced in the stroke: Bouc-Wen is rate-independent, z' = s' phi(z, sign
s') with phi = A - (beta sign(s') sign(z) + gamma) |z|^n, so over a step z_{k+1} = z_k + the integral of phi ds
over the step's stroke increment, taken by Heun's rule (second order in the increment over z_max; exact while
phi = A). The increment depends on e_{k+1} through the states: a fixed-point iteration (`ITERATIONS`) finds both.
A stroke reversal inside a step is taken at the step's end. A damping schedule (`integrate_scheduled`: a semi-active
law's C) is held over each step, the step map that of its C, built once per distinct C.
The steps are compiled (`uavdamp.platform.wire_rope_kernel`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
import xarray as xr

from uavdamp.platform import wire_rope_kernel as kernel
from uavdamp.platform.bouc_wen import BoucWen
from uavdamp.platform.six_axis import (
    AXES,
    SixAxisIsolator,
    damping_matrix,
    mass_matrix,
    state_space,
    strokes_matrix,
    total_stiffness,
)
from uavdamp.platform.six_axis_run import run_dataset, schedule_array
from uavdamp.platform.statespace import StateSpace, discretise

WHERE = "payload.wire_rope"  # the config section these parameters come from
# fixed-point passes per step, each from the previous step's increment (the coupling per step is O(h^2 k / m)): on a
# yielding run one pass is within 8e-9 of the converged rotations' range (two: 5e-13), far below Heun's rule's 3e-5
ITERATIONS = 1
MAX_MAPS = 1024  # step maps a run keeps (about 3 kB each): more are rebuilt when next taken


@dataclass(frozen=True)
class WireRope:
    """The Bouc-Wen shape shared by every wire-rope element (`uavdamp.platform.bouc_wen` for the symbols): the
    hysteretic axes (names of `AXES`), alpha (1, post-yield over initial stiffness), the yield stroke z_max (m,
    A / (beta + gamma) to the power 1/n, with A = 1), the exponent n (1) and beta's share of beta + gamma (1, in
    [0.5, 1]: gamma <= beta keeps the loop dissipative)."""

    axes: tuple[str, ...] = ("x", "y")
    alpha: float = 0.5
    yield_stroke: float = 1.0e-3  # m
    exponent: float = 1.0
    beta_share: float = 0.5

    def __post_init__(self):
        axes = tuple(self.axes)
        if not axes or len(set(axes)) != len(axes) or not set(axes) <= set(AXES):
            raise ValueError(f"{WHERE}.axes: must be distinct names of {list(AXES)}, got {list(self.axes)}")
        checks = (
            ("alpha", 0 < self.alpha <= 1, "must lie in (0, 1] (0: no restoring stiffness once yielded)"),
            ("yield_stroke_m", math.isfinite(self.yield_stroke) and self.yield_stroke > 0, "must be > 0"),
            ("exponent", math.isfinite(self.exponent) and self.exponent >= 1, "must be >= 1"),
            ("beta_share", 0.5 <= self.beta_share <= 1, "must lie in [0.5, 1] (gamma <= beta: dissipative)"),
        )
        value = {"alpha": self.alpha, "yield_stroke_m": self.yield_stroke}
        value |= {"exponent": self.exponent, "beta_share": self.beta_share}
        for key, ok, rule in checks:
            if not ok:
                raise ValueError(f"{WHERE}.{key}: {rule}, got {value[key]}")
        object.__setattr__(self, "axes", axes)

    @cached_property
    def beta_gamma(self) -> tuple[float, float]:
        """(beta, gamma), m^-n: beta_share and its complement of beta + gamma = yield_stroke^-n (A = 1)."""
        total = self.yield_stroke ** (-self.exponent)
        return self.beta_share * total, (1 - self.beta_share) * total

    def element(self, stiffness: float) -> BoucWen:
        """The `BoucWen` of one hysteretic axis of initial stiffness k (N m-1)."""
        return BoucWen(stiffness, self.alpha, 1.0, *self.beta_gamma, self.exponent)

    def phi(self, z: np.ndarray, direction: np.ndarray) -> np.ndarray:
        """dz/ds (1) at hysteretic displacements z (m) for strokes moving in `direction` (+1, -1)."""
        beta, gamma = self.beta_gamma
        magnitude = np.abs(z) if self.exponent == 1 else np.abs(z) ** self.exponent
        return 1.0 - (beta * direction * np.sign(z) + gamma) * magnitude


def hysteretic_axes(isolator: SixAxisIsolator, wire: WireRope) -> list[tuple[int, int]]:
    """(element, axis index) of every hysteretic axis, element-major."""
    return [(i, AXES.index(a)) for i in range(isolator.n_elements) for a in wire.axes]


def post_yield(isolator: SixAxisIsolator, wire: WireRope) -> SixAxisIsolator:
    """The isolator with its hysteretic stiffnesses at alpha k (the tangent of a fully yielded element): its modes
    are the wire rope's large-amplitude limit."""
    scale = np.array([wire.alpha if a in wire.axes else 1.0 for a in AXES])
    elements = tuple(replace(e, stiffness=tuple((np.asarray(e.stiffness) * scale).tolist())) for e in isolator.elements)
    return replace(isolator, elements=elements)


def _model(isolator: SixAxisIsolator, wire: WireRope, semi_active_damping) -> tuple[StateSpace, np.ndarray, np.ndarray]:
    """The states' model with inputs (u, e) and their slopes, e = s - z the hysteretic axes' strokes beyond their
    hysteretic displacement (the element force k s - (1 - alpha) k e); H (n_h, 6) and k (n_h,) N m-1."""
    axes = hysteretic_axes(isolator, wire)
    h_rows = strokes_matrix(isolator)[[3 * i + a for i, a in axes]]
    k_h = np.array([isolator.elements[i].stiffness[a] for i, a in axes])
    m = mass_matrix(isolator.payload)
    k, c = total_stiffness(isolator), damping_matrix(isolator, semi_active_damping)
    mk, mc = np.linalg.solve(m, k), np.linalg.solve(m, c)
    g = np.linalg.solve(m, h_rows.T * ((1 - wire.alpha) * k_h))  # (6, n_h): q'' per unit e
    n_h, zero, eye = k_h.size, np.zeros((6, 6)), np.eye(6)
    b = np.zeros((12, 2 * (6 + n_h)))
    b[6:, :6], b[6:, 6 : 6 + n_h] = mk, g  # u and e (first-order hold)
    b[6:, 6 + n_h : 12 + n_h] = mc  # the mount's rate (e's slope enters only through the hold)
    m_in = 6 + n_h  # the outputs are not used (`_steps` reads the states): one zero row each
    plant = StateSpace(
        np.block([[zero, eye], [-mk, -mc]]), b, np.zeros((1, 12)), np.zeros((1, m_in)), np.zeros((1, m_in))
    )
    return plant, h_rows, k_h


def _mount(time, translation, rotation) -> tuple[np.ndarray, float, np.ndarray]:
    """(time s, step s, the mount's coordinates (..., n, 6)), checked: a uniform time, finite (..., 3, n) inputs."""
    t = np.asarray(time, dtype=float)
    h = float(t[1] - t[0]) if t.size > 1 else math.nan
    tr, rot = np.asarray(translation, dtype=float), np.asarray(rotation, dtype=float)
    ok = t.size > 1 and tr.shape == rot.shape and tr.shape[-2:] == (3, t.size) and np.all(np.isfinite(tr))
    if not (ok and np.all(np.isfinite(rot)) and np.allclose(np.diff(t), h, rtol=1e-9)):
        raise ValueError(f"time, translation, rotation: need a uniform time and finite (3, {t.size}) arrays")
    return t, h, np.swapaxes(np.concatenate([tr, rot], axis=-2), -1, -2)


def integrate(
    isolator: SixAxisIsolator, wire: WireRope, time, translation, rotation, dampings
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """States (n_c, n, 12): (q, q') of the payload (m, rad and rates), and z (n_c, n, n_h) m, for each of the
    `dampings` (n_c values per semi-active element, N s m-1, or None: their own) under the mount motion
    (translation (3, n) m, rotation (3, n) rad on a uniform `time`, s), integrated side by side; also the mount's
    coordinates (n, 6). Starts with the payload moving with the mount and z = 0."""
    _, h, u = _mount(time, translation, rotation)
    if u.ndim != 2:
        raise ValueError("translation, rotation: one mount motion, (3, n) each")
    bank = _Bank(isolator, wire, h)
    fixed = [bank.find(c) for c in dampings]
    w, z = _steps(wire, bank, u, len(fixed), lambda k, w_k: fixed, held=True)
    return w, z, u


def integrate_scheduled(
    isolator: SixAxisIsolator, wire: WireRope, time, translation, rotation, schedules: list
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """`integrate` with the semi-active elements' damping scheduled, one run per item of `schedules` side by side:
    None (their own), an array (n_semi,) or (n_semi, n) N s m-1 acting from each sample on, or a callable
    (t_k, outputs_k) -> (n_semi,) called at every sample with the outputs there (`uavdamp.platform.six_axis_run.run`'s
    protocol: `six_axis.output_names`, the mount's rate at a sample the slope of the step from it). Each step is
    the exact map at its held C (one `discretise` per distinct C). Returns states (B, n, 12), z (B, n, n_h), the
    mount's coordinates (n, 6) and the applied C (B, n, n_semi) (NaN: the elements' own)."""
    t, h, u = _mount(time, translation, rotation)
    if u.ndim != 2:
        raise ValueError("translation, rotation: one mount motion, (3, n) each")
    n, n_semi = t.size, len(isolator.semi_active)
    plans = [None if callable(s) or s is None else schedule_array(isolator, s, n) for s in schedules]
    outputs = state_space(isolator)  # the outputs do not depend on the damping
    rates = np.vstack([np.diff(u, axis=0), np.diff(u, axis=0)[-1:]]) / h
    driven = u @ outputs.du.T + rates @ outputs.dv.T  # the inputs' share of the outputs, every sample at once
    applied = np.full((len(schedules), n, n_semi), np.nan)
    bank = _Bank(isolator, wire, h)

    def choose(k: int, w_k: np.ndarray) -> list:
        y = w_k @ outputs.c.T + driven[k]
        found = []
        for b, (schedule, plan) in enumerate(zip(schedules, plans, strict=True)):
            c = plan[k] if plan is not None else None if schedule is None else schedule(float(t[k]), y[b])
            if c is not None:
                applied[b, k] = c = np.asarray(c, dtype=float).ravel()
            found.append(bank.find(c))
        return found

    w, z = _steps(wire, bank, u, len(schedules), choose)
    return w, z, u, applied


class _Bank:
    """The step maps of `_model` at each damping a run takes (N s m-1 per semi-active element, or None: their own),
    each built once (at most `MAX_MAPS` kept: a lagged damper's C is new every step), stacked per run of a batch
    (`take`): [phi | gamma_u's e, u columns | gamma_v's u columns] (12, 24 + n_h) over (q, q', e_k, u_k, u's
    slope), gamma_v's e columns / h (12, n_h), the states' increment per unit e increment, and its strokes H of
    them (n_h, n_h)."""

    def __init__(self, isolator: SixAxisIsolator, wire: WireRope, h: float):
        self.isolator, self.wire, self.h = isolator, wire, h
        self.h_rows = _model(isolator, wire, None)[1]  # the strokes do not depend on the damping
        self.parts: dict = {}

    def find(self, c) -> tuple | None:
        """The key of damping c (built now if new)."""
        key = None if c is None else tuple(np.asarray(c, dtype=float).ravel().tolist())
        self._part(key)
        return key

    def _part(self, key) -> tuple[np.ndarray, ...]:
        if key not in self.parts:
            if len(self.parts) >= MAX_MAPS:
                self.parts.clear()
            s = discretise(_model(self.isolator, self.wire, None if key is None else np.array(key))[0], self.h)
            maps = np.hstack([s.phi, s.gamma_u[:, 6:], s.gamma_u[:, :6], s.gamma_v[:, :6]])
            ge1 = s.gamma_v[:, 6 : 6 + self.h_rows.shape[0]] / self.h
            self.parts[key] = (maps, ge1, self.h_rows @ ge1[:6])
        return self.parts[key]

    def take(self, keys: list) -> tuple[np.ndarray, ...]:
        return tuple(np.stack(a) for a in zip(*[self._part(k) for k in keys], strict=True))


def _steps(wire: WireRope, bank: _Bank, u: np.ndarray, n_c: int, choose, held: bool = False):
    """States (B, n, 12) and z (B, n, n_h) of B = n_c runs side by side under the mount coordinates u (n, 6), or
    u[b] when u is (B, n, 6): over step k run b takes the step map of the bank's key choose(k, w_k)[b], w_k (B, 12)
    the states at sample k (choose returns a list of `_Bank.find` keys; it is also called at the last sample).
    held: choose's keys are the same at every sample (asked once; the whole run in one compiled call). The steps
    are `wire_rope_kernel.advance`'s."""
    h_rows, h = bank.h_rows, bank.h
    # writeable as well as C-ordered: a read-only array (a broadcast view) is another signature, another compilation
    n_h, u = h_rows.shape[0], np.require(np.broadcast_to(u, (n_c, *u.shape[-2:])), requirements="CW")
    n = u.shape[1]
    slopes = np.diff(u, axis=1) / h
    mount_strokes = u @ h_rows.T  # (n_c, n, n_h): H u
    w = np.zeros((n_c, n, 12))
    w[:, 0, :6], w[:, 0, 6:] = u[:, 0], slopes[:, 0]
    z = np.zeros((n_c, n, n_h))
    s_k, de = np.zeros((n_c, n_h)), np.zeros((n_c, n_h))  # the strokes at the step's start; e's increment
    beta, gamma = wire.beta_gamma
    fixed = (h_rows, u, slopes, mount_strokes, w, z, s_k, de, np.array([beta, gamma, wire.exponent]), ITERATIONS)
    fixed += (kernel.workspace(n_h),)
    kernel.compile_now()
    if held:
        kernel.advance(*bank.take(choose(0, w[:, 0])), *fixed, 0, n - 1)
        return w, z
    index = None
    for k in range(n - 1):
        found = choose(k, w[:, k])
        if found != index:
            index = found
            maps = bank.take(index)
        kernel.advance(*maps, *fixed, k, k + 1)
    if n > 1:
        choose(n - 1, w[:, n - 1])  # a schedule's decision at the last sample (applied over no step)
    return w, z


def sine_transmissibility(
    isolator: SixAxisIsolator,
    wire: WireRope,
    freq_hz,
    amplitude: float,
    semi_active_damping=None,
    settle_s: float | None = None,
    fit_s: float = 1.0,
    h: float = 5e-4,
) -> np.ndarray:
    """|payload translation / mount translation| (3, nf) along x, y, z (at the reference point, as
    `six_axis.axis_transmissibility`) for a mount sine of `amplitude` m along that axis alone at each frequency
    (Hz), the semi-active elements at `semi_active_damping` (N s m-1; None: their own): the response's component
    at the drive frequency (a least-squares sine and offset over the last `fit_s` s of a run of settle_s + fit_s s
    from rest on a grid of h s) over the amplitude; settle_s None: seven of the linear isolator's slowest 1/e decay
    times (its start-up transient left below 0.1 %; the hysteresis only adds damping). A wire rope's
    transmissibility depends on the amplitude; below its yield stroke it is the linear isolator's."""
    f = np.atleast_1d(np.asarray(freq_hz, dtype=float))
    if settle_s is None:
        poles = np.linalg.eigvals(state_space(isolator, semi_active_damping).a)
        settle_s = 7.0 * float(np.max(-1.0 / poles.real))
    t = np.arange(int(round((settle_s + fit_s) / h)) + 1) * h
    u = np.zeros((3, f.size, t.size, 6))
    for axis in range(3):
        u[axis, :, :, axis] = amplitude * np.sin(2 * np.pi * f[:, None] * t)
    bank = _Bank(isolator, wire, h)
    fixed = [bank.find(semi_active_damping)] * (3 * f.size)
    w, _ = _steps(wire, bank, u.reshape(-1, t.size, 6), len(fixed), lambda k, w_k: fixed)
    keep = t >= t[-1] - fit_s
    out = np.empty((3, f.size))
    for axis in range(3):
        for j, freq in enumerate(f):
            phase = 2 * np.pi * freq * t[keep]
            basis = np.column_stack([np.sin(phase), np.cos(phase), np.ones_like(phase)])
            coef = np.linalg.lstsq(basis, w[axis * f.size + j, keep, axis], rcond=None)[0]
            out[axis, j] = math.hypot(coef[0], coef[1]) / amplitude
    return out


def run(isolator: SixAxisIsolator, wire: WireRope, time, translation, rotation, schedule=None) -> xr.Dataset:
    """The payload's response to a mount motion (`integrate_scheduled`) with the semi-active elements' damping
    from `schedule` (None: their own; an array (n_semi,) or (n_semi, n) N s m-1; or a callable, the protocol of
    `uavdamp.platform.six_axis_run.run`): the variables of that run plus each hysteretic axis's z (m) and force
    (1 - alpha) k z (N)."""
    t = np.asarray(time, dtype=float)
    w, z, u, applied = integrate_scheduled(isolator, wire, t, translation, rotation, [schedule])
    return _dataset(isolator, wire, t, u, w[0], z[0], applied[0])


def _dataset(isolator, wire, t, u, w, z, applied) -> xr.Dataset:
    outputs = state_space(isolator)  # its outputs (q, strokes, stroke rates) do not depend on the stiffness
    rates = np.vstack([np.diff(u, axis=0), np.diff(u, axis=0)[-1:]]) / (t[1] - t[0])
    y = w @ outputs.c.T + u @ outputs.du.T + rates @ outputs.dv.T
    k_h = _model(isolator, wire, None)[2]
    ds = run_dataset(isolator, t, u, y, applied, w[:, 6:])
    axes = hysteretic_axes(isolator, wire)
    coord = {
        "hysteretic_axis": (
            "hysteretic_axis",
            [f"{i}_{AXES[a]}" for i, a in axes],
            {"units": "1", "long_name": "element and axis of a Bouc-Wen hysteresis"},
        )
    }
    ds = ds.assign_coords(coord)
    ds["hysteretic_displacement"] = (
        ("hysteretic_axis", "time"),
        z.T,
        {"units": "m", "long_name": "Bouc-Wen hysteretic displacement z of the element's axis"},
    )
    ds["hysteretic_force"] = (
        ("hysteretic_axis", "time"),
        ((1 - wire.alpha) * k_h)[:, None] * z.T,
        {"units": "N", "long_name": "hysteretic part (1 - alpha) k z of the element's spring force on its stroke"},
    )
    ds.attrs["title"] = "Six-axis isolator with wire-rope (Bouc-Wen) elements: payload response to a mount motion"
    ds.attrs |= {"alpha": wire.alpha, "yield_stroke_m": wire.yield_stroke, "exponent": wire.exponent}
    ds.attrs["beta_share"] = wire.beta_share
    return ds
