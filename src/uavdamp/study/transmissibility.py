"""What each mount passes from the mount's motion to the camera's line of sight, in closed form: the per-axis
curves isolator makers print, for a camera fixed to the mount's body and for the stabilised gimbal on it.

For a mount motion e^{j w t} along one DOF (a rotation about roll, pitch or yaw, rad; or a translation, m) the
mount's body moves as q = H(j w) e at the reference point: H the isolator's transmissibility
(`uavdamp.platform.six_axis.transmissibility`, the elements' own damping), the identity on the rigid mount. A camera
fixed to the body turns with it: its line of sight about an axis is q's rotation about it. The gimbal, at the
point `lever` (m) of the body as in the payload runs, sees the body's rotation and rate about its axis, the
imbalance torque of the point's acceleration -w^2 T(lever) q on its offset camera (none when balanced) and that
acceleration's lateral component in its tilt reading, and answers through its sampled loop
(`uavdamp.platform.gimbal_loop.closed_loop`, exact at the sample times); one-way coupling as in the runs
(assumption: the motors' reaction on the body is left out). An axis the gimbal does not stabilise follows the body.
The runs' time-domain simulation (`uavdamp.study.payload_runs`) agrees within 1 % (tests/test_transmissibility.py).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from uavdamp.platform.gimbal import AXES, LATERAL, design, imbalance_torque
from uavdamp.platform.gimbal_loop import closed_loop
from uavdamp.platform.six_axis import DOFS, transform, transmissibility
from uavdamp.study import payload_runs as runs

FREQ_HZ = np.geomspace(0.5, 200.0, 241)  # Hz, the curves' grid (choice: 120 points a decade from 0.5 Hz)
CARRIED = ("fixed", "gimbal")  # a camera fixed to the mount's body; the stabilised gimbal on it
DIRECTIONS = ("x", "y", "z")  # the mount's translations


def body_motion(isolator, freq_hz: np.ndarray) -> np.ndarray:
    """H (nf, 6, 6): the body's DOF (row) per unit mount DOF (column) at the reference point; the identity for the
    rigid mount (`isolator` None)."""
    if isolator is None:
        return np.broadcast_to(np.eye(6, dtype=complex), (freq_hz.size, 6, 6))
    return transmissibility(isolator, freq_hz)


def gimbal_line_of_sight(p, gains: dict, lever, freq_hz: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The gimbal's line of sight (3, nf), rad, for the body's complex motion q (nf, 6) at the reference point:
    each stabilised axis through its closed loop, the others following the body."""
    w = 2 * np.pi * freq_hz
    point = -(w**2)[:, None] * (q @ transform(lever).T)  # (nf, 3) the gimbal's acceleration, m s-2
    los = q[:, 3:].T.copy()
    for axis, g in gains.items():
        i = AXES.index(axis)
        torque = imbalance_torque(p, axis, point.real.T) + 1j * imbalance_torque(p, axis, point.imag.T)
        lateral = point[:, LATERAL[axis]] if LATERAL[axis] is not None else np.zeros(freq_hz.size)
        inputs = np.stack([q[:, 3 + i], 1j * w * q[:, 3 + i], torque, lateral])
        los[i] = closed_loop(p, g, freq_hz, inputs)["line_of_sight"]
    return los


def line_of_sight(section, mount: str, carried: str, freq_hz=FREQ_HZ) -> np.ndarray:
    """Complex line of sight (3 LOS axes, 6 mount DOFs, nf), rad per unit mount DOF (m or rad), of `carried`
    ("fixed" or "gimbal") on `mount` ("rigid", "yz", "six_axis") at the section's middle damping."""
    f = np.asarray(freq_hz, dtype=float)
    h = body_motion(runs.isolator(section, mount, section.middle_damping), f)
    if carried == "fixed":
        return np.moveaxis(h[:, 3:, :], 0, -1)
    p = runs.gimbal_params(section)
    gains, lever = design(p), (0.0, 0.0, runs.gimbal_height(section))
    return np.stack([gimbal_line_of_sight(p, gains, lever, f, h[:, :, j]) for j in range(6)], axis=1)


def dataset(section, freq_hz=FREQ_HZ) -> xr.Dataset:
    """Per mount and carried camera: |line of sight about each axis| per mount rotation about the same axis
    (rad rad-1), and |line of sight| (root sum square over the axes) per mount acceleration along x, y, z
    (rad per m s-2: a translation of -1 / w^2 m). Not the wire-rope mount: below its yield stroke its curves are
    the six-axis isolator's (the same elements), above it they depend on the amplitude (no closed form)."""
    f = np.asarray(freq_hz, dtype=float)
    w2 = (2 * np.pi * f) ** 2
    mounts = [m for m in section.mounts if m != "wire_rope"]
    per_rotation = np.empty((len(mounts), len(CARRIED), 3, f.size))
    per_acceleration = np.empty_like(per_rotation)
    for m, mount in enumerate(mounts):
        for c, carried in enumerate(CARRIED):
            los = line_of_sight(section, mount, carried, f)
            per_rotation[m, c] = np.abs(np.stack([los[i, 3 + i] for i in range(3)]))
            per_acceleration[m, c] = np.sqrt((np.abs(los[:, :3]) ** 2).sum(axis=0)) / w2
    return _dataset(mounts, f, per_rotation, per_acceleration, section.middle_damping)


def _dataset(mounts, f, per_rotation, per_acceleration, damping: float) -> xr.Dataset:
    dims = ("mount", "carried", "axis", "frequency")
    data = {
        "los_per_rotation": (
            dims,
            per_rotation,
            {"units": "rad rad-1", "long_name": "line of sight about the axis per mount rotation about it"},
        ),
        "los_per_acceleration": (
            ("mount", "carried", "direction", "frequency"),
            per_acceleration,
            {"units": "rad s2 m-1", "long_name": "line of sight (root sum square of the axes) per mount acceleration"},
        ),
    }
    coords = {
        "mount": ("mount", mounts, {"units": "1", "long_name": "camera mount (isolator)"}),
        "carried": (
            "carried",
            list(CARRIED),
            {"units": "1", "long_name": "camera fixed to the mount or on the gimbal"},
        ),
        "axis": ("axis", list(AXES), {"units": "1", "long_name": "line-of-sight axis and mount rotation axis"}),
        "direction": ("direction", list(DIRECTIONS), {"units": "1", "long_name": "mount acceleration direction"}),
        "frequency": ("frequency", f, {"units": "Hz", "long_name": "frequency of the mount's sine motion"}),
    }
    attrs = {"damping_N_s_m": damping, "dofs": " ".join(DOFS), "coupling": "one-way (the gimbal's reaction left out)"}
    return xr.Dataset(data, coords=coords, attrs=attrs)
