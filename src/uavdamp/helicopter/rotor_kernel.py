"""The rotors' blade-element loads as the tree's generalized forces in one compiled call (numba): what
`uavdamp.helicopter.rotorloads.RotorLoads.update` computes every solver step.

The same arithmetic as the numpy pieces it replaces on that path, which stay as its reference: the tree's frames
and generalized forces (`uavdamp.helicopter.treekinematics`, themselves checked against Exudyn's
SensorKinematicTree and virtual work) and the section velocities and loads (`uavdamp.helicopter.aerodynamics`);
`tests/test_rotor_kernel.py` checks the kernel against them. `RotorLoads.update` takes 31 us a step where the numpy
pieces took 261 us, and the default hover flight 11.9 s where it took 25.6 s (`benchmarks/bench_helicopter.py
--flight`, one run each, load average 1.9); compiled once per machine (``cache=True``: 3.5 s the first time on a
quiet machine, imports included).

Packed inputs (built once by `uavdamp.helicopter.rotorloads.RotorLoads`): per rotor its blades' stations,
quadrature weights, first-moment weights and twist (4, S) and airfoil scalars (`AIRFOIL`); the tree's fixed parts
(the flap hinges' azimuth rotations and offsets, the coordinates' indices); per step the state vector of `loads`.
"""

from __future__ import annotations

import math

import numpy as np

from uavdamp import compiled

# the airfoil scalars' order in a rotor's packed array (`airfoil`)
AIRFOIL = ("chord", "lift_slope", "alpha_zero_lift", "alpha_stall", "cd0", "cd2")
# numba on first use (`uavdamp.compiled`), callees first
COMPILED = ("_rot", "_mm", "_mv", "_tv", "_dot", "_cross", "_blade", "_loads")


def airfoil(blade) -> np.ndarray:
    """A `BladeAero`'s airfoil scalars (`AIRFOIL`' order) as floats."""
    return np.array([float(getattr(blade, k)) for k in AIRFOIL])


def _rot(axis, angle):
    """The rotation matrix (3, 3) about coordinate axis 0, 1 or 2 by `angle` rad."""
    c, s = math.cos(angle), math.sin(angle)
    out = np.zeros((3, 3))
    i, j = (1, 2) if axis == 0 else ((2, 0) if axis == 1 else (0, 1))
    out[axis, axis] = 1.0
    out[i, i], out[j, j], out[i, j], out[j, i] = c, c, -s, s
    return out


def _mm(a, b):
    """a @ b of two (3, 3) matrices."""
    out = np.zeros((3, 3))
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, 0] * b[0, j] + a[i, 1] * b[1, j] + a[i, 2] * b[2, j]
    return out


def _mv(a, v):
    """a @ v of a (3, 3) matrix and a 3-vector."""
    return np.array([a[i, 0] * v[0] + a[i, 1] * v[1] + a[i, 2] * v[2] for i in range(3)])


def _tv(a, v):
    """a.T @ v (v @ a) of a (3, 3) matrix and a 3-vector."""
    return np.array([a[0, j] * v[0] + a[1, j] * v[1] + a[2, j] * v[2] for j in range(3)])


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _blade(rot, v0, omega, air, pitch, stations, weights, moment_weights, foil, rho):
    """(force, moment about the blade frame's origin) in the common frame of one blade: its frame `rot` (3, 3,
    columns the blade axes), origin velocity v0 and angular velocity omega (3,), the air's velocity at each station
    air (S, 3) and the pitch (S,) rad (`aerodynamics.section_velocities` and `blade_loads`)."""
    chord, slope, alpha0, stall, cd0, cd2 = foil[0], foil[1], foil[2], foil[3], foil[4], foil[5]
    omega_b = _tv(rot, omega)
    force, first_y, first_z = np.zeros(3), 0.0, 0.0
    for s in range(stations.size):
        rel = _tv(rot, v0 - air[s])
        u_t = rel[1] + omega_b[2] * stations[s]
        u_p = rel[2] - omega_b[1] * stations[s]
        u_r = -rel[0]
        speed = math.sqrt(u_t * u_t + u_p * u_p)
        alpha = pitch[s] - math.atan2(u_p, u_t) - alpha0
        cl = slope * min(max(alpha, -stall), stall)
        cd = cd0 + cd2 * alpha * alpha
        q = (0.5 * rho * chord) * speed
        f_y, f_z = -q * (cl * u_p + cd * u_t), q * (cl * u_t - cd * u_p)
        force[0] += q * cd * u_r * weights[s]
        force[1] += f_y * weights[s]
        force[2] += f_z * weights[s]
        first_y += f_y * moment_weights[s]
        first_z += f_z * moment_weights[s]
    return _mv(rot, force), _mv(rot, np.array([0.0, -first_z, first_y]))


