"""Rotor inflow: uniform momentum (Glauert) inflow and the Pitt-Peters three-state dynamic inflow.

Non-dimensional as usual: inflow ratios are velocities over the tip speed Omega R, positive DOWN through the
disc; C_T = T / (rho pi R^2 (Omega R)^2), moment coefficients over one more R; time psi = Omega t (rad of
azimuth, not revolutions), so d/dt = Omega d/dpsi.

Azimuth and signs (Peters' convention, rotor turning counter-clockwise seen from above like the uavdamp main
rotor): psi = 0 over the tail, increasing with the rotation, so psi = pi/2 points to the right (-y in uavdamp's
x forward, y left, z up). For the uavdamp tree, blade k of N sits at Psi_k = hub angle + 2 pi k / N from +x
(the RevoluteZ hub coordinate), and psi_k = Psi_k - pi (`blade_azimuth`). A point at (r, psi) lies at
r (-cos psi, -sin psi, 0) in the non-rotating hub frame. Forcing coefficients: C_L the aerodynamic roll moment
on the rotor, positive right side down (about +x in uavdamp), C_M the pitch moment, positive nose up (about -y
in uavdamp): `rotor_coefficients` converts uavdamp hub loads. Forward flight is taken along +x: for a free
stream from another direction the harmonics must be rotated into wind axes (not done here).

Pitt-Peters (Pitt & Peters 1981; Peters & HaQuang 1988; Peters 2009, Eqs. 7-11), states nu = (nu_0, nu_s, nu_c),
induced ratio nu_0 + nu_s (r/R) sin psi + nu_c (r/R) cos psi:

    M nu' + V L^-1 nu = (C_T, -C_L, -C_M),   M = diag(8/(3 pi), 16/(45 pi), 16/(45 pi)),
    V = diag(V_T, V_m, V_m),  V_T = sqrt(mu^2 + lambda^2),  V_m = (mu^2 + lambda (lambda + nu_0)) / V_T,
    L = [[1/2, 0, -k X], [0, 2 (1 + X^2), 0], [k X, 0, 2 (1 - X^2)]],  k = 15 pi / 64,  X = tan(chi / 2),

with lambda = mu_z + nu_0 the total inflow ratio and chi = atan(mu / lambda) the wake skew angle. The L
off-diagonal is antisymmetric with this forcing sign (the symmetric form in the literature goes with +C_L, +C_M
and negative cyclic L entries); steadily it gives Pitt-Peters' nu_c / nu_0 = (15 pi / 32) tan(chi / 2), more
inflow at the rear. The uniform state's nonlinear mass flow V_T makes its hover perturbation mass flow
d(V_T nu_0)/d nu_0 = V_m = 2 lambda: time constant M_00 / (4 lambda) in psi (momentum theory with the disc's
apparent mass 8 rho R^3 / 3), not M_00 / (2 lambda), which a mass flow frozen at V_T = lambda would give.
Valid for lambda >= 0 (helicopter working states; no vortex-ring or windmill correction).
"""

from __future__ import annotations

import math

import numpy as np

APPARENT_MASS = (8.0 / (3.0 * math.pi), 16.0 / (45.0 * math.pi), 16.0 / (45.0 * math.pi))
SKEW_COUPLING = 15.0 * math.pi / 64.0
MIN_MASS_FLOW = 1e-6  # lower bound of V_T (the rotor at rest in still air has none)


def uniform_inflow(thrust_coeff: float, mu: float, mu_z: float = 0.0, iterations: int = 30) -> float:
    """Total inflow ratio lambda = mu_z + C_T / (2 sqrt(mu^2 + lambda^2)) (Glauert), by Newton's method.

    mu: advance ratio (free stream in the disc plane over Omega R); mu_z: free stream through the disc over
    Omega R, positive down (climb). The induced part is lambda - mu_z; in hover it is sqrt(C_T / 2), i.e.
    v_i = sqrt(T / (2 rho A)). Valid for C_T >= 0 and lambda > 0.
    """
    lam = mu_z + math.sqrt(max(thrust_coeff, 0.0) / 2.0) + 1e-9
    for _ in range(iterations):
        root = math.sqrt(mu * mu + lam * lam)
        f = lam - mu_z - thrust_coeff / (2.0 * root)
        step = f / (1.0 + thrust_coeff * lam / (2.0 * root**3))
        lam -= step
        if abs(step) < 1e-14:
            break
    return lam


def mass_flow(mu: float, mu_z: float, nu_0: float) -> tuple[float, float, float]:
    """(lambda, V_T, V_m): total inflow ratio and the uniform and harmonic mass-flow parameters (Peters)."""
    lam = mu_z + nu_0
    v_t = max(math.sqrt(mu * mu + lam * lam), MIN_MASS_FLOW)
    return lam, v_t, (mu * mu + lam * (lam + nu_0)) / v_t


def skew_parameter(mu: float, lam: float) -> float:
    """X = tan(chi / 2) = mu / (V_T + lambda) of the wake skew angle chi = atan(mu / lambda), clipped to [0, 1]."""
    v_t = math.sqrt(mu * mu + lam * lam)
    return min(max(mu / max(v_t + lam, MIN_MASS_FLOW), 0.0), 1.0)


