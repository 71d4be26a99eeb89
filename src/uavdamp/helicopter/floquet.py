"""Floquet analysis of the linearised helicopter over one rotor revolution (imbalanced rotor allowed).

The linearisation about hover without aerodynamics (blades in the disc plane, fuselage at rest, hub at
Omega t), in the blades' rotating coordinates, is periodic with the revolution T = 2 pi / Omega:
x' = A(Omega t) x. The monodromy matrix Phi(T) is the product of exp(A(psi_mid) h) over `n_steps` azimuth
steps (exponential midpoint rule, second order in h); its eigenvalues mu give the Floquet exponents
s = ln(mu) / T, whose imaginary parts are defined only modulo Omega (returned in (-Omega/2, Omega/2]).
For the balanced rotor they must equal the multiblade (Coleman) eigenvalues modulo Omega (a test checks it).
For an imbalanced rotor the linearisation ignores the small forced motion of the fuselage (an assumption:
the periodic orbit is taken as the hover state).
"""

from __future__ import annotations

import numpy as np
import xarray as xr
from scipy.linalg import expm

from uavdamp.helicopter import model as H
from uavdamp.helicopter.modes import linearise
from uavdamp.helicopter.params import Helicopter


def state_matrix(m: np.ndarray, d: np.ndarray, k: np.ndarray) -> np.ndarray:
    """First-order form of M q'' + D q' + K q = 0: x = (q, q'), x' = A x (1/s)."""
    n = m.shape[0]
    return np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(m, k), -np.linalg.solve(m, d)]])


def monodromy(heli: Helicopter, n_steps: int = 360) -> np.ndarray:
    """State transition matrix over one main-rotor revolution (rotating blade coordinates; hub and tail hub
    held by their constraints, tail rotor stopped)."""
    omega = heli.main_rotor.omega_rad_s
    if omega <= 0:
        raise ValueError(f"main_rotor.omega_rad_s: {omega}; a Floquet analysis needs a turning rotor")
    if heli.tail_rotor.omega_rad_s != 0.0:
        raise ValueError(
            f"tail_rotor.omega_rad_s: {heli.tail_rotor.omega_rad_s}; the tail rotor must be stopped (a second period)"
        )
    if n_steps < 8:
        raise ValueError(f"n_steps: {n_steps}; at least 8 azimuth steps per revolution")
    model = H.build(heli)
    n = model.mbs.systemData.ODE2Size()
    held = [H.HUB_LINK, n - 1]
    h = 2 * np.pi / omega / n_steps
    phi = np.eye(2 * (n - len(held)))
    for step in range(n_steps):
        psi = 2 * np.pi * (step + 0.5) / n_steps
        m, k, d = linearise(model, heli, psi, held)
        phi = expm(state_matrix(m, d, k) * h) @ phi
    return phi


def floquet_exponents(heli: Helicopter, n_steps: int = 360) -> np.ndarray:
    """Floquet exponents s (1/s) of the linearised helicopter, imaginary parts wrapped into (-Omega/2, Omega/2],
    sorted by decay rate then frequency."""
    omega = heli.main_rotor.omega_rad_s
    mu = np.linalg.eigvals(monodromy(heli, n_steps))
    period = 2 * np.pi / omega
    s = np.log(mu.astype(complex)) / period  # principal log: Im in (-Omega/2, Omega/2]
    return s[np.lexsort((s.imag, -s.real))]


def wrap_frequency(omega_rad_s: np.ndarray, rotor_omega_rad_s: float) -> np.ndarray:
    """Angular frequencies wrapped into (-Omega/2, Omega/2], rad/s (the Floquet ambiguity)."""
    half = rotor_omega_rad_s / 2
    return -((-np.asarray(omega_rad_s) + half) % rotor_omega_rad_s - half)


def floquet_dataset(heli: Helicopter, n_steps: int = 360) -> xr.Dataset:
    """Floquet exponents of `heli` with non-negative imaginary part (one per conjugate pair) as a Dataset on
    dimension `exponent`: frequency modulo Omega (rad s-1) and decay rate (s-1)."""
    s = floquet_exponents(heli, n_steps)
    s = s[s.imag >= 0]
    attrs = {
        "units": "rad s-1",
        "long_name": "Floquet exponent imaginary part (angular frequency modulo the "
        f"rotor speed, in [0, Omega/2]), main blade {heli.imbalance.blade} at mass factor "
        f"{heli.imbalance.mass_factor}",
    }
    return xr.Dataset(
        {
            "floquet_frequency": ("exponent", s.imag, attrs),
            "floquet_decay_rate": ("exponent", -s.real, {"units": "s-1", "long_name": "Floquet exponent -Re(s)"}),
        },
        coords={"exponent": ("exponent", np.arange(s.size), {"units": "1", "long_name": "Floquet exponent number"})},
        attrs={"floquet_azimuth_steps": n_steps},
    )
