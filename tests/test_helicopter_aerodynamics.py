"""Blade-element loads, momentum and Pitt-Peters inflow against closed forms (never the code's own numbers)."""

from __future__ import annotations

import math
from dataclasses import replace

import exudyn as exu
import exudyn.itemInterface as eii
import numpy as np
import pytest
from conftest import helicopter_of
from scipy.integrate import solve_ivp

from uavdamp import helicopter as H
from uavdamp.helicopter import aerodynamics as A
from uavdamp.helicopter import inflow as I
from uavdamp.helicopter import model as model_links

OMEGA = 44.4  # rad/s, uavdamp main rotor
RHO = A.AIR_DENSITY
G = 9.80665  # m/s^2
R_TIP = 0.687 + 4.91  # m, uavdamp tip radius

# Blade of classical blade-element theory: lifting from the shaft axis to the tip, constant chord, no cut-out.
IDEAL = replace(A.BO105_MAIN, hinge_offset=0.0, length=R_TIP, n_stations=40)


def coefficients(blade: A.BladeAero, collective: float, lam: float) -> tuple[float, float]:
    """(C_T, C_P) of the rotor in hover with uniform inflow ratio lam, normalised here."""
    _, thrust, torque = A.hover_loads(blade, collective, lam, OMEGA, RHO)
    scale = RHO * math.pi * blade.tip_radius**2 * (OMEGA * blade.tip_radius) ** 2
    return thrust / scale, -torque * OMEGA / (scale * OMEGA * blade.tip_radius)


@pytest.fixture(scope="module")
def weight(default_config) -> float:
    """Weight of the whole uavdamp helicopter (fuselage 2200 kg and all blades), N."""
    return helicopter_of(default_config["helicopter"]).total_mass() * G


# --- kinematics --------------------------------------------------------------------------------------------------


def test_a_blade_rotating_at_omega_sees_omega_r():
    blade = A.BO105_MAIN
    rot = A.blade_rotations(0.3, blade.n_blades)
    hinge = blade.hinge_offset * rot[:, :, 0]  # hinge positions in the hub frame
    omega = np.array([0.0, 0.0, OMEGA])
    u_t, u_p, u_r = A.section_velocities(blade, rot, np.cross(omega, hinge), np.tile(omega, (4, 1)), np.zeros(3))
    np.testing.assert_allclose(u_t, np.tile(OMEGA * (blade.hinge_offset + blade.stations), (4, 1)), rtol=1e-12)
    np.testing.assert_allclose(u_p, 0.0, atol=1e-10)
    np.testing.assert_allclose(u_r, 0.0, atol=1e-10)


def test_section_velocities_are_rigid_body_kinematics_in_any_orientation():
    """v = v_0 + omega x (s e_x), minus the air, resolved on the blade axes: U_T = -w.y, U_P = -w.z, U_R = w.x."""
    rng = np.random.default_rng(5)
    blade = replace(A.BO105_MAIN, n_stations=6)
    rot = np.linalg.qr(rng.normal(size=(3, 3, 3)))[0]
    v0, omega, air = rng.normal(size=(3, 3)), rng.normal(size=(3, 3)), rng.normal(size=(3, 6, 3))
    u_t, u_p, u_r = A.section_velocities(blade, rot, v0, omega, air)
    for b in range(3):
        for k, s in enumerate(blade.stations):
            w = air[b, k] - (v0[b] + np.cross(omega[b], s * rot[b, :, 0]))
            expected = (-w @ rot[b, :, 1], -w @ rot[b, :, 2], w @ rot[b, :, 0])
            np.testing.assert_allclose((u_t[b, k], u_p[b, k], u_r[b, k]), expected, rtol=1e-12, atol=1e-12)


def test_tip_down_flap_rate_gives_upflow():
    """The model's flap coordinate turns the tip down (RevoluteY): a rate q' makes U_P = -s q'."""
    blade = A.BO105_MAIN
    rot = A.blade_rotations(0.0, 1)
    rate = 0.2
    u_t, u_p, _ = A.section_velocities(blade, rot, np.zeros((1, 3)), rate * rot[:, :, 1], np.zeros(3))
    np.testing.assert_allclose(u_p[0], -blade.stations * rate, rtol=1e-12)
    np.testing.assert_allclose(u_t, 0.0, atol=1e-12)


