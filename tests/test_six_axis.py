"""The six-axis isolator: matrices and modes against hand-derived closed forms and Exudyn's eigen-analysis, the
transmissibility against the SDOF closed form, the time-domain run against the transmissibility and an
independent ODE integration, and the paper's Y-Z isolator as a special case."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from conftest import platform_params
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from uavdamp.platform import six_axis_exudyn
from uavdamp.platform.six_axis import (
    DOFS,
    Element,
    Payload,
    SixAxisIsolator,
    axis_transmissibility,
    damping_matrix,
    dominant_dofs,
    mass_matrix,
    paper_yz,
    rigid_body_modes,
    skew,
    square_layout,
    stiffness_matrix,
    strokes_matrix,
    total_stiffness,
    transmissibility,
)
from uavdamp.platform.six_axis_run import run

# The gimbal layout (choice): a 1.4 kg gimbal + camera as a 150 x 120 x 150 mm box, its centre of mass 50 mm above
# a 100 mm square plate of four rubber balls, each 250 N/m laterally and 500 N/m vertically, 2 N s/m.
GIMBAL = Payload.box(1.4, (0.15, 0.12, 0.15), (0.0, 0.0, 0.05))
A, KL, KZ, C = 0.05, 250.0, 500.0, 2.0
LINE_HZ = 28.0  # a 4/rev line


def gimbal(semi_active: bool = False) -> SixAxisIsolator:
    return square_layout(GIMBAL, A, (KL, KL, KZ), (C, C, C), semi_active=semi_active)


def coupled_pair(k_trans: float, k_rot: float, m: float, j_com: float, h: float) -> np.ndarray:
    """Sway-rocking pair about the plate centre (centre of mass h above it), by hand: M = [[m, m h], [m h, J + m
    h^2]], K = diag(k_trans, k_rot); det(K - lam M) = 0 is m J lam^2 - (k_t (J + m h^2) + k_r m) lam + k_t k_r = 0.
    Returns the two frequencies, Hz."""
    a, b, c = m * j_com, k_trans * (j_com + m * h * h) + k_rot * m, k_trans * k_rot
    root = math.sqrt(b * b - 4 * a * c)
    return np.sqrt(np.array([(b - root) / (2 * a), (b + root) / (2 * a)])) / (2 * np.pi)


def test_symmetric_layout_modes_match_hand_derived_closed_forms():
    freq, shapes = rigid_body_modes(gimbal())
    m, (jx, jy, jz) = GIMBAL.mass, np.diag(GIMBAL.inertia)
    h = GIMBAL.com[2]
    expected = {
        "z": math.sqrt(4 * KZ / m) / (2 * math.pi),  # vertical: sqrt(sum kz / m)
        "rz": math.sqrt(4 * A * A * (KL + KL) / jz) / (2 * math.pi),  # yaw: sqrt(sum (kx y^2 + ky x^2) / Izz)
    }
    x_ry = coupled_pair(4 * KL, 4 * KZ * A * A, m, jy, h)  # x sway with pitch rocking
    y_rx = coupled_pair(4 * KL, 4 * KZ * A * A, m, jx, h)  # y sway with roll rocking
    want = np.sort([expected["z"], expected["rz"], *x_ry, *y_rx])
    np.testing.assert_allclose(freq, want, rtol=1e-10)
    # mass-normalised shapes, and the decoupled modes are pure
    np.testing.assert_allclose(shapes.T @ mass_matrix(GIMBAL) @ shapes, np.eye(6), atol=1e-10)
    np.testing.assert_allclose(
        shapes.T @ stiffness_matrix(gimbal()) @ shapes, np.diag((2 * np.pi * freq) ** 2), atol=1e-6
    )
    names = dominant_dofs(shapes, GIMBAL)
    assert names[int(np.argmin(abs(freq - expected["z"])))] == ["z"]
    assert names[int(np.argmin(abs(freq - expected["rz"])))] == ["rz"]


def test_the_gimbal_layout_stays_below_a_third_of_the_4_per_rev_line():
    """The layout's choice (module constants): all six modes below 28 Hz / 3 = 9.33 Hz."""
    freq, _ = rigid_body_modes(gimbal())
    assert freq.max() < LINE_HZ / 3
    assert freq.min() > 1.0  # and not so soft that the weight sags it far: m g / (4 kz) = 6.9 mm
    assert GIMBAL.mass * 9.80665 / (4 * KZ) < 0.01


