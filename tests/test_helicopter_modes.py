"""Coupled rotor-fuselage modes in multiblade coordinates: transform, closed forms, Exudyn's own eigen-analysis."""

from __future__ import annotations

from dataclasses import replace

import exudyn as exu
import numpy as np
import pytest
from conftest import helicopter_of

from uavdamp import io
from uavdamp.helicopter import floquet as F
from uavdamp.helicopter import model as H
from uavdamp.helicopter import modes as R


@pytest.fixture(scope="module")
def heli(default_config) -> H.Helicopter:
    return helicopter_of(default_config["helicopter"]).balanced()


def undamped(heli: H.Helicopter) -> H.Helicopter:
    return replace(heli, main_rotor=replace(heli.main_rotor, flap_damping=0.0, lag_damping=0.0, feather_damping=0.0))


def blade_hinge_inertias(heli: H.Helicopter) -> tuple[float, float, float, float]:
    """(S, J_flap, J_lag, J_axis) of a uniform blade about its hinge: first moment m L/2 (kg m) and moments of
    inertia (kg m^2); the paper's blade axes are x chordwise (flap), y along the blade, z normal (lag)."""
    main = heli.main_rotor
    ix, iy, iz = main.blade_inertia
    m, half = main.blade_mass, main.blade_length / 2
    return m * half, ix + m * half**2, iz + m * half**2, iy


@pytest.mark.parametrize("n_blades", [3, 4, 5])
def test_multiblade_matrix_derivatives_match_finite_differences(n_blades):
    psi, h = 0.7, 1e-5
    b, b1, b2 = R.multiblade_matrix(n_blades, psi)
    plus, minus = R.multiblade_matrix(n_blades, psi + h)[0], R.multiblade_matrix(n_blades, psi - h)[0]
    np.testing.assert_allclose(b1, (plus - minus) / (2 * h), atol=1e-8)
    np.testing.assert_allclose(b2, (plus - 2 * b + minus) / h**2, atol=1e-4)
    assert np.linalg.cond(b) < 10  # square, well conditioned: a change of coordinates


def test_two_blade_rotor_is_refused():
    with pytest.raises(ValueError, match="main_rotor.n_blades: 2"):
        R.multiblade_matrix(2, 0.0)


def test_imbalanced_rotor_is_refused(default_config):
    heli = helicopter_of(default_config["helicopter"])
    with pytest.raises(ValueError, match="imbalance.mass_factor"):
        R.campbell(heli, [0.0, heli.main_rotor.omega_rad_s])


def test_multiblade_matrices_do_not_depend_on_azimuth(heli):
    """In rotating coordinates the linearised matrices change with psi; after the transform they must not."""
    model = H.build(heli)
    n = model.mbs.systemData.ODE2Size()
    k0 = R.linearise(model, heli, 0.0, [H.HUB_LINK, n - 1])[1]
    k1 = R.linearise(model, heli, 1.3, [H.HUB_LINK, n - 1])[1]
    assert np.abs(k1 - k0).max() > 0.1 * np.abs(k0).max()  # periodic in the rotating frame
    assert R.periodicity_residual(heli, [0.4, 1.3, 2.9]) < 1e-5


def test_zero_speed_modes_equal_exudyns_eigen_analysis(heli):
    """At rest the multiblade transform is a constant change of coordinates: Exudyn's complex eigenvalues
    (first-order form with damping, constraints projected by SVD) are the Campbell modes at 0 rad/s."""
    still = R._with_rotor_speed(heli, 0.0)
    model = H.build(still)
    lam = np.asarray(
        model.mbs.ComputeODE2Eigenvalues(
            exu.SimulationSettings(),
            useSparseSolver=False,
            computeComplexEigenvalues=True,
            useAbsoluteValues=False,
            ignoreAlgebraicEquations=False,
            convert2Frequencies=False,
        )[0]
    )
    expected = np.sort_complex(lam[lam.imag > R.RIGID_TOL_RAD_S])
    ds = R.campbell(still, [0.0])
    computed = ds.frequency.values[:, 0] * 1j - ds.decay_rate.values[:, 0]
    oscillating = np.sort_complex(computed[computed.imag > 0])
    assert oscillating.size == expected.size > 0
    np.testing.assert_allclose(oscillating, expected, rtol=1e-6)
    # each non-oscillating degree of freedom (rigid body, free flap hinge; a free lag hinge with its damper)
    # is one of Exudyn's real roots, its slower one
    real = list(np.where(np.abs(lam) < R.RIGID_TOL_RAD_S, 0.0, lam.real)[np.abs(lam.imag) <= R.RIGID_TOL_RAD_S])
    for root in computed[computed.imag == 0].real:
        match = int(np.argmin(np.abs(np.array(real) - root)))
        assert abs(real.pop(match) - root) <= 1e-6 * (1 + abs(root))


