"""Helicopter model physics: closed-form hinged-blade frequencies, imbalance, momentum, rotor angle."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from conftest import helicopter_of, solver_options
from scipy.spatial.transform import Rotation

from uavdamp.helicopter import model as H


@pytest.fixture(scope="module")
def heli(default_config) -> H.Helicopter:
    return helicopter_of(default_config["helicopter"])


def hinged_blade_frequencies(heli: H.Helicopter) -> np.ndarray:
    """Closed form for uniform rods hinged at offset e, spinning at Omega (fuselage held), rad/s.

    flap: nu^2 = Omega^2 (1 + 3e / (2L)) + k_flap / I_h
    lag:  nu^2 = Omega^2 (3e / (2L))     + k_lag / I_h,  I_h = I_com + m (L/2)^2 (about the hinge)
    feather: nu^2 = k_feather / I_axis (no propeller moment: the two other inertias are equal).
    A blade's mass scale cancels in flap and lag; its feather inertia scales with it.
    """
    main = heli.main_rotor
    e, length, omega = main.hinge_offset, main.blade_length, main.omega_rad_s
    ix, i_axis, iz = main.blade_inertia
    out = []
    for mass in heli.blade_masses():
        scale = mass / main.blade_mass
        i_flap = scale * ix + mass * (length / 2) ** 2
        i_lag = scale * iz + mass * (length / 2) ** 2
        out.append(np.sqrt(omega**2 * (1 + 3 * e / (2 * length)) + main.flap_stiffness / i_flap))
        out.append(np.sqrt(omega**2 * (3 * e / (2 * length)) + main.lag_stiffness / i_lag))
        out.append(np.sqrt(main.feather_stiffness / (scale * i_axis)))
    return np.sort(out)


@pytest.mark.parametrize("lag_stiffness", [0.0, 2e4], ids=["free-lag-hinge", "lag-spring"])
def test_blade_frequencies_match_closed_form(heli, lag_stiffness):
    heli = replace(heli, main_rotor=replace(heli.main_rotor, lag_stiffness=lag_stiffness))
    expected = hinged_blade_frequencies(heli)
    computed = H.blade_frequencies(heli)
    assert computed.shape == expected.shape == (3 * heli.main_rotor.n_blades,)
    np.testing.assert_allclose(computed, expected, rtol=0.01)
    # the textbook pair, unaffected by springs when they are zero
    if lag_stiffness == 0.0:
        omega, e, length = heli.main_rotor.omega_rad_s, heli.main_rotor.hinge_offset, heli.main_rotor.blade_length
        assert np.any(np.isclose(computed, omega * np.sqrt(3 * e / (2 * length)), rtol=0.01))
        assert np.any(np.isclose(computed, omega * np.sqrt(1 + 3 * e / (2 * length)), rtol=0.01))


def test_balanced_rotor_vibrates_a_million_times_less(heli):
    options = solver_options(duration=2.0, step=0.002, output_step=0.004)
    imbalanced = H.run(heli, options).mount_displacement.sel(mount="cg", axis=["y", "z"])
    balanced = H.run(heli.balanced(), options).mount_displacement.sel(mount="cg", axis=["y", "z"])
    ratio = float(np.abs(balanced).max() / np.abs(imbalanced).max())
    assert float(np.abs(imbalanced).max()) > 1e-3  # a real vibration, mm scale
    assert ratio < 1e-6


def test_rotor_angle_exact_after_50_s(heli):
    ds = H.run(heli, solver_options(duration=50.0, step=0.0025, output_step=0.005))
    assert float(ds.time[-1]) == pytest.approx(50.0)
    assert abs(ds.attrs["rotor_angle_error_rad"]) < 1e-8


def test_initial_velocity_cancels_rotor_momentum(heli):
    v0 = H.initial_fuselage_velocity(heli)
    assert np.linalg.norm(v0) > 0.5  # the imbalance alone would carry the helicopter away (m/s)
    assert np.allclose(H.initial_fuselage_velocity(heli.balanced()), 0.0)


def test_total_linear_momentum_stays_zero(heli):
    """Zero at t = 0 by construction; afterwards only the integrator's error (no external force)."""
    model = H.build(heli, momentum_sensors=True)
    H.solve(model, solver_options(duration=3.0, step=0.001, output_step=0.005))
    time, momentum = H.linear_momentum(model)
    main = heli.main_rotor
    rotor_scale = (
        main.blade_mass
        * (1 - heli.imbalance.mass_factor)
        * main.omega_rad_s
        * (main.hinge_offset + main.blade_length / 2)
    )  # kg m/s the imbalance carries
    assert np.abs(momentum[0]).max() < 1e-9 * rotor_scale
    assert np.abs(momentum).max() < 1e-3 * rotor_scale