def test_the_uavdamp_blade_links_are_blade_frames(default_config):
    """Exudyn's feather links of the uavdamp tree: U_T = Omega r, a flap-coordinate rate q' gives U_P = -s q' (tip
    down), a feather angle turns the leading edge (frame y) up: the conventions `aerodynamics` documents."""
    heli = helicopter_of(default_config["helicopter"]).balanced()
    model = H.build(heli, fix_fuselage=True)
    mbs, blade, flap_rate, feather = model.mbs, A.BO105_MAIN, 0.5, 0.1
    flap = model_links.HUB_LINK + 1  # blade 0: flap, lag, feather links
    for name, value in (("initialCoordinates_t", flap_rate), ("initialCoordinates", feather)):
        q = np.array(mbs.GetNodeParameter(model.node, name))
        q[flap + (0 if name.endswith("_t") else 2)] = value
        mbs.SetNodeParameter(model.node, name, list(q))
    sensors = {
        var: mbs.AddSensor(
            eii.SensorKinematicTree(
                objectNumber=0,
                linkNumber=flap + 2,
                localPosition=[0.0, 0.0, 0.0],
                outputVariableType=getattr(exu.OutputVariableType, var),
                storeInternal=False,
            )
        )
        for var in ("RotationMatrix", "Velocity", "AngularVelocity")
    }
    mbs.Assemble()
    read = {
        k: np.asarray(mbs.GetSensorValues(s, configuration=exu.ConfigurationType.Initial)) for k, s in sensors.items()
    }
    rot = read["RotationMatrix"].reshape(1, 3, 3)
    assert rot[0, 2, 1] == pytest.approx(math.sin(feather), rel=1e-9)  # leading edge up: nose-up pitch
    u_t, u_p, _ = A.section_velocities(blade, rot, read["Velocity"][None], read["AngularVelocity"][None], np.zeros(3))
    # (U_T, U_P) are components along the pitched frame's (y', z'); rotate them back to the hub's (y, z)
    tangential = u_t[0] * rot[0, 1, 1] + u_p[0] * rot[0, 1, 2]
    normal = u_t[0] * rot[0, 2, 1] + u_p[0] * rot[0, 2, 2]
    np.testing.assert_allclose(tangential, OMEGA * (heli.main_rotor.hinge_offset + blade.stations), rtol=1e-9)
    np.testing.assert_allclose(normal, -blade.stations * flap_rate, rtol=1e-9)


# --- inflow ------------------------------------------------------------------------------------------------------


def test_hover_inflow_matches_momentum_theory(weight):
    """Blade-element thrust with momentum inflow: v_i = sqrt(T / (2 rho A)) for the thrust the blades make."""
    blade = A.BO105_MAIN
    area = math.pi * blade.tip_radius**2
    scale = RHO * area * (OMEGA * blade.tip_radius) ** 2
    theta, thrust = 0.17, weight
    for _ in range(30):  # fixed point: inflow from the blades' thrust, thrust from that inflow
        lam = I.uniform_inflow(thrust / scale, 0.0)
        thrust = A.hover_loads(blade, theta, lam, OMEGA)[1]
    v_i = lam * OMEGA * blade.tip_radius
    assert v_i == pytest.approx(math.sqrt(thrust / (2 * RHO * area)), rel=0.02)
    assert thrust > 0.5 * weight


@pytest.mark.parametrize("mu", [0.3, 0.4])
def test_forward_flight_inflow_tends_to_glauert_high_speed_limit(mu):
    assert I.uniform_inflow(0.003, mu) == pytest.approx(0.003 / (2 * mu), rel=0.02)


def test_climb_inflow_is_momentum_theory_closed_form():
    c_t, mu_z = 0.003, 0.02
    induced = -mu_z / 2 + math.sqrt((mu_z / 2) ** 2 + c_t / 2)
    assert I.uniform_inflow(c_t, 0.0, mu_z) - mu_z == pytest.approx(induced, rel=1e-6)


# --- blade-element thrust, power, trim -----------------------------------------------------------------------------


