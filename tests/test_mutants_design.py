"""The platform's closed-form design against hand-worked mass matrices, decoupled limits and mode shapes.

Issue 17's planted bug: the other root of design_stiffness's quadratic also places the modes at 4.5/5.7/6.7 Hz
but swaps which spring carries which mode (structural spring 2011 -> 1112 N/m). The mode shape says which is
which: in the designed platform the highest mode is the displacement mode.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
from test_platform import params

from uavdamp.platform.design import design_stiffness, mass_matrix, pitch_link

TARGETS_HZ = (6.7, 5.7, 4.5)


def hand_mass_matrix(com_x: float) -> np.ndarray:
    """The config's platform (tests/test_platform.py CONFIG) worked by hand, camera COM at (com_x, 0, 0.03) m.

    The camera is a 0.9 kg box 0.10 x 0.06 x 0.06 m: Iyy = m (a^2 + c^2) / 12, Izz = m (a^2 + b^2) / 12 about its
    COM, shifted to the pitch axis (origin) by m d^2; the pitch body (0.15 kg, 1e-4 kg m2) sits on that axis.
    """
    m_cam, a, b, c, com_z = 0.9, 0.10, 0.06, 0.06, 0.03
    m11 = 0.25 + 0.15 + m_cam
    j_yaw = 2.0e-4 + 1.0e-4 + m_cam * (a * a + b * b) / 12 + m_cam * com_x**2  # yaw axis through the origin
    j_pitch = 1.0e-4 + m_cam * (a * a + c * c) / 12 + m_cam * (com_x**2 + com_z**2)
    return np.array([[m11, 0.0, -m_cam * com_x], [0.0, j_yaw, 0.0], [-m_cam * com_x, 0.0, j_pitch]])


@pytest.mark.parametrize("com_x", [0.0, 0.015, -0.02])
def test_mass_matrix_worked_by_hand(com_x):
    m = mass_matrix(params(camera_com_x_m=com_x).structure)
    np.testing.assert_allclose(m, hand_mass_matrix(com_x), rtol=1e-13, atol=1e-18)


def test_pitch_link_mass_and_centre():
    mass, com, inertia = pitch_link(params().structure)
    assert mass == pytest.approx(1.05, rel=1e-15)
    np.testing.assert_allclose(com, [0.9 * 0.015 / 1.05, 0.0, 0.9 * 0.03 / 1.05], rtol=1e-14)
    assert inertia.shape == (3, 3) and np.allclose(inertia, inertia.T, rtol=0, atol=1e-18)


def test_decoupled_platform_has_one_spring_per_mode():
    """camera_com_x = 0: no coupling, so k_disp = m11 w_high^2, k_yaw = J_yaw w_mid^2, k_pitch = J_pitch w_low^2."""
    m = hand_mass_matrix(0.0)
    w = 2 * np.pi * np.array(TARGETS_HZ)
    expected = [m[0, 0] * w[0] ** 2, m[1, 1] * w[1] ** 2, m[2, 2] * w[2] ** 2]
    np.testing.assert_allclose(design_stiffness(params(camera_com_x_m=0.0).structure), expected, rtol=1e-12)


@pytest.mark.parametrize("com_x", [0.015, -0.02, 0.01])
def test_design_places_the_modes_exactly_with_the_displacement_mode_highest(com_x):
    """Kills 'the other root': eigenvalues of (diag(k), M) are the targets to 1e-12, and the 6.7 Hz mode's
    kinetic energy sits mostly in the displacement coordinate (the other root puts it in pitch)."""
    s = params(camera_com_x_m=com_x).structure
    k = design_stiffness(s)
    m = mass_matrix(s)
    lam, shapes = scipy.linalg.eigh(np.diag(k), m)
    np.testing.assert_allclose(np.sqrt(lam) / (2 * np.pi), sorted(TARGETS_HZ), rtol=1e-12)
    high = shapes[:, 2]
    assert m[0, 0] * high[0] ** 2 > m[2, 2] * high[2] ** 2
    low = shapes[:, 0]
    assert m[2, 2] * low[2] ** 2 > m[0, 0] * low[0] ** 2
    assert k[1] == pytest.approx(m[1, 1] * (2 * np.pi * 5.7) ** 2, rel=1e-14)


def test_too_strong_a_coupling_is_refused_naming_the_key():
    with pytest.raises(
        ValueError,
        match=r"platform.structure.camera_com_x_m: the displacement-pitch coupling 0\.\d+ "
        r"is too strong to place the modes at \(6.7, 5.7, 4.5\) Hz",
    ):
        design_stiffness(params(camera_com_x_m=0.2).structure)


def test_exudyn_eigen_analysis_meets_the_targets_to_round_off():
    """The design is exact: Exudyn's eigen-analysis of the built model returns the targets to 1e-9 (not 1 %)."""
    from uavdamp.platform import natural_frequencies

    freq_hz, _ = natural_frequencies(params())
    np.testing.assert_allclose(freq_hz, sorted(TARGETS_HZ), rtol=1e-9)
    assert math.isclose(freq_hz[0], 4.5, rel_tol=1e-9)