def l_matrix(mu: float, lam: float) -> np.ndarray:
    """Pitt-Peters L (3, 3) for the forcing (C_T, -C_L, -C_M), states (nu_0, nu_s, nu_c)."""
    x = skew_parameter(mu, lam)
    k = SKEW_COUPLING * x
    return np.array([[0.5, 0.0, -k], [0.0, 2.0 * (1.0 + x * x), 0.0], [k, 0.0, 2.0 * (1.0 - x * x)]])


def pitt_peters_rhs(
    state, thrust_coeff: float, roll_coeff: float, pitch_coeff: float, mu: float, mu_z: float = 0.0
) -> np.ndarray:
    """d(nu_0, nu_s, nu_c)/dpsi (per radian of azimuth; multiply by Omega for d/dt, e.g. an Exudyn ODE1 node).

    roll_coeff C_L, pitch_coeff C_M: aerodynamic hub moment coefficients in Peters' signs (module docstring).
    mu_z: free stream through the disc over Omega R, positive down (climb). The total inflow lambda = mu_z +
    nu_0 is formed from the state, so the mass flow follows the inflow (pass no lagged lambda).
    """
    nu_0, nu_s, nu_c = (float(v) for v in state)
    lam, v_t, v_m = mass_flow(mu, mu_z, nu_0)
    x = skew_parameter(mu, lam)
    b, d = SKEW_COUPLING * x, 2.0 * (1.0 - x * x)
    det = 0.5 * d + b * b  # of L's (nu_0, nu_c) block [[1/2, -b], [b, d]], >= 1/2 for X in [0, 1]
    y_0 = (d * nu_0 + b * nu_c) / det  # L^-1 nu
    y_c = (0.5 * nu_c - b * nu_0) / det
    y_s = nu_s / (2.0 * (1.0 + x * x))
    m_0, m_s, m_c = APPARENT_MASS
    return np.array(
        [
            (thrust_coeff - v_t * y_0) / m_0,
            (-roll_coeff - v_m * y_s) / m_s,
            (-pitch_coeff - v_m * y_c) / m_c,
        ]
    )


def pitt_peters_steady(
    thrust_coeff: float, roll_coeff: float, pitch_coeff: float, mu: float, mu_z: float = 0.0, iterations: int = 200
) -> np.ndarray:
    """Steady Pitt-Peters states nu = L V^-1 (C_T, -C_L, -C_M), solved for nu_0 by damped fixed-point iteration.

    With no moments nu_0 is Glauert's uniform inflow; a start state for a simulation.
    """
    nu_0 = uniform_inflow(thrust_coeff, mu, mu_z) - mu_z
    forcing = np.array([thrust_coeff, -roll_coeff, -pitch_coeff])
    for _ in range(iterations):
        lam, v_t, v_m = mass_flow(mu, mu_z, nu_0)
        nu = l_matrix(mu, lam) @ (forcing / np.array([v_t, v_m, v_m]))
        if abs(nu[0] - nu_0) < 1e-14:
            break
        nu_0 = 0.5 * (nu_0 + nu[0])
    return nu


def induced_velocity(state, r_over_radius, psi, omega_rad_s: float, radius: float) -> np.ndarray:
    """Induced velocity, m/s, positive down, at stations (r/R, psi): Omega R (nu_0 + nu_s r sin psi + nu_c r cos psi).

    Broadcasts r_over_radius against psi (e.g. (S,) stations and (B, 1) blade azimuths). The air velocity to
    give `aerodynamics.section_velocities` is then -v_i along the shaft (hub +z).
    """
    nu_0, nu_s, nu_c = (float(v) for v in state)
    r = np.asarray(r_over_radius, dtype=float)
    psi = np.asarray(psi, dtype=float)
    return omega_rad_s * radius * (nu_0 + r * (nu_s * np.sin(psi) + nu_c * np.cos(psi)))


def blade_azimuth(hub_angle: float, n_blades: int) -> np.ndarray:
    """Peters azimuth psi_k (rad) of the uavdamp blades: hub angle + 2 pi k / N - pi (0 over the tail)."""
    return hub_angle + 2.0 * np.pi * np.arange(n_blades) / n_blades - np.pi


def rotor_coefficients(
    thrust: float, moment_x: float, moment_y: float, rho: float, omega_rad_s: float, radius: float
) -> tuple[float, float, float]:
    """(C_T, C_L, C_M) from the uavdamp rotor's aerodynamic hub loads in the non-rotating hub frame.

    thrust: N along +z (shaft); moment_x, moment_y: N m about the hub centre, about +x (forward) and +y (left).
    C_L = M_x / (rho A (Omega R)^2 R) (right side down positive), C_M = -M_y / (...) (nose up positive).
    """
    scale = rho * math.pi * radius**2 * (omega_rad_s * radius) ** 2
    return thrust / scale, moment_x / (scale * radius), -moment_y / (scale * radius)