@pytest.mark.parametrize(("theta_0", "twist"), [(math.radians(8.0), 0.0), (math.radians(12.0), -0.1082)])
def test_thrust_matches_blade_element_closed_form(theta_0, twist):
    """C_T = sigma a / 2 (theta_0 / 3 + theta_tw / 4 - lambda / 2), theta_0 on the shaft axis."""
    blade = replace(IDEAL, twist_rad=twist, cd0=0.0)
    lam = 0.04
    c_t, _ = coefficients(blade, theta_0, lam)
    closed = blade.solidity * blade.lift_slope / 2 * (theta_0 / 3 + twist / 4 - lam / 2)
    assert c_t == pytest.approx(closed, rel=0.02)


def test_thrust_with_hinge_offset_matches_closed_form_from_the_hinge():
    """Lifting from x_0 = e / R to the tip: C_T = sigma a / 2 (theta_0 (1 - x_0^3) / 3 + theta_tw (1 - x_0^4) / 4
    - lambda (1 - x_0^2) / 2)."""
    blade = A.BO105_MAIN
    x0, theta_0, lam = blade.hinge_offset / blade.tip_radius, 0.18, 0.04
    c_t, _ = coefficients(blade, theta_0, lam)
    tw = blade.twist_rad
    closed = (
        blade.solidity
        * blade.lift_slope
        / 2
        * (theta_0 * (1 - x0**3) / 3 + tw * (1 - x0**4) / 4 - lam * (1 - x0**2) / 2)
    )
    assert c_t == pytest.approx(closed, rel=0.02)


def test_station_count_convergence():
    """Gauss converges fast on the uavdamp blade (10 stations within 1e-4); the midpoint rule at second order."""
    theta_0, lam = 0.18, 0.04
    reference = coefficients(replace(A.BO105_MAIN, n_stations=200), theta_0, lam)[0]
    gauss = [
        abs(coefficients(replace(A.BO105_MAIN, n_stations=n), theta_0, lam)[0] / reference - 1) for n in (2, 4, 10)
    ]
    assert gauss[0] > gauss[1] > gauss[2] and gauss[2] < 1e-4
    mid = [
        abs(coefficients(replace(A.BO105_MAIN, n_stations=n, quadrature="midpoint"), theta_0, lam)[0] / reference - 1)
        for n in (10, 20, 40)
    ]
    assert 3.5 < mid[0] / mid[1] < 4.5 and 3.5 < mid[1] / mid[2] < 4.5


def test_profile_power_is_sigma_cd0_over_8():
    """Unloaded: C_P = sigma C_d0 / 8; loaded with uniform inflow: C_P - lambda C_T (induced) = sigma C_d0 / 8."""
    blade = IDEAL
    closed = blade.solidity * blade.cd0 / 8
    assert coefficients(blade, 0.0, 0.0)[1] == pytest.approx(closed, rel=0.05)
    lam = 0.04
    c_t, c_p = coefficients(blade, 0.16, lam)
    assert c_p - lam * c_t == pytest.approx(closed, rel=0.05)
    x0 = A.BO105_MAIN.hinge_offset / A.BO105_MAIN.tip_radius  # drag from the hinge outward, torque about the shaft
    with_hinge = A.BO105_MAIN.solidity * A.BO105_MAIN.cd0 * (1 - x0**4) / 8
    assert coefficients(A.BO105_MAIN, 0.0, 0.0)[1] == pytest.approx(with_hinge, rel=0.05)


def test_hover_trim_collective_matches_blade_element_momentum_closed_form(weight):
    """theta_75 = 6 C_T / (sigma a) + 3/2 sqrt(C_T / 2) for thrust = weight (2200 kg fuselage + blades)."""
    blade = replace(IDEAL, n_stations=20)
    theta, lam = A.hover_collective(blade, weight, OMEGA)
    c_t = weight / (RHO * math.pi * R_TIP**2 * (OMEGA * R_TIP) ** 2)
    closed = 6 * c_t / (blade.solidity * blade.lift_slope) + 1.5 * math.sqrt(c_t / 2)
    assert theta + 0.75 * blade.twist_rad == pytest.approx(closed, rel=0.02)
    assert lam == pytest.approx(math.sqrt(c_t / 2), rel=1e-9)