def test_collective_flap_heave_mode_matches_closed_form(heli):
    """Collective flap beta of N blades hinged at e with the whole helicopter (mass M) free to heave z:

        M z'' + N S beta'' = 0,   J_flap beta'' + S z'' + (Omega^2 (e S + J_lag - J_axis) + k_flap) beta = 0,
        => omega^2 = (Omega^2 (e S + J_lag - J_axis) + k_flap) / (J_flap - N S^2 / M),

    S = m L / 2 the blade's first moment about its hinge; the centrifugal term is -d2/dbeta2 of
    Omega^2 I_zz(beta) / 2 about the shaft. No flap damper: the mode is undamped. (Fuselage held: M -> inf.)
    """
    main = heli.main_rotor
    s, j_flap, j_lag, j_axis = blade_hinge_inertias(heli)
    k_beta = main.omega_rad_s**2 * (main.hinge_offset * s + j_lag - j_axis) + main.flap_stiffness
    expected = np.sqrt(k_beta / (j_flap - main.n_blades * s**2 / heli.total_mass()))
    ds = R.campbell(heli, [0.0, main.omega_rad_s])
    share = ds.energy_share.sel(rotor_speed=main.omega_rad_s, coordinate="flap collective")
    mode = int(np.argmax(share.values))
    assert float(share[mode]) > 0.5  # the rest is mostly the heave
    assert float(ds.frequency.sel(rotor_speed=main.omega_rad_s)[mode]) == pytest.approx(expected, rel=0.01)
    assert float(ds.damping_ratio.sel(rotor_speed=main.omega_rad_s)[mode]) == pytest.approx(0.0, abs=1e-4)


def test_fuselage_held_cyclic_flap_and_lag_split_by_rotor_speed(heli):
    """Hub held: a blade flaps at nu_f and lags at nu_l in the rotating frame (closed forms below); in the fixed
    frame the collective and differential stay there and the cyclic pairs move to nu + Omega and |nu - Omega|.
        nu_f^2 = (Omega^2 (e S + J_lag - J_axis) + k_flap) / J_flap,
        nu_l^2 = (Omega^2 e S + k_lag) / J_lag   (turning a blade about its vertical hinge keeps its own I_zz).
    Undamped, to compare frequencies exactly."""
    heli = undamped(heli)
    main = heli.main_rotor
    omega, e = main.omega_rad_s, main.hinge_offset
    s, j_flap, j_lag, j_axis = blade_hinge_inertias(heli)
    nu_f = np.sqrt((omega**2 * (e * s + j_lag - j_axis) + main.flap_stiffness) / j_flap)
    nu_l = np.sqrt((omega**2 * e * s + main.lag_stiffness) / j_lag)
    (m, d, k), names = R.multiblade_system(heli, 0.3, fix_fuselage=True)
    lam, shapes = R.modes(m, d, k)
    freq = lam.imag
    energy = np.abs(shapes) ** 2 * np.diag(m)[:, None]
    labels = R.mode_labels(shapes, (energy / energy.sum(axis=0)).T, names, freq, omega)
    for nu, dof in ((nu_f, "flap"), (nu_l, "lag")):
        expected = {
            "collective": nu,
            "differential": nu,
            "cyclic 1 progressive": nu + omega,
            "cyclic 1 regressive": abs(nu - omega),
        }
        for name, target in expected.items():
            assert np.min(np.abs(freq - target)) < 0.01 * target
            if "cyclic" in name:
                assert labels[int(np.argmin(np.abs(freq - target)))] == f"{dof} {name}"


def test_mac_and_tracking():
    rng = np.random.default_rng(5)
    shapes = np.linalg.qr(rng.normal(size=(6, 6)))[0] + 0j
    np.testing.assert_allclose(R.mac(shapes, shapes * (2 - 3j)), np.eye(6), atol=1e-12)
    swapped = shapes[:, [1, 0, 2, 3, 5, 4]]
    order, score = R.track([shapes, swapped, shapes], start=0)
    np.testing.assert_array_equal(order[1], [1, 0, 2, 3, 5, 4])
    np.testing.assert_array_equal(order[2], np.arange(6))
    np.testing.assert_allclose(score, 1.0)


def test_campbell_dataset(heli):
    speeds = np.linspace(0.0, 1.2 * heli.main_rotor.omega_rad_s, 7)
    ds = R.campbell(heli, speeds)
    io.check_metadata(ds)
    assert ds.frequency.dims == ("mode", "rotor_speed") and ds.sizes["mode"] == 18
    nominal = ds.sel(rotor_speed=heli.main_rotor.omega_rad_s, method="nearest")
    np.testing.assert_allclose(nominal.mac, 1.0)
    assert "flap collective" in ds.mode_label.values
    np.testing.assert_allclose(ds.frequency_hz, ds.frequency / (2 * np.pi))
    with pytest.raises(ValueError, match="rotor_speeds_rad_s"):
        R.campbell(heli, [10.0, 5.0])


def test_floquet_exponents_of_the_balanced_rotor_are_its_multiblade_modes(heli):
    """Floquet (monodromy over one revolution, rotating coordinates) and Coleman (time-invariant multiblade
    form) are two routes to the same modes: equal decay rates, frequencies equal modulo Omega."""
    omega = heli.main_rotor.omega_rad_s
    lam = R.modes(*R.multiblade_system(heli)[0])[0]
    s = F.floquet_exponents(heli, n_steps=48)
    assert s.size == 2 * lam.size
    for target in lam:
        distance = np.abs(s.real - target.real) + np.abs(F.wrap_frequency(s.imag - target.imag, omega))
        assert distance.min() < 2e-3 * max(abs(target), 1.0)
    ds = F.floquet_dataset(heli, n_steps=48)
    io.check_metadata(ds)
    assert np.all((ds.floquet_frequency >= 0) & (ds.floquet_frequency <= omega / 2 + 1e-9))


def test_floquet_refuses_a_rotor_at_rest(heli):
    with pytest.raises(ValueError, match="main_rotor.omega_rad_s: 0.0"):
        F.monodromy(R._with_rotor_speed(heli, 0.0))
