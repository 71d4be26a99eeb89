"""Coupled rotor-fuselage modes of the balanced rotor in multiblade (Coleman) coordinates; Campbell diagram.

Linearised about hover without aerodynamics (blades in the disc plane, fuselage at rest, hub turning at
Omega), the equations of motion in the blades' rotating coordinates are periodic in the rotor azimuth psi:
eigenvalues taken at one instant are not modes. For an isotropic rotor of N >= 3 blades the multiblade
transform q_blades = B(psi) z (collective, cyclic cos/sin n = 1 .. (N-1)/2, differential if N is even) makes
them time-invariant. Route chosen: Exudyn linearises the whole helicopter at a rotor azimuth psi (M, K, D
with centrifugal and Coriolis terms), and the transform is applied analytically with its time derivatives,
q = T z, dq/dt = T dz/dt + Omega T' z, d2q/dt2 = T d2z/dt2 + 2 Omega T' dz/dt + Omega^2 T'' z, so that

    M_z = T^-1 M T,   D_z = T^-1 (D T + 2 Omega M T'),   K_z = T^-1 (K T + Omega D T' + Omega^2 M T'').

Exudyn's model stays the only model (no second derivation to keep in step). Checks (tests/test_helicopter_modes.py):
the transformed matrices do not depend on psi (a wrong blade order or azimuth breaks that); with the hub held
the cyclic flap and lag modes sit at nu + Omega and |nu - Omega| (the Omega terms); at rest the modes are
Exudyn's own complex eigenvalues. Eigenvalues of (M_z, D_z, K_z) are fixed-frame frequencies.
"""

from __future__ import annotations

from dataclasses import replace

import exudyn as exu
import numpy as np
import xarray as xr

from uavdamp.helicopter import model as H
from uavdamp.helicopter.params import Helicopter

FUSELAGE_COORDINATES = ("x", "y", "z", "roll", "pitch", "yaw")
BLADE_COORDINATES = ("flap", "lag", "feather")  # per blade, in the tree's order
RIGID_TOL_RAD_S = 1e-3  # |eigenvalue| below this is a rigid-body (zero) root
CLUSTER_TOL = 1e-3  # relative distance of eigenvalues treated as one repeated root