def test_gravity_adds_the_hessian_of_the_exact_potential():
    """Under gravity, total_stiffness is the Hessian at rest of the exact potential (finite rotations by scipy's
    rotation vector): four springs each preloaded by m g / 4 (the symmetric layout's share, by hand) plus the
    weight; central differences of step 1e-4 (m, rad) are exact to ~1e-8 relative for this smooth V. And the
    closed form: -m g h added to the tilt stiffness about x and y (h the centre of mass above the elements)."""
    g, below = 9.80665, 0.02  # the plate 20 mm below the reference point: the preloads' own term shows
    plate = square_layout(GIMBAL, A, (KL, KL, KZ)).elements
    iso = SixAxisIsolator(tuple(replace(e, position=(*e.position[:2], -below)) for e in plate), GIMBAL, g)
    m, com = GIMBAL.mass, np.asarray(GIMBAL.com)
    points = np.array([e.position for e in iso.elements])
    k = np.array([e.stiffness for e in iso.elements])
    preload = np.array([0.0, 0.0, -m * g / 4 / KZ])  # spring length offset: force k (0 - offset) = m g / 4 up

    def potential(q):
        rot = Rotation.from_rotvec(q[3:]).as_matrix()
        moved = q[:3] + points @ rot.T - points  # each element point's displacement
        return 0.5 * np.sum(k * (moved + preload) ** 2) + m * g * (q[2] + (rot @ com)[2])

    step, hessian = 1e-4, np.zeros((6, 6))
    e = np.eye(6) * step
    for i in range(6):
        for j in range(6):
            hessian[i, j] = (
                potential(e[i] + e[j]) - potential(e[i] - e[j]) - potential(-e[i] + e[j]) + potential(-e[i] - e[j])
            ) / (4 * step * step)
    np.testing.assert_allclose(total_stiffness(iso), hessian, rtol=0, atol=1e-6 * np.abs(hessian).max())
    shift = total_stiffness(iso) - stiffness_matrix(iso)
    tilt = -m * g * (com[2] + below)  # -m g h, h the centre of mass's height above the elements
    np.testing.assert_allclose(shift, np.diag([0, 0, 0, tilt, tilt, 0]), atol=1e-12)
    with pytest.raises(ValueError, match="gravity_m_s2"):  # tall enough to tip over
        square_layout(Payload.box(1.4, (0.1, 0.1, 0.1), (0.0, 0.0, 0.5)), A, (KL, KL, KZ), gravity=g)