def test_flap_rate_damping_about_the_hinge_is_the_lock_number_closed_form():
    """dM_y/dq' = -rho a c Omega (L^4 / 4 + e L^3 / 3) / 2 for a tip-down flap rate q' (uniform blade, e offset)."""
    blade = A.BO105_MAIN
    e, length = blade.hinge_offset, blade.length
    rot = A.blade_rotations(0.0, 1)
    omega_hub = np.array([[0.0, 0.0, OMEGA]])
    v0 = np.cross(omega_hub, e * rot[:, :, 0])

    def hinge_moment(rate: float) -> float:
        u = A.section_velocities(blade, rot, v0, omega_hub + rate * rot[:, :, 1], np.zeros(3))
        return A.blade_loads(blade, *u, 0.0).moment[0, 1]

    h = 1e-3
    slope = (hinge_moment(h) - hinge_moment(-h)) / (2 * h)
    closed = -0.5 * RHO * blade.lift_slope * blade.chord * OMEGA * (length**4 / 4 + e * length**3 / 3)
    assert slope == pytest.approx(closed, rel=0.01)
    # flap mode of a uniform hinged blade: I = m L^2 / 3, nu^2 = 1 + 3 e / (2 L); damping ratio from the slope
    inertia, nu = 31.06 * length**2 / 3, math.sqrt(1 + 1.5 * e / length)
    zeta = -slope / (2 * inertia * nu * OMEGA)
    gamma = RHO * blade.lift_slope * blade.chord * length**4 / inertia
    assert blade.lock_number(inertia) == pytest.approx(gamma, rel=1e-12)
    assert zeta == pytest.approx(gamma / 16 * (1 + 4 * e / (3 * length)) / nu, rel=0.01)


def test_lift_stops_growing_beyond_the_stall_angle():
    blade = replace(A.BO105_MAIN, cd0=0.0)
    u = np.full((1, blade.n_stations), 100.0)
    normal = [A.blade_loads(blade, u, 0 * u, 0 * u, p).force[0, 2] for p in (0.5, 1.0, 1.0 * blade.alpha_stall)]
    lift_at_stall = 0.5 * RHO * blade.chord * 100.0**2 * blade.lift_slope * blade.alpha_stall * blade.length
    np.testing.assert_allclose(normal, lift_at_stall, rtol=1e-12)


def test_yawed_flow_drag_has_the_radial_component_along_the_radial_flow():
    """Zero lift, U_P = 0, radial flow U_R: f = 1/2 rho c U_T C_d0 (U_R, -U_T, 0) per metre (drag along the flow)."""
    blade = A.BO105_MAIN
    u_t, u_r = np.full((1, blade.n_stations), 80.0), np.full((1, blade.n_stations), 12.0)
    force = A.blade_loads(blade, u_t, 0 * u_t, u_r, 0.0).force[0]
    scale = 0.5 * RHO * blade.chord * 80.0 * blade.cd0 * blade.length
    np.testing.assert_allclose(force, [scale * 12.0, -scale * 80.0, 0.0], rtol=1e-12, atol=1e-12)


# --- Pitt-Peters -------------------------------------------------------------------------------------------------


def test_pitt_peters_hover_steady_state_is_momentum_theory():
    c_t = 0.003
    np.testing.assert_allclose(I.pitt_peters_steady(c_t, 0.0, 0.0, 0.0), [math.sqrt(c_t / 2), 0, 0], atol=1e-12)
    np.testing.assert_allclose(I.pitt_peters_rhs([math.sqrt(c_t / 2), 0, 0], c_t, 0, 0, 0.0), 0.0, atol=1e-12)


def test_pitt_peters_hover_linearisation_rates():
    """About hover: d(nu_0)' / d(nu_0) = -4 lambda / M_00 (mass flow 2 lambda, L_00 = 1/2), cyclic -lambda / M_11."""
    c_t = 0.003
    lam = math.sqrt(c_t / 2)
    base, h = np.array([lam, 0.0, 0.0]), 1e-7
    jac = np.column_stack(
        [
            (I.pitt_peters_rhs(base + h * e, c_t, 0, 0, 0.0) - I.pitt_peters_rhs(base - h * e, c_t, 0, 0, 0.0))
            / (2 * h)
            for e in np.eye(3)
        ]
    )
    expected = np.diag([-4 * lam / (8 / (3 * math.pi)), -lam / (16 / (45 * math.pi)), -lam / (16 / (45 * math.pi))])
    np.testing.assert_allclose(jac, expected, rtol=0.02, atol=1e-9)