def test_invalid_parameters_are_named(default_config):
    cfg = default_config["helicopter"]
    bad = {**cfg, "fuselage": {**cfg["fuselage"], "mass_kg": -1.0}}
    with pytest.raises(ValueError, match="fuselage.mass"):
        helicopter_of(bad)
    bad = {**cfg, "imbalance": {**cfg["imbalance"], "blade": 7}}
    with pytest.raises(ValueError, match="imbalance.blade"):
        helicopter_of(bad)
    solver = {**cfg["solver"], "step_s": 0.002, "output_step_s": 0.005}
    with pytest.raises(ValueError, match=r"helicopter\.solver\.output_step_s: 0\.005 s must be a whole multiple"):
        helicopter_of({**cfg, "solver": solver})


@pytest.mark.parametrize("rotor", ["main_rotor", "tail_rotor"])
def test_blade_radius_of_gyration_longer_than_the_blade_is_refused(default_config, rotor):
    """The paper prints Ix = Iz = 12.48 kg m2 for the 6.212 kg, 0.982 m tail blade: sqrt(12.48 / 6.212) = 1.42 m."""
    cfg = default_config["helicopter"]
    tail = {**cfg["tail_rotor"], "blade_inertia_kg_m2": [12.48, 0.015, 12.48]}
    with pytest.raises(
        ValueError, match=r"tail_rotor.blade_inertia_kg_m2: 12.48 kg m2 gives a radius of gyration 1.42 m"
    ):
        helicopter_of({**cfg, "tail_rotor": tail})
    blade = cfg[rotor]
    length = blade["blade_length_m"]
    inertia = blade["blade_mass_kg"] * (1.01 * length) ** 2
    bad = {**cfg, rotor: {**blade, "blade_inertia_kg_m2": [inertia, blade["blade_inertia_kg_m2"][1], inertia]}}
    with pytest.raises(ValueError, match=f"{rotor}.blade_inertia_kg_m2"):
        helicopter_of(bad)
    rod = blade["blade_mass_kg"] * length**2 / 12  # a uniform rod is accepted
    helicopter_of({**cfg, rotor: {**blade, "blade_inertia_kg_m2": [rod, blade["blade_inertia_kg_m2"][1], rod]}})


def test_config_tail_blade_is_a_uniform_rod(default_config):
    tail = default_config["helicopter"]["tail_rotor"]
    rod = tail["blade_mass_kg"] * tail["blade_length_m"] ** 2 / 12
    assert tail["blade_inertia_kg_m2"][0] == pytest.approx(rod, rel=1e-3)
    assert tail["blade_inertia_kg_m2"][2] == pytest.approx(rod, rel=1e-3)


def test_mount_points_move_as_one_rigid_body(heli):
    """Every mount point's displacement is the centre of mass's plus (R(t) - R(0)) r, R the fuselage's attitude
    (rigid-body kinematics, exact); to first order in the rotation, theta x r."""
    heli = replace(heli, mount_points={"cg": (0.0, 0.0, 0.0), "nose_low": (2.0, 0.0, -1.0), "tail": (-6.0, 0.5, 1.72)})
    ds = H.run(heli, solver_options(duration=1.0, step=0.002, output_step=0.004))
    rotation = Rotation.from_rotvec(ds.mount_rotation.transpose("time", "axis").values)
    cg = ds.mount_displacement.sel(mount="cg").transpose("time", "axis").values
    theta = ds.mount_rotation.transpose("time", "axis").values
    assert np.abs(theta).max() > 1e-4  # the imbalanced rotor rocks the fuselage
    for name in ("nose_low", "tail"):
        r = np.asarray(heli.mount_points[name])
        got = ds.mount_displacement.sel(mount=name).transpose("time", "axis").values
        np.testing.assert_allclose(got, cg + rotation.apply(r) - r, rtol=0, atol=1e-12)
        first_order = cg + np.cross(theta, r)
        assert np.abs(got - first_order).max() <= np.abs(theta).max() ** 2 * np.linalg.norm(r)  # second-order term
    assert ds.mount_rotation.attrs["units"] == "rad" and "rotation vector" in ds.mount_rotation.attrs["rotation"]


def test_a_run_repeats_exactly(heli):
    """The vacuum run draws no random number: run twice, every variable is bit for bit the same (what lets the
    pipeline's determinism test seed the helicopter stage from the session's quick run)."""
    options = solver_options(duration=0.3, step=0.002, output_step=0.004)
    first, second = H.run(heli, options), H.run(heli, options)
    assert set(first.variables) == set(second.variables)
    for name in first.variables:
        np.testing.assert_array_equal(first[name].values, second[name].values, err_msg=name)