def test_rotational_stiffness_comes_from_the_geometry():
    """One isotropic element k at r: the rotational block is k (|r|^2 I - r r^T), the coupling block k skew(r)."""
    r, k = np.array([0.03, -0.02, 0.05]), 700.0
    # one element alone leaves the rotation about its own point free (a singular K): add it to a stable set and
    # test its contribution by difference
    elements = [Element(tuple(r), (k, k, k)), Element((0.0, 0.0, 0.0), (k, k, k), rotational_stiffness=(1, 1, 1))]
    base = SixAxisIsolator((elements[1],), GIMBAL)
    both = SixAxisIsolator(tuple(elements), GIMBAL)
    added = stiffness_matrix(both) - stiffness_matrix(base)
    np.testing.assert_allclose(added[:3, :3], k * np.eye(3), rtol=1e-12)
    np.testing.assert_allclose(added[3:, 3:], k * (r @ r * np.eye(3) - np.outer(r, r)), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(added[3:, :3], k * skew(r), rtol=1e-12, atol=1e-12)


def asymmetric() -> SixAxisIsolator:
    """Three unequal elements at odd positions under an offset, tilted-inertia payload: every DOF coupled."""
    j = np.array([[6e-3, 4e-4, -3e-4], [4e-4, 5e-3, 2e-4], [-3e-4, 2e-4, 4e-3]])
    payload = Payload(1.3, (0.01, -0.008, 0.045), tuple(map(tuple, j)))
    elements = (
        Element((0.06, 0.01, -0.01), (300.0, 200.0, 600.0), (1.0, 2.0, 3.0), "wire_rope"),
        Element((-0.04, 0.05, 0.0), (250.0, 350.0, 450.0), (2.0, 1.0, 2.0), "elastomer"),
        Element((-0.03, -0.06, 0.01), (400.0, 300.0, 500.0), (1.5, 1.5, 1.5), "rubber_ball", semi_active=True),
    )
    return SixAxisIsolator(elements, payload)


@pytest.mark.parametrize("build", [gimbal, asymmetric, lambda: paper_yz(1.6, 10.0)], ids=["gimbal", "odd", "yz"])
def test_modes_match_exudyns_eigen_analysis(build):
    """Exudyn (rigid body on Cartesian spring-dampers, Tait-Bryan node) gives the same six modes: both solve the
    same well-conditioned symmetric problem in double precision, so 1e-9 relative leaves orders of margin."""
    iso = build()
    freq, shapes = rigid_body_modes(iso)
    freq_exu, shapes_exu = six_axis_exudyn.modes(iso)
    np.testing.assert_allclose(freq_exu, freq, rtol=1e-9)
    distinct = np.flatnonzero(np.min(np.abs(freq[:, None] - freq[None, :]) + np.eye(6) * 1e9, axis=1) > 1e-6 * freq)
    for k in distinct:  # a non-repeated mode's shape is the same line (modal assurance criterion 1)
        a, b = shapes[:, k], shapes_exu[:, k]
        assert (a @ b) ** 2 / ((a @ a) * (b @ b)) == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("build", [gimbal, asymmetric], ids=["gimbal", "odd"])
def test_a_run_matches_exudyns_time_integration(build):
    """The linear run (`six_axis_run.run`) against Exudyn's own integration of the same bodies and elements
    (`six_axis_exudyn.run`: a prescribed mount body, Tait-Bryan nodes, the elements' global axes, the implicit
    trapezoidal rule) under all six mount DOFs at once (lines of 10 um or 10 urad at 3-12 Hz, across the
    modes): every payload coordinate within 1 % of its largest value over 2 s (measured: at most 0.12 %). They
    differ by the rule's (w h)^2 / 12 <= 1.2e-4 at 12 Hz and by the geometry's second-order terms, relative to
    the motion's size: at 0.1 mm (and 10 urad) the elements' forces turning with the displaced body gave the
    yaw a drift of 11 % of its line in 2 s, at 10 um 0.12 %, at 1 um 0.015 % (the integrator's floor)."""
    iso = build()
    t = np.arange(4001) * 5e-4
    lines = np.array([3.0, 5.0, 12.0, 4.0, 7.0, 9.0])  # Hz: x, y, z, rx, ry, rz
    u = 1e-5 * np.sin(2 * np.pi * lines[:, None] * t)
    linear = run(iso, t, u[:3], u[3:])
    expected = np.vstack([linear.payload_translation.values, linear.payload_rotation.values])
    got = six_axis_exudyn.run(iso, t, u[:3], u[3:])
    angles = Rotation.from_rotvec(expected[3:].T).as_euler("XYZ").T  # Exudyn's node angles
    expected = np.vstack([expected[:3], angles])
    for k in range(6):
        scale = np.abs(expected[k]).max()
        assert np.abs(got[k] - expected[k]).max() <= 0.01 * scale, (k, np.abs(got[k] - expected[k]).max() / scale)


@pytest.mark.parametrize("zeta", [0.05, 0.3])
def test_single_axis_transmissibility_matches_the_sdof_closed_form(zeta):
    """Centre of mass in the element plane: z is decoupled, T = |1 + 2 i zeta r| / |1 - r^2 + 2 i zeta r|."""
    payload = Payload.box(1.4, (0.15, 0.12, 0.15), (0.0, 0.0, 0.0))
    m, kz = payload.mass, 500.0
    cz = 2 * zeta * math.sqrt(4 * kz * m) / 4
    iso = square_layout(payload, A, (KL, KL, kz), (C, C, cz))
    fn = math.sqrt(4 * kz / m) / (2 * math.pi)
    r = np.array([0.2, 0.9, 1.0, 1.3, 3.0, 10.0])
    want = np.abs(1 + 2j * zeta * r) / np.abs(1 - r**2 + 2j * zeta * r)
    got = axis_transmissibility(iso, r * fn)[:, DOFS.index("z")]
    np.testing.assert_allclose(got, want, rtol=1e-10)


def sine_fit(time: np.ndarray, x: np.ndarray, freq_hz: float) -> complex:
    """Complex amplitude (a sin + b cos fit: a + i b) of x at freq_hz, least squares."""
    w = 2 * np.pi * freq_hz
    basis = np.column_stack([np.sin(w * time), np.cos(w * time)])
    (a, b), *_ = np.linalg.lstsq(basis, x, rcond=None)
    return complex(a, b)


@pytest.mark.parametrize(("axis", "freq_hz"), [("x", 12.0), ("rx", 5.0), ("z", 28.0)])
def test_time_domain_steady_state_matches_the_transmissibility(axis, freq_hz):
    """A mount sine (1 mm or 1 mrad) on one axis: every payload DOF's steady amplitude within 1 % of |H|, the
    semi-active elements at a scheduled 4 N s/m. The first-order hold of the 1 ms samples changes the input's
    fundamental by (pi f h)^2 / 3 < 3e-3 at 28 Hz."""
    iso = gimbal(semi_active=True)
    h, duration = 1e-3, 10.0
    time = np.arange(0.0, duration + h / 2, h)
    j = DOFS.index(axis)
    amplitude = 1e-3
    u = np.zeros((6, time.size))
    u[j] = amplitude * np.sin(2 * np.pi * freq_hz * time)
    out = run(iso, time, u[:3], u[3:], schedule=np.full(4, 4.0))
    want = transmissibility(iso, freq_hz, np.full(4, 4.0))[0][:, j] * amplitude
    steady = time >= duration - 2.0
    payload = np.vstack([out.payload_translation.values, out.payload_rotation.values])
    got = np.array([sine_fit(time[steady], payload[i, steady], freq_hz) for i in range(6)])
    big = np.abs(want) > 1e-3 * np.abs(want).max()
    np.testing.assert_allclose(np.abs(got[big]), np.abs(want[big]), rtol=0.01)
    assert np.all(np.abs(got[~big]) < 0.01 * np.abs(want).max())


def passive_damping(iso: SixAxisIsolator, c: float) -> np.ndarray:
    """C (6, 6) of `iso` with its semi-active elements made passive at damping c on every axis (by hand)."""
    elements = tuple(replace(e, damping=(c, c, c), semi_active=False) if e.semi_active else e for e in iso.elements)
    return damping_matrix(SixAxisIsolator(elements, iso.payload))


def test_switched_damping_run_matches_an_independent_integration():
    """A ramp-and-hold mount motion (exact under first-order hold) and damping switched 0.5 -> 8 N s/m at 0.3 s:
    the run against scipy's DOP853 on M q'' + C(t) (q' - u') + K (q - u) = 0 from the same start."""
    iso = asymmetric()
    h = 1e-3
    time = np.arange(0.0, 0.8 + h / 2, h)
    direction = np.array([1e-3, -2e-3, 1.5e-3, 4e-3, -3e-3, 2e-3])  # m and rad at the ramp's end
    ramp = np.clip(time / 0.1, 0.0, 1.0)
    u = direction[:, None] * ramp
    c_of_t = np.where(time < 0.3, 0.5, 8.0)
    out = run(iso, time, u[:3], u[3:], schedule=c_of_t[None, :])
    m, k = mass_matrix(iso.payload), stiffness_matrix(iso)
    u_rate = direction / 0.1

    def rhs(t, state, c):
        inside = t < 0.1
        um, vm = direction * min(t / 0.1, 1.0), u_rate * inside
        q, qd = state[:6], state[6:]
        return np.concatenate([qd, np.linalg.solve(m, -c @ (qd - vm) - k @ (q - um))])

    state = np.concatenate([np.zeros(6), u_rate])  # the payload starts moving with the mount
    pieces = []
    for t0, t1, c in ((0.0, 0.1, 0.5), (0.1, 0.3, 0.5), (0.3, 0.8, 8.0)):  # split at the kinks
        grid = time[(time >= t0 - h / 2) & (time <= t1 + h / 2)]
        sol = solve_ivp(rhs, (t0, t1), state, "DOP853", t_eval=grid, rtol=1e-11, atol=1e-14,
                        args=(passive_damping(iso, c),))  # fmt: skip
        pieces.append(sol.y[:, :-1])
        state = sol.y[:, -1]
    states = np.hstack([*pieces, state[:, None]])
    reference = states[:6]
    got = np.vstack([out.payload_translation.values, out.payload_rotation.values])
    scale = np.abs(reference).max(axis=1, keepdims=True)
    np.testing.assert_allclose(got / scale, reference / scale, atol=1e-7)
    # stroke rates T_i (q' - u'), u' the slope of the step starting at each sample
    u_rate_k = u_rate[:, None] * (time < 0.1 - h / 2)
    rates = (strokes_matrix(iso) @ (states[6:] - u_rate_k)).reshape(3, 3, -1)
    scale = np.abs(rates).max()
    np.testing.assert_allclose(out.element_stroke_rate.values / scale, rates / scale, atol=1e-7)
    np.testing.assert_array_equal(out.damping.values[0], c_of_t)


def test_a_callable_schedule_sees_the_outputs_and_acts_from_then_on():
    """A skyhook-like callable on the z stroke rate against the same damping history given as an array."""
    iso = gimbal(semi_active=True)
    h = 1e-3
    time = np.arange(0.0, 0.5, h)
    z = 1e-3 * np.sin(2 * np.pi * 6.0 * time)
    zero = np.zeros_like(time)
    seen = []

    def law(t, y):
        seen.append(y.copy())
        return np.full(4, 1.0 if y[6 + 12 + 2] > 0 else 6.0)  # element 0's z stroke rate (after 12 strokes)

    out = run(iso, time, np.vstack([zero, zero, z]), np.zeros((3, time.size)), schedule=law)
    again = run(iso, time, np.vstack([zero, zero, z]), np.zeros((3, time.size)), schedule=out.damping.values)
    np.testing.assert_allclose(again.payload_translation.values, out.payload_translation.values, rtol=0, atol=1e-15)
    seen = np.array(seen)  # every output the law saw is the one the run reports at that sample
    np.testing.assert_allclose(seen[:, DOFS.index("z")], out.payload_translation.values[2], rtol=0, atol=1e-15)
    n_el = iso.n_elements
    for part, name in ((slice(6, 6 + 3 * n_el), "element_stroke"), (slice(6 + 3 * n_el, None), "element_stroke_rate")):
        reported = out[name].values.transpose(2, 0, 1).reshape(time.size, -1)
        np.testing.assert_allclose(seen[:, part], reported, rtol=0, atol=1e-12 * np.abs(reported).max())
    assert set(np.unique(out.damping.values)) == {1.0, 6.0}


def test_the_paper_yz_isolator_is_a_special_case():
    """Today's platform lumped on K in y and z: two modes at sqrt(K / m_total), x and rotation near-rigid, and the
    y transmissibility the SDOF closed form with zeta = C / (2 sqrt(K m_total))."""
    p = platform_params()
    m, k, c = p.structure.total_mass, p.isolator_stiffness, 2.0
    iso = paper_yz(m, k, c)
    freq, shapes = rigid_body_modes(iso)
    fn = math.sqrt(k / m) / (2 * math.pi)
    np.testing.assert_allclose(freq[:2], fn, rtol=1e-10)
    assert sorted(sum(dominant_dofs(shapes[:, :2], iso.payload), [])) == ["y", "z"]
    assert freq[2:].min() > 100 * fn
    zeta, r = c / (2 * math.sqrt(k * m)), np.array([0.5, 1.0, 2.0, 17.6])
    got = axis_transmissibility(iso, r * fn)
    np.testing.assert_allclose(got[:, 1], np.abs(1 + 2j * zeta * r) / np.abs(1 - r**2 + 2j * zeta * r), rtol=1e-10)
    np.testing.assert_allclose(got[:, [0, 3, 4, 5]], 1.0, atol=1e-3)  # x and rotation follow the mount


def test_the_run_dataset_carries_units():
    iso = gimbal()
    time = np.arange(0.0, 0.05, 1e-3)
    out = run(iso, time, np.zeros((3, time.size)), np.zeros((3, time.size)))
    for name in [*out.data_vars, *out.coords]:
        assert out[name].attrs["units"] and out[name].attrs["long_name"], name
    assert out.element_stroke.shape == (4, 3, time.size)
    assert np.all(np.isnan(out.damping.values))  # no semi-active element here: an empty variable
    assert out.damping.shape == (0, time.size)


@pytest.mark.parametrize(
    ("make", "key"),
    [
        (lambda: Element((0, 0, 0), (-1.0, 1.0, 1.0)).checked("e"), "e.stiffness_n_m"),
        (lambda: Element((0, 0, 0), (1.0, 1.0, 1.0), kind="spring").checked("e"), "e.kind"),
        (lambda: Element((0, 0, 0), (1.0, 1.0, 1.0), damper_axes=("w",)).checked("e"), "e.damper_axes"),
        (lambda: Payload(0.0, (0, 0, 0), tuple(map(tuple, np.eye(3)))), "payload.mass_kg"),
        (lambda: Payload(1.0, (0, 0, 0), ((1, 0, 0), (0, -1, 0), (0, 0, 1))), "payload.inertia_kg_m2"),
        (lambda: SixAxisIsolator((Element((0, 0, 0), (1.0, 1.0, 1.0)),), GIMBAL), "six_axis.elements"),
        (lambda: square_layout(GIMBAL, 0.0, (1.0, 1.0, 1.0)), "six_axis.half_spacing_m"),
        (lambda: damping_matrix(gimbal(semi_active=True), [1.0, 2.0]), "semi-active damping"),
        (lambda: run(gimbal(True), np.arange(3.0), np.zeros((3, 3)), np.zeros((3, 3)), [1.0]), "damping schedule"),
        (lambda: run(gimbal(), [0.0, 1.0, 3.0], np.zeros((3, 3)), np.zeros((3, 3))), "time"),
    ],
)
def test_bad_input_is_refused_naming_the_key(make, key):
    with pytest.raises(ValueError, match=key):
        make()
