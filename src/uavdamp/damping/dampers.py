"""Magnetorheological (MR) damper: the phenomenological model of Spencer, Dyke, Sain & Carlson (1997).

    SpencerParams                 the model's parameters, SI; published() (the paper's Table 1), scaled(),
                                  for_platform() (a damper of the platform's size)
    SpencerMR(params, n_axes)     one damper per axis (one command voltage), advanced one solver step at a time
    equivalent_damping(...)       energy per cycle / (pi omega X^2) of a settled sinusoidal stroke, N s m-1
    voltage_for_damping(...)      the command voltage whose equivalent damping is a demand (a monotone table)

The model ("modified Bouc-Wen", J. Eng. Mech. 123(3), 230-238): stroke x (m), internal node y (m), Bouc-Wen
evolutionary variable z (m), filtered command u (V) of the command voltage v (V):

    F  = c1 y' + k1 (x - x0)                                           force to move the stroke, N
    z' = -gamma |x' - y'| z |z|^(n-1) - beta (x' - y') |z|^n + A (x' - y')
    y' = (alpha z + c0 x' + k0 (x - y)) / (c0 + c1)
    u' = -eta (u - v),   alpha = alpha_a + alpha_b u,  c0 = c0a + c0b u,  c1 = c1a + c1b u

y' is the force balance at the massless node y: alpha z + c0 (x' - y') + k0 (x - y) = c1 y' (so c0 multiplies x',
not x' - y', once solved for y'). F is the force on the stroke's moving end needed to move it (the force on the
base, with stroke = base - mount, is -F). Under a monotonic stroke z tends to z_max = (A / (gamma + beta))^(1/n)
(gamma >= |beta|); alpha z_max is the field-dependent yield force.

Scaling (choice, `SpencerParams.scaled`, `for_platform`): the paper's damper gives kN at cm strokes; the
platform needs tens of N s m-1 at mm. With x, y, z -> s x, s y, s z and F -> f F at unchanged times, the equations
hold again when every stiffness and damping (alpha, c0, c1, k0, k1, per V too) is multiplied by f / s, x0 by s,
gamma and beta by s^-n (A, n, eta unchanged): the loop shape in x / s and all time constants (eta, the yield
transition) are the paper's. c_eq(v) -> (f / s) c_eq(v) at the stroke s X: s sets where on the published
damper's amplitude curve the reference stroke falls (so the ratio c_eq(v_max) / c_eq(0) there), f / s the level.

Integration (choice): the states (y, z) per sub-step with the two-stage L-stable SDIRK of Alexander (1977, order
2, stiffly accurate); each stage's implicit equation is linear in y, which is eliminated, leaving one scalar
equation in z per axis, solved by Newton (its residual is increasing in z on |z| <= z_max, so the root is unique).
u is exact for a command held over the step. The stroke over a step is the cubic Hermite interpolant of (x, x')
at its ends (consistent: x' is its derivative), or, when only the start is given, x' held and x linear.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from uavdamp.damping import spencer_kernel

V_MAX = 2.25  # V, the largest command of the paper's tests (0, 0.75, 1.5, 2.25 V); the table's range
REFERENCE_FREQUENCY_HZ = 8.0  # Hz, reference stroke (choice: the isolator's 8 Hz design point, config platform)
REFERENCE_VELOCITY = 0.05  # m s-1, reference stroke rate amplitude (choice: ~1 mm at 8 Hz, the paper's 1.3 mm input)
MAX_SUBSTEP = 5e-4  # s, default internal sub-step (choice: force within 0.2 % of Radau, tests/test_dampers.py)

_CM = 1e-2  # m per cm: the paper's Table 1 is in N, cm, s and V


@dataclass(frozen=True)
class SpencerParams:
    """Parameters of the Spencer model, SI: c (N s m-1), c_b (N s m-1 V-1), k (N m-1), alpha_a (N m-1), alpha_b
    (N m-1 V-1), x0 (m), gamma and beta (m^-n), A and n (1), eta (s-1)."""

    c0a: float
    c0b: float
    k0: float
    c1a: float
    c1b: float
    k1: float
    x0: float
    alpha_a: float
    alpha_b: float
    gamma: float
    beta: float
    A: float
    n: float
    eta: float

    def __post_init__(self):
        values = [getattr(self, f) for f in self.__dataclass_fields__]
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f"Spencer parameters must be finite, got {self}")
        if min(self.c0a, self.c1a) <= 0 or min(self.c0b, self.c1b, self.k0, self.k1, self.alpha_a, self.alpha_b) < 0:
            raise ValueError("Spencer parameters: need c0a, c1a > 0 and c0b, c1b, k0, k1, alpha_a, alpha_b >= 0")
        if self.A <= 0 or self.n < 1 or self.eta <= 0 or self.gamma < abs(self.beta) or self.gamma + self.beta <= 0:
            raise ValueError("Spencer parameters: need A > 0, n >= 1, eta > 0 and gamma >= |beta|, gamma + beta > 0")

    @classmethod
    def published(cls) -> SpencerParams:
        """Table 1 of Spencer et al. (1997), converted from N, cm, s, V: the Lord prototype damper."""
        return cls(
            c0a=21.0 / _CM,  # 21.0 N s cm-1
            c0b=3.50 / _CM,  # 3.50 N s cm-1 V-1
            k0=46.9 / _CM,  # 46.9 N cm-1
            c1a=283.0 / _CM,  # 283 N s cm-1
            c1b=2.95 / _CM,  # 2.95 N s cm-1 V-1
            k1=5.00 / _CM,  # 5.00 N cm-1
            x0=14.3 * _CM,  # 14.3 cm
            alpha_a=140.0 / _CM,  # 140 N cm-1
            alpha_b=695.0 / _CM,  # 695 N cm-1 V-1
            gamma=363.0 / _CM**2,  # 363 cm-2
            beta=363.0 / _CM**2,  # 363 cm-2
            A=301.0,
            n=2.0,
            eta=190.0,  # 190 s-1
        )

    def scaled(self, force_scale: float, stroke_scale: float) -> SpencerParams:
        """The damper whose force is force_scale x this one's for a stroke stroke_scale x this one's, at the same
        times: x -> s x, y -> s y, z -> s z, F -> f F. Every N m-1 and N s m-1 term (per V too) scales by f / s,
        x0 by s, gamma and beta by s^-n; A, n, eta are unchanged (exact: the model's equations are invariant)."""
        f, s = float(force_scale), float(stroke_scale)
        if not (f > 0 and s > 0 and math.isfinite(f) and math.isfinite(s)):
            raise ValueError(f"force_scale and stroke_scale must be finite and > 0, got {force_scale}, {stroke_scale}")
        g = f / s
        return replace(
            self,
            **{k: getattr(self, k) * g for k in ("c0a", "c0b", "k0", "c1a", "c1b", "k1", "alpha_a", "alpha_b")},
            x0=self.x0 * s,
            gamma=self.gamma / s**self.n,
            beta=self.beta / s**self.n,
        )

    @classmethod
    def for_platform(
        cls,
        c_min: float,
        c_max: float,
        *,
        velocity: float = REFERENCE_VELOCITY,
        frequency: float = REFERENCE_FREQUENCY_HZ,
        v_max: float = V_MAX,
        preload: bool = False,
    ) -> SpencerParams:
        """The published damper scaled (`scaled`) so that its equivalent damping at a sinusoidal stroke of rate
        amplitude `velocity` (m s-1) and `frequency` (Hz) is c_min at 0 V and c_max at v_max (N s m-1).

        The ratio c_eq(v_max) / c_eq(0) of the published damper depends only on the non-dimensional stroke
        X / s (X = velocity / omega), so s is chosen where it equals c_max / c_min (the root on the large-stroke
        side of its maximum, where the loop is Bingham-like), and then f / s = c_max / c_eq(v_max) at X / s.
        preload False (choice) drops the accumulator offset (x0 = 0: no static force on the isolator)."""
        f, s = _platform_scales(float(c_min), float(c_max), float(velocity), float(frequency), float(v_max))
        out = cls.published().scaled(f, s)
        return out if preload else replace(out, x0=0.0)

    @property
    def z_max(self) -> float:
        """m, the Bouc-Wen variable's bound (A / (gamma + beta))^(1/n), reached under a monotonic stroke."""
        return (self.A / (self.gamma + self.beta)) ** (1.0 / self.n)


@lru_cache(maxsize=16)
def _platform_scales(c_min: float, c_max: float, velocity: float, frequency: float, v_max: float):
    """(force_scale, stroke_scale) of `SpencerParams.for_platform` (cached: about 40 loop simulations)."""
    from scipy.optimize import brentq

    if not 0 < c_min < c_max:
        raise ValueError(f"need 0 < c_min < c_max (an MR damper's off-state damping is > 0), got {c_min}, {c_max}")
    base, omega = SpencerParams.published(), 2 * math.pi * frequency

    def ceq(stroke: float, volts: float) -> float:  # published damper, stroke amplitude m
        return equivalent_damping(base, volts, omega * stroke, frequency)

    target = math.log(c_max / c_min)

    def excess(log_stroke: float) -> float:
        stroke = math.exp(log_stroke)
        return math.log(ceq(stroke, v_max) / ceq(stroke, 0.0)) - target

    grid = np.log(np.geomspace(1e-5, 1e-1, 13))  # published strokes: 10 um (pre-yield) to 10 cm
    values = np.array([excess(g) for g in grid])
    peak = int(np.argmax(values))
    if values[peak] < 0:
        ratio = math.exp(values[peak] + target)
        raise ValueError(f"c_max / c_min = {c_max / c_min:.3g} exceeds the published damper's largest, {ratio:.3g}")
    below = np.nonzero(values[peak:] < 0)[0]
    if below.size == 0:
        raise ValueError(f"c_max / c_min = {c_max / c_min:.3g} is below the ratio at a 10 cm stroke: lower c_min")
    k = peak + below[0]
    stroke = math.exp(brentq(excess, grid[k - 1], grid[k], xtol=1e-6))
    s = velocity / omega / stroke
    return s * c_max / ceq(stroke, v_max), s


class SpencerMR:
    """Spencer MR dampers on `n_axes` axes (default 2: y, z) under one command voltage.

    States (arrays, one entry per axis): y (m), z (m), u (V). `step` advances them over one solver step and
    returns the force F (N, per axis) at the step's end; `force_mean` is then F averaged over the step (N, the
    trapezoidal rule on the sub-steps: the impulse / h a plant holding one force over the step should apply).
    Sub-steps: ceil(h / max_substep) equal ones (choice; see the module docstring for the scheme), each axis
    advanced on its own by the compiled scheme (`uavdamp.damping.spencer_kernel`: the axes do not interact).
    """

    def __init__(self, params: SpencerParams, n_axes: int = 2, max_substep: float = MAX_SUBSTEP):
        if not max_substep > 0:
            raise ValueError(f"max_substep: must be > 0, got {max_substep}")
        self.params, self.n_axes, self.max_substep = params, int(n_axes), float(max_substep)
        self._step, self._packed = spencer_kernel.step, spencer_kernel.packed(params)
        self.reset()

    def reset(self, x0=0.0) -> None:
        """At rest at the stroke x0 (m, scalar or per axis): y = x0 (k0 unstretched), z = 0, u = 0 V."""
        self.y = np.broadcast_to(np.asarray(x0, float), (self.n_axes,)).copy()
        self.z = np.zeros(self.n_axes)
        self.u = np.zeros(self.n_axes)
        self.force_mean = np.zeros(self.n_axes)

    def force(self, x, xd) -> np.ndarray:
        """F (N) at the present states for the stroke x (m) and rate xd (m s-1)."""
        return spencer_kernel.force_at(self._packed, (self.y, self.z, self.u), x, xd)

    def step(self, h: float, voltage, x0, xd0, x1=None, xd1=None) -> np.ndarray:
        """Advance y, z, u over a step h (s) with the command `voltage` (V, held) and the stroke x (m) and rate
        x' (m s-1) at the step's start (x0, xd0) and end (x1, xd1; None: x' held, x linear); F (N) at the end."""
        if (x1 is None) != (xd1 is None):
            raise ValueError("give both the stroke and its rate at the step's end, or neither")
        if x1 is None:
            x1, xd1 = np.asarray(x0, float) + h * np.asarray(xd0, float), xd0
        states, stroke = (self.y, self.z, self.u), (x0, xd0, x1, xd1)
        f_end, self.force_mean = self._step(self._packed, states, voltage, h, self.max_substep, stroke)
        return f_end

    def coupled_step(self, h: float, voltage: float, start, free_end, g_rows) -> np.ndarray:
        """The coupling's predictor-corrector step (`spencer_kernel.couple`) at the held `voltage` (V) from the stroke
        `start` = (x0 m, xd0 m s-1) with the plant's free stroke and rates `free_end` and force response `g_rows`;
        F (N) at the end, and `force_mean` the step's mean."""
        f_end, self.force_mean = spencer_kernel.coupled_step(
            self._packed, (self.y, self.z, self.u), voltage, h, self.max_substep, start, free_end, g_rows
        )
        return f_end


def _settled_loop(params: SpencerParams, voltage: float, velocity: float, frequency: float, cycles: int, n: int):
    """(x', F) over the last of `cycles` periods of x = X sin(omega t), X = velocity / omega, u settled at
    `voltage` from the start; n steps a period."""
    omega = 2 * math.pi * frequency
    amp, h = velocity / omega, 1.0 / (frequency * n)
    damper = SpencerMR(params, n_axes=1, max_substep=min(MAX_SUBSTEP, h))
    damper.u[:] = voltage
    t = np.arange(cycles * n + 1) * h
    x, xd = amp * np.sin(omega * t), velocity * np.cos(omega * t)
    force = np.empty_like(t)
    force[0] = damper.force(x[:1], xd[:1])[0]
    for k in range(cycles * n):
        force[k + 1] = damper.step(h, voltage, x[k : k + 1], xd[k : k + 1], x[k + 1 : k + 2], xd[k + 1 : k + 2])[0]
    last = slice((cycles - 1) * n, None)
    return xd[last], force[last]


def equivalent_damping(
    params: SpencerParams, voltage: float, velocity: float, frequency: float, *, cycles: int = 2, n: int = 200
) -> float:
    """Equivalent viscous damping, N s m-1: the energy the damper takes in a settled cycle of x = X sin(omega t)
    (rate amplitude `velocity` m s-1, `frequency` Hz, command `voltage` V held, u settled), over pi omega X^2.
    The energy is the integral of F x' dt over the last of `cycles` periods (trapezoidal rule, n steps a period)."""
    xd, force = _settled_loop(params, voltage, velocity, frequency, cycles, n)
    h = 1.0 / (frequency * n)
    power = force * xd
    energy = h * (power.sum() - 0.5 * (power[0] + power[-1]))
    omega = 2 * math.pi * frequency
    return energy * omega / (math.pi * velocity**2)  # E / (pi omega X^2), X = velocity / omega


@lru_cache(maxsize=32)
def damping_table(
    params: SpencerParams, v_ref: float, frequency: float = REFERENCE_FREQUENCY_HZ, v_max: float = V_MAX, n: int = 19
) -> tuple[np.ndarray, np.ndarray]:
    """(voltages V, equivalent damping N s m-1): c_eq on n equal voltage steps over [0, v_max] at the reference
    stroke (rate amplitude v_ref m s-1, `frequency` Hz); ValueError unless strictly increasing. Cached."""
    volts = np.linspace(0.0, v_max, n)
    ceq = np.array([equivalent_damping(params, v, v_ref, frequency) for v in volts])
    if not np.all(np.diff(ceq) > 0):
        raise ValueError(f"equivalent damping is not increasing in the command at {v_ref} m/s, {frequency} Hz")
    volts.setflags(write=False)
    ceq.setflags(write=False)
    return volts, ceq


def voltage_for_damping(
    c_demand, params: SpencerParams, v_ref: float = REFERENCE_VELOCITY, *, frequency=REFERENCE_FREQUENCY_HZ, v_max=V_MAX
):
    """The command voltage (V, in [0, v_max]) whose equivalent damping at the reference stroke (rate amplitude
    v_ref m s-1, `frequency` Hz) is c_demand (N s m-1): `damping_table` inverted by linear interpolation;
    demands below c_eq(0 V) give 0 V, above c_eq(v_max) give v_max."""
    volts, ceq = damping_table(params, float(v_ref), float(frequency), float(v_max))
    out = np.interp(np.asarray(c_demand, float), ceq, volts)
    return float(out) if np.ndim(out) == 0 else out