def multiblade_matrix(n_blades: int, psi: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coleman matrix B (blade k, multiblade coordinate) at rotor azimuth psi (rad), and dB/dpsi, d2B/dpsi2.

    Columns: collective, cos(n psi_k), sin(n psi_k) for n = 1 .. (N-1)//2, then (-1)^k if N is even;
    psi_k = psi + 2 pi k / N. Square and invertible for N >= 3.
    """
    if n_blades < 3:
        raise ValueError(
            f"main_rotor.n_blades: {n_blades}; the multiblade transform needs an isotropic rotor "
            "of at least 3 blades (a 2-blade rotor stays periodic)"
        )
    psi_k = psi + 2 * np.pi * np.arange(n_blades) / n_blades
    cols = [[np.ones(n_blades), np.zeros(n_blades), np.zeros(n_blades)]]
    for n in range(1, (n_blades - 1) // 2 + 1):
        c, s = np.cos(n * psi_k), np.sin(n * psi_k)
        cols += [[c, -n * s, -(n**2) * c], [s, n * c, -(n**2) * s]]
    if n_blades % 2 == 0:
        cols.append([(-1.0) ** np.arange(n_blades), np.zeros(n_blades), np.zeros(n_blades)])
    return tuple(np.stack([col[d] for col in cols], axis=1) for d in range(3))


def multiblade_names(n_blades: int) -> list[str]:
    """Names of the model's free coordinates in multiblade form: fuselage, then per blade DOF its harmonics."""
    harmonics = ["collective"]
    for n in range(1, (n_blades - 1) // 2 + 1):
        harmonics += [f"cyclic cos {n}", f"cyclic sin {n}"]
    if n_blades % 2 == 0:
        harmonics.append("differential")
    return list(FUSELAGE_COORDINATES) + [f"{dof} {h}" for dof in BLADE_COORDINATES for h in harmonics]


def _transform(n_blades: int, psi: float, n_fuselage: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """T, T', T'' mapping multiblade coordinates (fuselage, then per DOF kind) to the free tree coordinates
    (fuselage, then blade k's flap, lag, feather)."""
    n_dof = len(BLADE_COORDINATES)
    size = n_fuselage + n_dof * n_blades
    out = []
    for d, b in enumerate(multiblade_matrix(n_blades, psi)):
        t = np.zeros((size, size))
        if d == 0:
            t[:n_fuselage, :n_fuselage] = np.eye(n_fuselage)
        for j in range(n_dof):
            rows = n_fuselage + n_dof * np.arange(n_blades) + j
            cols = n_fuselage + j * n_blades + np.arange(n_blades)
            t[np.ix_(rows, cols)] = b
        out.append(t)
    return tuple(out)


def linearise(model: H.Model, heli: Helicopter, psi: float, held: list[int]):
    """M, K, D of the free coordinates (held ones deleted) at rotor azimuth psi (rad), rotor at Omega."""
    mbs = model.mbs
    n = mbs.systemData.ODE2Size()
    q, v = np.zeros(n), np.zeros(n)
    q[H.HUB_LINK] = psi
    v[H.HUB_LINK] = heli.main_rotor.omega_rad_s
    for config in (exu.ConfigurationType.Initial, exu.ConfigurationType.Current):
        mbs.systemData.SetODE2Coordinates(q, configuration=config)
        mbs.systemData.SetODE2Coordinates_t(v, configuration=config)
    # coordinate constraints only: their nullspace is the other coordinates, so delete rows and columns
    # (Exudyn's SVD projection would return an arbitrary basis and lose the coordinates' identity)
    m, k, d = (
        np.asarray(a)
        for a in mbs.ComputeLinearizedSystem(exu.SimulationSettings(), projectIntoConstraintNullspace=False)[:3]
    )
    free = np.setdiff1d(np.arange(n), held)
    return tuple(a[np.ix_(free, free)] for a in (m, k, d))


def _check_isotropic(heli: Helicopter) -> None:
    if heli.imbalance.mass_factor != 1.0:
        raise ValueError(
            "imbalance.mass_factor: the multiblade analysis needs the balanced rotor "
            f"(got {heli.imbalance.mass_factor}); use Helicopter.balanced()"
        )
    if heli.tail_rotor.omega_rad_s != 0.0 and heli.tail_rotor.n_blades < 3:
        raise ValueError(
            f"tail_rotor.omega_rad_s: {heli.tail_rotor.omega_rad_s}; a turning "
            f"{heli.tail_rotor.n_blades}-blade tail rotor makes the system periodic: stop it (0)"
        )


def multiblade_system(heli: Helicopter, psi: float = 0.0, *, fix_fuselage: bool = False):
    """(M_z, D_z, K_z) in multiblade coordinates at rotor azimuth psi (rad), and the coordinate names.

    Units: kg, kg m, kg m^2 (and per s, per s^2) as the coordinates are m or rad. For the balanced rotor
    the result does not depend on psi (a test checks this).
    """
    _check_isotropic(heli)
    model = H.build(heli, fix_fuselage=fix_fuselage)
    n = model.mbs.systemData.ODE2Size()
    held = [H.HUB_LINK, n - 1] + (list(range(6)) if fix_fuselage else [])
    m, k, d = linearise(model, heli, psi, held)
    n_fuselage = 0 if fix_fuselage else 6
    t, t1, t2 = _transform(heli.main_rotor.n_blades, psi, n_fuselage)
    omega = heli.main_rotor.omega_rad_s
    t_inv = np.linalg.inv(t)
    mz = t_inv @ m @ t
    dz = t_inv @ (d @ t + 2 * omega * m @ t1)
    kz = t_inv @ (k @ t + omega * d @ t1 + omega**2 * m @ t2)
    names = multiblade_names(heli.main_rotor.n_blades)[6 - n_fuselage :]
    return (mz, dz, kz), names


def modes(m: np.ndarray, d: np.ndarray, k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One eigenvalue (1/s) and displacement shape per degree of freedom of M q'' + D q' + K q = 0.

    An oscillating mode is its root with positive imaginary part; the non-oscillating degrees of freedom are
    zero roots (a double zero counting once) and then the slowest other real roots (an overdamped degree of
    freedom by its slower root; a damped free hinge's root pair 0, -c/I may show as -c/I). Returns
    (eigenvalues (n,), shapes (n, n) as columns), sorted by frequency then decay rate.
    """
    n = m.shape[0]
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(m, k), -np.linalg.solve(m, d)]])
    lam = np.linalg.eigvals(a)
    lam = np.where(np.abs(lam) < RIGID_TOL_RAD_S, 0.0, lam)
    oscillating = lam[lam.imag > RIGID_TOL_RAD_S]
    # non-oscillating degrees of freedom: zero roots, a double zero (rigid body, free hinge) counting once,
    # then the slowest other real roots (an overdamped degree of freedom by its slower root)
    n_zero = min(int(np.ceil(np.sum(lam == 0) / 2)), n - oscillating.size)
    real = lam[(np.abs(lam.imag) <= RIGID_TOL_RAD_S) & (lam != 0)].real
    n_over = n - oscillating.size - n_zero
    if n_over < 0 or n_over > real.size:
        raise RuntimeError(
            f"mode selection: {oscillating.size} oscillating, {n_zero} zero and {real.size} real "
            f"roots do not make {n} degrees of freedom"
        )
    slow = real[np.argsort(np.abs(real), kind="stable")][:n_over]
    lam = np.concatenate([oscillating, np.zeros(n_zero), slow]).astype(complex)
    lam = lam[np.lexsort((-lam.real, lam.imag))]
    return lam, _shapes(m, d, k, lam)


def _shapes(m, d, k, lam: np.ndarray) -> np.ndarray:
    """Null vectors of lam^2 M + lam D + K by SVD, one per eigenvalue; eigenvalues within CLUSTER_TOL of each
    other share one SVD and take its smallest singular vectors in turn (distinct vectors for repeated roots,
    where the state matrix's own eigenvectors are unreliable: the rigid-body roots are defective)."""
    shapes = np.zeros((m.shape[0], lam.size), dtype=complex)
    done = np.zeros(lam.size, dtype=bool)
    for i in range(lam.size):
        if done[i]:
            continue
        group = np.flatnonzero(~done & (np.abs(lam - lam[i]) <= CLUSTER_TOL * max(1.0, abs(lam[i]))))
        s = lam[group].mean()
        _, _, vh = np.linalg.svd(s**2 * m + s * d + k)
        shapes[:, group] = vh[::-1][: group.size].conj().T
        done[group] = True
    return shapes


def mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Modal assurance criterion |a_i^H b_j|^2 / ((a_i^H a_i)(b_j^H b_j)) between the columns of a and b, 1."""
    cross = np.abs(a.conj().T @ b) ** 2
    norm = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    return cross / np.maximum(norm, np.finfo(float).tiny)


def track(
    shapes: list[np.ndarray], start: int, eigenvalues: list[np.ndarray] | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Follow modes across steps by MAC, outward from step `start` (whose order defines the mode numbers).

    Matches are one-to-one, minimising the summed (1 - MAC) plus, when `eigenvalues` (1/s, per step) are
    given, the relative eigenvalue distance |s_a - s_b| / (|s_a| + |s_b| + 1 s-1), which breaks near-ties
    (e.g. a progressive and a regressive mode that whirl the same way have equal shapes). Returns (order
    (steps, modes): column index at each step of each mode, mac (steps, modes): the MAC of each match with the
    neighbouring step towards `start`, 1 at `start`).
    """
    from scipy.optimize import linear_sum_assignment

    n_steps, n = len(shapes), shapes[start].shape[1]
    order, score = np.zeros((n_steps, n), dtype=int), np.ones((n_steps, n))
    order[start] = np.arange(n)
    for direction in (1, -1):
        step = start + direction
        while 0 <= step < n_steps:
            prev = order[step - direction]
            matrix = mac(shapes[step - direction][:, prev], shapes[step])
            cost = 1.0 - matrix
            if eigenvalues is not None:
                a, b = eigenvalues[step - direction][prev][:, None], eigenvalues[step][None, :]
                cost = cost + np.abs(a - b) / (np.abs(a) + np.abs(b) + 1.0)
            rows, cols = linear_sum_assignment(cost)
            order[step, rows] = cols
            score[step, rows] = matrix[rows, cols]
            step += direction
    return order, score


def mode_labels(
    shapes: np.ndarray, share: np.ndarray, names: list[str], frequency: np.ndarray, omega: float, second: float = 0.25
) -> list[str]:
    """A name per mode (columns of `shapes`; energy `share` (mode, coordinate); fixed-frame `frequency`, rad/s,
    at rotor speed `omega`): its largest coordinate group (a cyclic cos/sin pair counts as one, with its
    branch), and the second group after " + " when that holds more than `second` of the energy."""
    groups = {}
    for i, name in enumerate(names):
        groups.setdefault(name.replace(" cos ", " ").replace(" sin ", " "), []).append(i)
    labels = []
    for mode in range(shapes.shape[1]):
        energy = {g: share[mode, idx].sum() for g, idx in groups.items()}
        ranked = sorted(energy, key=energy.get, reverse=True)
        parts = [
            g + _branch(shapes[groups[g], mode], frequency[mode], omega) if len(groups[g]) == 2 else g
            for g in ranked[:2]
            if g == ranked[0] or energy[g] > second
        ]
        labels.append(" + ".join(parts))
    return labels


def _branch(cos_sin: np.ndarray, frequency: float, omega: float) -> str:
    """ " progressive" (nu + Omega: whirls with the rotor, above Omega) or " regressive" (|nu - Omega|) for the
    cos and sin amplitudes (a_c, a_s) of a mode exp(i w t): it whirls with the rotor when Im(conj(a_c) a_s) < 0
    (a_s = -i a_c)."""
    with_rotor = np.imag(np.conj(cos_sin[0]) * cos_sin[1]) < 0
    return " progressive" if with_rotor and frequency > omega else " regressive"


def periodicity_residual(heli: Helicopter, azimuths_rad, reference=None) -> float:
    """Largest relative change of (M_z, D_z, K_z) between psi = 0 and each azimuth (rad), 1: zero for a valid
    transform of an isotropic rotor (up to Exudyn's numerical differentiation)."""
    ref = reference if reference is not None else multiblade_system(heli, 0.0)[0]
    worst = 0.0
    for psi in azimuths_rad:
        other = multiblade_system(heli, float(psi))[0]
        changes = (np.abs(a - b).max() / max(np.abs(a).max(), 1e-300) for a, b in zip(ref, other, strict=True))
        worst = max(worst, *changes)
    return float(worst)


def _with_rotor_speed(heli: Helicopter, omega_rad_s: float) -> Helicopter:
    return replace(heli, main_rotor=replace(heli.main_rotor, omega_rad_s=float(omega_rad_s)))


def _modes_over_speeds(heli: Helicopter, speeds: np.ndarray, check_azimuths_rad):
    """Per rotor speed: eigenvalues, mode shapes, energy shares, periodicity residual; and the coordinate names."""
    lams, shapes, shares, residual = [], [], [], []
    for omega in speeds:
        h = _with_rotor_speed(heli, omega)
        (mz, dz, kz), names = multiblade_system(h, 0.0)
        lam, vec = modes(mz, dz, kz)
        energy = np.abs(vec) ** 2 * np.diag(mz)[:, None]
        lams.append(lam)
        shapes.append(vec)
        shares.append(energy / np.maximum(energy.sum(axis=0), np.finfo(float).tiny))
        residual.append(periodicity_residual(h, check_azimuths_rad, reference=(mz, dz, kz)))
    return lams, shapes, shares, residual, names


_CAMPBELL_ATTRS = {
    "frequency": ("rad s-1", "modal angular frequency, fixed frame"),
    "frequency_hz": ("Hz", "modal frequency, fixed frame"),
    "damping_ratio": ("1", "modal damping ratio -Re(s)/|s| (NaN for a rigid-body zero root)"),
    "decay_rate": ("s-1", "modal decay rate -Re(s)"),
    "mac": ("1", "modal assurance criterion of the match with the neighbouring rotor speed towards the nominal one"),
    "energy_share": ("1", "share of the mode's kinetic energy in each multiblade coordinate (diagonal of M)"),
    "periodicity_residual": ("1", "largest relative change of the multiblade matrices with rotor azimuth"),
}


def campbell(heli: Helicopter, rotor_speeds_rad_s, *, check_azimuths_rad=(0.4, 1.3)) -> xr.Dataset:
    """Coupled rotor-fuselage modes of the balanced helicopter against main rotor speed (rad/s).

    Modes are numbered by frequency at the speed nearest the nominal Omega and followed outward by MAC.
    Frequencies are in the fixed frame. Variables: frequency (rad s-1 and Hz), damping ratio, decay rate,
    MAC of each match, each coordinate's share of the mode's kinetic energy (diagonal of M_z), and the
    transform's residual dependence on azimuth.
    """
    _check_isotropic(heli)
    speeds = np.asarray(rotor_speeds_rad_s, dtype=float)
    if speeds.ndim != 1 or speeds.size < 1 or np.any(speeds < 0) or np.any(np.diff(speeds) <= 0):
        raise ValueError(f"rotor_speeds_rad_s: must be non-negative and increasing, got {speeds}")
    lams, shapes, shares, residual, names = _modes_over_speeds(heli, speeds, check_azimuths_rad)
    start = int(np.argmin(np.abs(speeds - heli.main_rotor.omega_rad_s)))
    order, score = track(shapes, start, lams)
    lam = np.array([lams[s][order[s]] for s in range(speeds.size)]).T  # (mode, speed)
    share = np.array([shares[s][:, order[s]] for s in range(speeds.size)]).transpose(2, 0, 1)
    labels = mode_labels(shapes[start][:, order[start]], share[:, start, :], names, lam[:, start].imag, speeds[start])
    size = np.abs(lam)
    dims = ("mode", "rotor_speed")
    values = {
        "frequency": (dims, lam.imag),
        "frequency_hz": (dims, lam.imag / (2 * np.pi)),
        "damping_ratio": (dims, np.where(size > 0, -lam.real / np.where(size > 0, size, 1.0), np.nan)),
        "decay_rate": (dims, -lam.real),
        "mac": (dims, score.T),
        "energy_share": ((*dims, "coordinate"), share),
        "periodicity_residual": ("rotor_speed", residual),
    }
    data = {
        k: (d, v, dict(zip(("units", "long_name"), _CAMPBELL_ATTRS[k], strict=True))) for k, (d, v) in values.items()
    }
    coords = {
        "mode": ("mode", np.arange(lam.shape[0]), {"units": "1", "long_name": "mode number (by frequency at Omega)"}),
        "mode_label": (
            "mode",
            labels,
            {"units": "1", "long_name": "coordinate with the largest energy share at the nominal rotor speed"},
        ),
        "rotor_speed": ("rotor_speed", speeds, {"units": "rad s-1", "long_name": "main rotor speed"}),
        "coordinate": ("coordinate", names, {"units": "1", "long_name": "multiblade coordinate"}),
    }
    return xr.Dataset(data, coords=coords, attrs={"nominal_rotor_speed_rad_s": heli.main_rotor.omega_rad_s})