def loads(q, q_t, azimuth, hinges, index, main, main_foil, tail, tail_foil, tail_frames, state, rho):
    """(Q (n,) the generalized forces, the main rotor's force and moment about the hub centre in fuselage axes,
    the tail hub's force and moment and the fuselage drag (global), the fuselage rotation (3, 3)).

    azimuth (B, 3, 3), hinges (B, 3): each main blade's fixed rotation about the hub and hinge offset; index: (hub
    coordinate, first flap coordinate); main, tail (4, S): stations, weights, first-moment weights, twist;
    tail_frames (Bt, 3, 3) the tail blades' frames on their hub; state: wind (3), hub offset (3), tail hub
    offset (3), inflow nu (3), tip speed, r / R of the main stations (S), then the tail's induced velocity, its
    collective, the drag's 0.5 rho f_e."""
    compiled.jit(globals(), COMPILED)
    return _loads(q, q_t, azimuth, hinges, index, main, main_foil, tail, tail_foil, tail_frames, state, rho)


def _loads(q, q_t, azimuth, hinges, index, main, main_foil, tail, tail_foil, tail_frames, state, rho):
    hub_i, flap0, n_b, n_s = index[0], index[1], azimuth.shape[0], main.shape[1]
    wind, hub_offset, tail_offset, nu = state[0:3], state[3:6], state[6:9], state[9:12]
    tip_speed, r_over_radius = state[12], state[13 : 13 + n_s]
    tail_vi, tail_collective, half_drag = state[13 + n_s], state[14 + n_s], state[15 + n_s]
    r3 = _rot(0, q[3])
    r4 = _mm(r3, _rot(1, q[4]))
    r5 = _mm(r4, _rot(2, q[5]))
    omega_f = r3[:, 0] * q_t[3] + r4[:, 1] * q_t[4] + r5[:, 2] * q_t[5]
    v_f = q_t[0:3].copy()
    hub = _mv(r5, hub_offset)
    r6 = _mm(r5, _rot(2, q[hub_i]))
    omega_h = omega_f + r5[:, 2] * q_t[hub_i]
    v_h = v_f + _cross(omega_f, hub)
    out = np.zeros(q.size)
    rotor_force, about_hub, air = np.zeros(3), np.zeros(3), np.empty((n_s, 3))
    psi0 = q[hub_i] - math.pi  # `inflow.blade_azimuth`
    for b in range(n_b):
        f = flap0 + 3 * b
        r_flap = _mm(_mm(r6, azimuth[b]), _rot(1, q[f]))
        r_lag = _mm(r_flap, _rot(2, q[f + 1]))
        blade = _mm(r_lag, _rot(0, q[f + 2]))
        hinge = _mv(r6, hinges[b])
        omega_b = omega_h + r_flap[:, 1] * q_t[f] + r_flap[:, 2] * q_t[f + 1] + r_lag[:, 0] * q_t[f + 2]
        psi = psi0 + 2.0 * math.pi * b / n_b
        harmonic = nu[1] * math.sin(psi) + nu[2] * math.cos(psi)
        for s in range(n_s):  # element by element: a row assignment compiles a shape check's error path (slow)
            inflow = tip_speed * (nu[0] + r_over_radius[s] * harmonic)
            for i in range(3):
                air[s, i] = wind[i] - inflow * r5[i, 2]
        force, moment = _blade(blade, v_h + _cross(omega_h, hinge), omega_b, air, main[3], main[0], main[1],
                               main[2], main_foil, rho)  # fmt: skip
        rotor_force += force
        about_hub += moment + _cross(hinge, force)
        out[f] = _dot(r_flap[:, 1], moment)
        out[f + 1] = _dot(r_flap[:, 2], moment)
        out[f + 2] = _dot(r_lag[:, 0], moment)
    tail_point = _mv(r5, tail_offset)
    tail_rot = _mm(r5, _rot(1, q[-1]))
    tail_v = v_f + _cross(omega_f, tail_point)
    tail_omega = omega_f + r5[:, 1] * q_t[-1]
    tail_air = np.empty((tail.shape[1], 3))
    for s in range(tail.shape[1]):
        for i in range(3):
            tail_air[s, i] = wind[i] - tail_vi * r5[i, 1]
    tail_force, tail_moment = np.zeros(3), np.zeros(3)
    for k in range(tail_frames.shape[0]):
        force, moment = _blade(_mm(tail_rot, tail_frames[k]), tail_v, tail_omega, tail_air, tail_collective + tail[3],
                               tail[0], tail[1], tail[2], tail_foil, rho)  # fmt: skip
        tail_force += force
        tail_moment += moment
    relative = wind - v_f
    speed = math.sqrt(relative[0] * relative[0] + relative[1] * relative[1] + relative[2] * relative[2])
    drag = half_drag * speed * relative  # (not `_dot`: a contiguous argument would be a second signature to compile)
    fuselage_force = rotor_force + tail_force + drag
    out[0], out[1], out[2] = fuselage_force[0], fuselage_force[1], fuselage_force[2]
    about_cg = about_hub + tail_moment + _cross(hub, rotor_force) + _cross(tail_point, tail_force)
    out[3], out[4], out[5] = _dot(r3[:, 0], about_cg), _dot(r4[:, 1], about_cg), _dot(r5[:, 2], about_cg)
    out[hub_i] = _dot(r5[:, 2], about_hub)
    out[-1] = _dot(r5[:, 1], tail_moment)
    return out, _tv(r5, rotor_force), _tv(r5, about_hub), tail_force, tail_moment, drag, r5
