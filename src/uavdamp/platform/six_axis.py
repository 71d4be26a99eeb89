"""A six-axis isolator: a rigid payload on N spring-damper elements between the mount plate and the payload base.

Coordinates q = (x, y, z, rx, ry, rz): the payload's translation (m) at its reference point and its small rotation
(rad) about the mount axes (x forward, y left, z up), both from the rest position; the mount plate's motion u has
the same six coordinates at the same point. Element i sits at r_i (m, from the reference point); its
translational stroke is s_i = T_i (q - u) with T_i = [I, -skew(r_i)], so the element set's stiffness about the
reference point is K = sum T_i^T diag(kx, ky, kz)_i T_i (rotational stiffness from the geometry) plus the
elements' own rotational stiffness (zero unless given), and likewise for the damping. Equations of motion:

    M q'' + C (q' - u') + K (q - u) = 0

with M the rigid-body mass matrix about the reference point and K the elastic stiffness plus, under gravity
(`SixAxisIsolator.gravity`, m s-2 along -z), the geometric stiffness of the weight and of the elements' static
preloads that carry it (`geometric_stiffness`: -m g h in tilt for a centre of mass h above symmetric elements).
Linear about the loaded rest position (the positions are those there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import eigh

from uavdamp.contract import XYZ
from uavdamp.platform.statespace import StateSpace

KINDS = ("elastomer", "rubber_ball", "wire_rope")
AXES = XYZ  # the payload's translation and rotation axes
DOFS = ("x", "y", "z", "rx", "ry", "rz")
WHERE = "platform.six_axis"  # the config section these parameters would come from


def _finite(values, n: int, key: str, *, nonnegative: bool = True) -> tuple[float, ...]:
    out = tuple(float(v) for v in np.asarray(values, dtype=float).ravel())
    if len(out) != n or not all(math.isfinite(v) for v in out):
        raise ValueError(f"{key}: must be {n} finite numbers, got {values!r}")
    if nonnegative and min(out) < 0:
        raise ValueError(f"{key}: must be >= 0, got {values!r}")
    return out


@dataclass(frozen=True)
class Element:
    """One isolator element: position (m, from the payload's reference point), translational stiffness (kx, ky,
    kz) N m-1 and viscous damping (cx, cy, cz) N s m-1 along the mount axes, its kind, and whether its damper is
    semi-active (then a schedule's C replaces its damping along `damper_axes`). rotational_stiffness (N m rad-1)
    and rotational_damping (N m s rad-1) are the element's own (about its point; zero for a point element)."""

    position: tuple[float, float, float]
    stiffness: tuple[float, float, float]
    damping: tuple[float, float, float] = (0.0, 0.0, 0.0)
    kind: str = "elastomer"
    semi_active: bool = False
    damper_axes: tuple[str, ...] = AXES
    rotational_stiffness: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotational_damping: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def checked(self, where: str) -> Element:
        """This element with its numbers as float tuples; ValueError naming `where` + the key it breaks."""
        if self.kind not in KINDS:
            raise ValueError(f"{where}.kind: must be one of {list(KINDS)}, got {self.kind!r}")
        axes = tuple(self.damper_axes)
        if not axes or len(set(axes)) != len(axes) or not set(axes) <= set(AXES):
            raise ValueError(f"{where}.damper_axes: must be distinct names of {list(AXES)}, got {self.damper_axes!r}")
        return Element(
            position=_finite(self.position, 3, f"{where}.position_m", nonnegative=False),
            stiffness=_finite(self.stiffness, 3, f"{where}.stiffness_n_m"),
            damping=_finite(self.damping, 3, f"{where}.damping_n_s_m"),
            kind=self.kind,
            semi_active=bool(self.semi_active),
            damper_axes=axes,
            rotational_stiffness=_finite(self.rotational_stiffness, 3, f"{where}.rotational_stiffness_n_m_rad"),
            rotational_damping=_finite(self.rotational_damping, 3, f"{where}.rotational_damping_n_m_s_rad"),
        )


@dataclass(frozen=True)
class Payload:
    """The rigid payload (gimbal base, gimbal and camera): mass kg, centre of mass (m, from the reference point)
    and inertia tensor (kg m2, 3x3, about the centre of mass, mount axes)."""

    mass: float
    com: tuple[float, float, float]
    inertia: tuple[tuple[float, float, float], ...]

    def __post_init__(self):
        where = f"{WHERE}.payload"
        if not (math.isfinite(self.mass) and self.mass > 0):
            raise ValueError(f"{where}.mass_kg: must be > 0, got {self.mass}")
        _finite(self.com, 3, f"{where}.com_m", nonnegative=False)
        j = np.asarray(self.inertia, dtype=float)
        if (
            j.shape != (3, 3)
            or not np.all(np.isfinite(j))
            or not np.allclose(j, j.T, rtol=0, atol=1e-12 * abs(j).max())
        ):
            raise ValueError(f"{where}.inertia_kg_m2: must be a finite symmetric 3x3 matrix, got {self.inertia!r}")
        if np.linalg.eigvalsh(j).min() <= 0:
            raise ValueError(f"{where}.inertia_kg_m2: must be positive definite, got {self.inertia!r}")

    @classmethod
    def box(cls, mass: float, size: tuple[float, float, float], com: tuple[float, float, float]) -> Payload:
        """A uniform box of edges `size` (m, x y z) with its centre at `com` (m): I = m (b^2 + c^2) / 12 etc."""
        a, b, c = (float(s) for s in size)
        j = mass / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
        return cls(float(mass), tuple(float(v) for v in com), tuple(map(tuple, j)))


@dataclass(frozen=True)
class SixAxisIsolator:
    """The payload on its elements (positions from the payload's reference point, the mount point at rest)."""

    elements: tuple[Element, ...]
    payload: Payload
    gravity: float = 0.0  # m s-2, along -z of the mount axes (0: the weightless isolator)

    def __post_init__(self):
        if not (math.isfinite(self.gravity) and self.gravity >= 0):
            raise ValueError(f"{WHERE}.gravity_m_s2: must be >= 0, got {self.gravity}")
        if len(self.elements) == 0:
            raise ValueError(f"{WHERE}.elements: needs at least one element")
        checked = tuple(e.checked(f"{WHERE}.elements[{i}]") for i, e in enumerate(self.elements))
        object.__setattr__(self, "elements", checked)
        k = stiffness_matrix(self)
        if np.linalg.eigvalsh(k).min() <= 1e-12 * np.abs(k).max():
            raise ValueError(
                f"{WHERE}.elements: the stiffness matrix is singular (a rigid-body motion the elements do not "
                "resist): give stiffness on enough axes and positions"
            )
        if np.linalg.eigvalsh(total_stiffness(self)).min() <= 1e-12 * np.abs(k).max():
            raise ValueError(
                f"{WHERE}.gravity_m_s2: the weight tips the payload over (elastic plus geometric stiffness not "
                "positive definite): lower the centre of mass or spread the elements"
            )

    @property
    def semi_active(self) -> tuple[int, ...]:
        """Indices of the semi-active elements."""
        return tuple(i for i, e in enumerate(self.elements) if e.semi_active)

    @property
    def n_elements(self) -> int:
        return len(self.elements)


def skew(r) -> np.ndarray:
    """The cross-product matrix of r: skew(r) @ v = r x v."""
    x, y, z = np.asarray(r, dtype=float)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def transform(r) -> np.ndarray:
    """T (3, 6): the translation of a point at r (m) of a body with 6-DOF motion (translation, small rotation)."""
    return np.hstack([np.eye(3), -skew(r)])


def _element_sum(isolator: SixAxisIsolator, reference, translational, rotational) -> np.ndarray:
    p = np.zeros(3) if reference is None else np.asarray(reference, dtype=float)
    out = np.zeros((6, 6))
    for i, e in enumerate(isolator.elements):
        t = transform(np.asarray(e.position) - p)
        out += t.T @ np.diag(translational(i, e)) @ t
        out[3:, 3:] += np.diag(rotational(i, e))
    return out


def stiffness_matrix(isolator: SixAxisIsolator, reference=None) -> np.ndarray:
    """K (6, 6) of the element set about `reference` (m, default the payload's reference point): N m-1, N rad-1,
    N m rad-1 in the blocks of translation and rotation."""
    return _element_sum(isolator, reference, lambda i, e: e.stiffness, lambda i, e: e.rotational_stiffness)


def element_damping(isolator: SixAxisIsolator, semi_active_damping=None) -> np.ndarray:
    """Translational damping (N, 3) N s m-1 per element: its own, with the semi-active elements' C (one value per
    semi-active element, in `isolator.semi_active` order) replacing it along their damper axes."""
    c = np.array([e.damping for e in isolator.elements])
    if semi_active_damping is None:
        return c
    values = np.asarray(semi_active_damping, dtype=float).ravel()
    index = isolator.semi_active
    if values.size != len(index):
        raise ValueError(f"semi-active damping: need {len(index)} values (one per semi-active element), got {values}")
    if not np.all(np.isfinite(values)) or values.min(initial=0.0) < 0:
        raise ValueError(f"semi-active damping: must be finite and >= 0 N s m-1, got {values}")
    for i, value in zip(index, values, strict=True):
        for axis in isolator.elements[i].damper_axes:
            c[i, AXES.index(axis)] = value
    return c


def damping_matrix(isolator: SixAxisIsolator, semi_active_damping=None, reference=None) -> np.ndarray:
    """C (6, 6) of the element set about `reference` (see `stiffness_matrix`), the semi-active elements at
    `semi_active_damping` (N s m-1 each; None: their own damping)."""
    c = element_damping(isolator, semi_active_damping)
    return _element_sum(isolator, reference, lambda i, e: c[i], lambda i, e: e.rotational_damping)


def mass_matrix(payload: Payload, reference=None) -> np.ndarray:
    """M (6, 6) of the rigid payload about `reference` (m, default its reference point): m T_c^T T_c + the
    rotational inertia about the centre of mass, T_c = [I, -skew(c)] for the centre of mass c from the point."""
    p = np.zeros(3) if reference is None else np.asarray(reference, dtype=float)
    t = transform(np.asarray(payload.com) - p)
    m = payload.mass * t.T @ t
    m[3:, 3:] += np.asarray(payload.inertia, dtype=float)
    return m


def rigid_body_modes(isolator: SixAxisIsolator) -> tuple[np.ndarray, np.ndarray]:
    """The six undamped rigid-body modes: natural frequencies (6,) Hz ascending and mode shapes (6, 6), columns
    over `DOFS` (m, rad), mass-normalised (phi^T M phi = I), by the generalised eigenproblem K phi = w^2 M phi."""
    w2, phi = eigh(total_stiffness(isolator), mass_matrix(isolator.payload))
    return np.sqrt(np.clip(w2, 0.0, None)) / (2 * np.pi), phi


def dominant_dofs(shapes: np.ndarray, payload: Payload, share: float = 0.1) -> list[list[str]]:
    """Per mode, the DOFs (of `DOFS`) holding at least `share` of its kinetic energy, largest first (the
    translation at the centre of mass, so that a rocking mode reads as rotation and not as sway; the rotation's
    share from the inertia's diagonal, products of inertia left out of this label)."""
    com = np.asarray(payload.com, dtype=float)
    moved = np.vstack([transform(com), np.hstack([np.zeros((3, 3)), np.eye(3)])]) @ shapes  # COM motion
    energy = np.vstack(
        [payload.mass * moved[:3] ** 2, np.asarray(payload.inertia).diagonal()[:, None] * moved[3:] ** 2]
    )
    energy = energy / energy.sum(axis=0)
    return [[DOFS[j] for j in np.argsort(-energy[:, k]) if energy[j, k] >= share] for k in range(shapes.shape[1])]


def _point_hessian(force: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Rotation block (3, 3) of the potential -F . (R r) of a constant force F at a body point r, at R = I:
    (F . r) I - (F r^T + r F^T) / 2 (from R r = r + theta x r + theta x (theta x r) / 2 + ...)."""
    return (force @ r) * np.eye(3) - (np.outer(force, r) + np.outer(r, force)) / 2


def static_element_forces(isolator: SixAxisIsolator) -> np.ndarray:
    """(N, 3) N: the force each element exerts on the payload at the loaded rest position (its preload), from
    the static deflection K q_s = the weight's generalised force (statically indeterminate sets included)."""
    p = isolator.payload
    weight = np.array([0.0, 0.0, -p.mass * isolator.gravity])
    q_static = np.linalg.solve(stiffness_matrix(isolator), transform(p.com).T @ weight)
    return np.array([-np.asarray(e.stiffness) * (transform(e.position) @ q_static) for e in isolator.elements])


def geometric_stiffness(isolator: SixAxisIsolator) -> np.ndarray:
    """(6, 6) N m rad-1, rotation block only: the weight at the centre of mass and the elements' preloads as
    constant forces at their points (the Hessian of their potential at the rest position); zero without gravity."""
    out = np.zeros((6, 6))
    if isolator.gravity == 0:
        return out
    p = isolator.payload
    weight = np.array([0.0, 0.0, -p.mass * isolator.gravity])
    out[3:, 3:] = _point_hessian(weight, np.asarray(p.com))
    for force, e in zip(static_element_forces(isolator), isolator.elements, strict=True):
        out[3:, 3:] += _point_hessian(force, np.asarray(e.position))
    return out


def total_stiffness(isolator: SixAxisIsolator) -> np.ndarray:
    """K (6, 6) of the dynamics: elastic (`stiffness_matrix`) plus geometric (`geometric_stiffness`)."""
    return stiffness_matrix(isolator) + geometric_stiffness(isolator)


def square_layout(
    payload: Payload,
    half_spacing: float,
    stiffness: tuple[float, float, float],
    damping: tuple[float, float, float] = (0.0, 0.0, 0.0),
    *,
    kind: str = "rubber_ball",
    semi_active: bool = False,
    gravity: float = 0.0,
) -> SixAxisIsolator:
    """Four equal elements at the corners (+-a, +-a, 0) of a square plate (a = half_spacing, m) whose centre is the
    payload's reference point; the payload's centre of mass (`payload.com`, e.g. (0, 0, h)) sits above it;
    gravity m s-2 (`SixAxisIsolator.gravity`)."""
    if not (math.isfinite(half_spacing) and half_spacing > 0):
        raise ValueError(f"{WHERE}.half_spacing_m: must be > 0, got {half_spacing}")
    a = float(half_spacing)
    corners = [(sx * a, sy * a, 0.0) for sx in (1, -1) for sy in (1, -1)]
    elements = tuple(Element(c, tuple(stiffness), tuple(damping), kind, semi_active) for c in corners)
    return SixAxisIsolator(elements, payload, gravity)


def paper_yz(
    total_mass: float,
    stiffness: float,
    damping: float = 0.0,
    *,
    inertia: float = 1e-3,
    rigid_frequency_hz: float = 1000.0,
    rigid_damping_ratio: float = 0.7,
) -> SixAxisIsolator:
    """The paper's Y-Z isolator as a six-axis isolator: the platform lumped into one body (total_mass kg, centre
    of mass at the reference point, isotropic inertia kg m2) on one semi-active element at that point with
    stiffness K (N m-1) and damping C (N s m-1) in y and z; x and the three rotations are near-rigid: element
    stiffness m w_r^2 (x) and I w_r^2 (rotation, its own rotational stiffness) at w_r = 2 pi rigid_frequency_hz,
    with damping ratio rigid_damping_ratio there (so those modes do not ring). The y and z equations are exactly
    m y'' + C (y' - u_y') + K (y - u_y) = 0 (no coupling: the element is at the centre of mass); x and rotation
    follow the mount to O((f / rigid_frequency_hz)^2). Gravity would add no geometric stiffness here (the weight
    and the element's preload act at one point), so it is left at 0."""
    w = 2 * np.pi * rigid_frequency_hz
    k_x, k_r = total_mass * w * w, inertia * w * w
    c_x, c_r = 2 * rigid_damping_ratio * total_mass * w, 2 * rigid_damping_ratio * inertia * w
    element = Element(
        position=(0.0, 0.0, 0.0),
        stiffness=(k_x, stiffness, stiffness),
        damping=(c_x, damping, damping),
        kind="elastomer",
        semi_active=True,
        damper_axes=("y", "z"),
        rotational_stiffness=(k_r, k_r, k_r),
        rotational_damping=(c_r, c_r, c_r),
    )
    payload = Payload(float(total_mass), (0.0, 0.0, 0.0), tuple(map(tuple, inertia * np.eye(3))))
    return SixAxisIsolator((element,), payload)


def strokes_matrix(isolator: SixAxisIsolator) -> np.ndarray:
    """(3 N, 6): the elements' translational strokes (x, y, z per element, m) of a relative 6-DOF motion q - u."""
    return np.vstack([transform(e.position) for e in isolator.elements])


def output_names(isolator: SixAxisIsolator) -> list[str]:
    """Names of the state-space outputs: the payload's DOFS, then each element's strokes, then their rates."""
    n = isolator.n_elements
    strokes = [f"stroke_{i}_{a}" for i in range(n) for a in AXES]
    return [*DOFS, *strokes, *(f"{s}_rate" for s in strokes)]


def state_space(isolator: SixAxisIsolator, semi_active_damping=None) -> StateSpace:
    """The linear model driven by the mount's 6-DOF motion u (m, rad) and its rate v: a
    `uavdamp.platform.statespace.StateSpace` with states (q, q'), inputs (u, v) and outputs `output_names`:
    the payload's q (m, rad), the element strokes T_i (q - u) (m) and their rates T_i (q' - v) (m s-1)."""
    m = mass_matrix(isolator.payload)
    k, c = total_stiffness(isolator), damping_matrix(isolator, semi_active_damping)
    mk, mc = np.linalg.solve(m, k), np.linalg.solve(m, c)
    zero, eye = np.zeros((6, 6)), np.eye(6)
    a = np.block([[zero, eye], [-mk, -mc]])
    b = np.block([[zero, zero], [mk, mc]])
    t = strokes_matrix(isolator)
    z3 = np.zeros_like(t)
    out_c = np.vstack([np.hstack([eye, zero]), np.hstack([t, z3]), np.hstack([z3, t])])
    du = np.vstack([zero, -t, z3])
    dv = np.vstack([zero, z3, -t])
    return StateSpace(a=a, b=b, c=out_c, du=du, dv=dv)


def transmissibility(isolator: SixAxisIsolator, freq_hz, semi_active_damping=None) -> np.ndarray:
    """Complex transmissibility (nf, 6, 6): payload DOF (row) per unit mount DOF (column) at each frequency (Hz),
    both at the reference point, (K - w^2 M + i w C)^-1 (K + i w C)."""
    omega = 2 * np.pi * np.atleast_1d(np.asarray(freq_hz, dtype=float))
    m = mass_matrix(isolator.payload)
    k, c = total_stiffness(isolator), damping_matrix(isolator, semi_active_damping)
    transmitted = k + 1j * omega[:, None, None] * c
    return np.linalg.solve(transmitted - omega[:, None, None] ** 2 * m, transmitted)


def axis_transmissibility(isolator: SixAxisIsolator, freq_hz, semi_active_damping=None) -> np.ndarray:
    """|payload DOF / the same mount DOF| (nf, 6) per axis of `DOFS` (1: translation per translation, rotation
    per rotation): the isolator maker's per-axis curve."""
    h = transmissibility(isolator, freq_hz, semi_active_damping)
    return np.abs(np.diagonal(h, axis1=1, axis2=2))
