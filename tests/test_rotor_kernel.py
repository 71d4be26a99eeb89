"""`uavdamp.helicopter.rotor_kernel.loads` (the compiled loads of `RotorLoads.update`) against the numpy pieces it
replaces on that path, assembled here: the tree's frames and generalized forces (`treekinematics`, checked against
Exudyn's SensorKinematicTree and virtual work in tests/test_helicopter_flight.py) and the section velocities and
loads (`aerodynamics`, checked against momentum and blade-element theory there)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from conftest import helicopter_of

from uavdamp.helicopter import flight as F
from uavdamp.helicopter import model as H
from uavdamp.helicopter.aerodynamics import blade_loads, section_velocities
from uavdamp.helicopter.inflow import blade_azimuth
from uavdamp.helicopter.model import HUB_LINK
from uavdamp.helicopter.rotorloads import RotorLoads
from uavdamp.helicopter.treekinematics import TreeKinematics


@pytest.fixture(scope="module")
def heli(default_config):
    return F.flight_helicopter(helicopter_of(default_config["helicopter"]).balanced())


def _reference(loads: RotorLoads, kin: TreeKinematics, q, q_t):
    """(Q, main force and moment about the hub in fuselage axes, tail force and moment, drag) from the numpy pieces."""
    fr = kin.frames(q, q_t)
    main, tail, rho = loads.main, loads.tail, loads.rho
    nu_0, nu_s, nu_c = loads.nu
    psi = blade_azimuth(q[HUB_LINK], main.n_blades)
    v_i = loads.tip_speed * (nu_0 + loads.r_over_radius * (nu_s * np.sin(psi) + nu_c * np.cos(psi))[:, None])
    air = loads.wind - v_i[..., None] * fr.fuselage[:, 2]
    u = section_velocities(main, fr.blades, fr.hinge_velocity, fr.blade_omega, air)
    lm = blade_loads(main, *u, main.twist, rho)
    force, moment = np.einsum("bij,bj->bi", fr.blades, lm.force), np.einsum("bij,bj->bi", fr.blades, lm.moment)
    rot = fr.tail @ loads.tail_frames
    air_t = loads.wind - loads.tail_lambda * loads.tail_omega * tail.tip_radius * fr.fuselage[:, 1]
    n = tail.n_blades
    vel, omega = np.broadcast_to(fr.tail_velocity, (n, 3)), np.broadcast_to(fr.tail_omega, (n, 3))
    lt = blade_loads(tail, *section_velocities(tail, rot, vel, omega, air_t), loads.tail_collective + tail.twist, rho)
    tail_force, tail_moment = np.einsum("bij,bj->i", rot, lt.force), np.einsum("bij,bj->i", rot, lt.moment)
    relative = loads.wind - fr.fuselage_velocity
    drag = loads.half_drag * np.linalg.norm(relative) * relative
    about_hub = moment.sum(axis=0) + np.cross(fr.hinges - fr.hub, force).sum(axis=0)
    q_gen = kin.generalized_forces(fr, force, moment, tail_force, tail_moment, drag)
    return q_gen, force.sum(axis=0) @ fr.fuselage, about_hub @ fr.fuselage, tail_force, tail_moment, drag


@pytest.mark.parametrize("inflow", ["uniform", "pitt_peters"])
def test_the_compiled_loads_are_the_numpy_pieces_at_random_states(heli, inflow):
    """Five random states of the free tree in a 20 m/s side wind, with an inflow (uniform, or with the Pitt-Peters
    harmonics), a tail inflow and collective: the generalized forces and the resultants agree within 1e-11 of
    each one's largest component (rounding of sums of a few hundred terms), the total force is Q's first three, and
    the kernel's loads move the tree (flap moments of 10^3 N m). Seen failing with the lag axis taken from the flap
    link, the harmonic inflow's azimuth off by one blade and the tail inflow along the wrong axis."""
    heli = replace(heli, aerodynamics=replace(heli.aerodynamics, inflow=inflow))
    model = H.build(heli)
    n = len(model.mbs.GetObjectParameter(0, "jointTypes"))
    rng = np.random.default_rng(4)
    loads = RotorLoads(model, heli, heli.aerodynamics, [3.0, 20.0, -1.0], 1.2, 1e-3)
    kin = TreeKinematics(heli, n)
    for _ in range(5):
        loads.nu[:] = [0.05, 0.01, -0.02] if inflow == "pitt_peters" else [0.05, 0.0, 0.0]
        loads.tail_lambda, loads.tail_collective = 0.03, -0.1
        q, q_t = 0.3 * rng.normal(size=n), rng.normal(size=n)
        q_t[HUB_LINK], q_t[-1] = heli.main_rotor.omega_rad_s, heli.tail_rotor.omega_rad_s
        expected = _reference(loads, kin, q, q_t)
        nu = loads.nu.copy()
        got = loads.update(q, q_t)
        loads.nu[:] = nu
        q_gen = np.asarray(model.mbs.GetObjectParameter(0, "jointForceVector"))
        pairs = zip(
            (q_gen, got.main_force, got.main_moment, got.tail_force, got.tail_moment, got.drag), expected, strict=True
        )
        for value, want in pairs:
            np.testing.assert_allclose(value, want, rtol=0, atol=1e-11 * np.abs(want).max())
        np.testing.assert_array_equal(got.total_force, q_gen[:3])
        assert np.abs(q_gen[HUB_LINK + 1 :: 3][:4]).max() > 1e3