def test_pitt_peters_thrust_step_decays_with_the_closed_form_time_constant():
    """A 0.1 % step in C_T from hover: nu_0 approaches its new value as exp(-psi / tau), tau = M_00 / (4 lambda)."""
    c_t0, c_t1 = 0.003, 0.003 * 1.001
    lam0, lam1 = math.sqrt(c_t0 / 2), math.sqrt(c_t1 / 2)
    tau = 8 / (3 * math.pi) / (4 * lam1)  # rad of azimuth; Bo-105: about 5.4 rad, 0.12 s at 44.4 rad/s
    psi = np.linspace(0.0, 3 * tau, 7)
    sol = solve_ivp(
        lambda t, y: I.pitt_peters_rhs(y, c_t1, 0, 0, 0.0),
        (0, psi[-1]),
        [lam0, 0, 0],
        t_eval=psi,
        rtol=1e-11,
        atol=1e-14,
    )
    gap = lam1 - sol.y[0]
    rate = -np.polyfit(psi, np.log(gap), 1)[0]
    assert rate == pytest.approx(1 / tau, rel=0.02)


def test_pitt_peters_forward_flight_gradient_is_pitt_peters_closed_form():
    """Steadily, with thrust only: 2 nu_0 sqrt(mu^2 + nu_0^2) = C_T and nu_c / nu_0 = (15 pi / 32) tan(chi / 2)."""
    c_t, mu = 0.003, 0.15
    nu_0, nu_s, nu_c = I.pitt_peters_steady(c_t, 0.0, 0.0, mu)
    assert 2 * nu_0 * math.sqrt(mu**2 + nu_0**2) == pytest.approx(c_t, rel=1e-6)
    chi = math.atan2(mu, nu_0)
    assert nu_c / nu_0 == pytest.approx(15 * math.pi / 32 * math.tan(chi / 2), rel=0.02)
    assert nu_s == 0.0
    np.testing.assert_allclose(I.pitt_peters_rhs([nu_0, nu_s, nu_c], c_t, 0, 0, mu), 0.0, atol=1e-10)


def test_pitt_peters_steady_state_is_the_rest_point_of_the_dynamics_with_moments():
    """nu = L V^-1 (C_T, -C_L, -C_M) (the steady solve) zeroes the right-hand side (its own L^-1) in skewed flow."""
    for mu in (0.0, 0.1, 0.3):
        forcing = (0.003, 2e-5, -3e-5)
        state = I.pitt_peters_steady(*forcing, mu, 0.01)
        np.testing.assert_allclose(I.pitt_peters_rhs(state, *forcing, mu, 0.01), 0.0, atol=1e-10)
        sol = solve_ivp(lambda t, y, f=forcing, m=mu: I.pitt_peters_rhs(y, *f, m, 0.01), (0, 400), [0.02, 0, 0])
        np.testing.assert_allclose(sol.y[:, -1], state, rtol=1e-3, atol=1e-7)


@pytest.mark.parametrize(
    ("point", "hub_angle_there"), [((0.0, -2.0, 0.0), 1.5 * math.pi), ((-2.0, 0.0, 0.0), math.pi)], ids=["right", "aft"]
)
def test_pitt_peters_inflow_is_larger_where_the_disc_carries_more_lift(point, hub_angle_there):
    """Extra lift at a point on the right (-y) or aft (-x) of the uavdamp disc: more inflow where blade 0 is over
    that point (its model azimuth, from +x counter-clockwise, is the hub angle) than on the opposite side."""
    thrust = 20000.0
    moment = np.cross(point, [0.0, 0.0, thrust])  # N m about the hub centre, uavdamp axes
    state = I.pitt_peters_steady(*I.rotor_coefficients(thrust, moment[0], moment[1], RHO, OMEGA, R_TIP), 0.0)
    psi = [I.blade_azimuth(angle, 1)[0] for angle in (hub_angle_there, hub_angle_there - math.pi)]
    there, opposite = I.induced_velocity(state, 0.8, np.array(psi), OMEGA, R_TIP)
    assert there > 1.5 * opposite > 0
