"""What the six-axis isolator's best damping depends on, for the gimbal the config names: the reference table's
construct (`uavdamp.reference_table.criteria`: the best C per point, its grid-edge flags, the best constant C and the
scheduling gain) on the payload, in closed form.

For a sine of the mount along one DOF (x, y, z at ``translation_amplitude_m``; roll, pitch, yaw at
``rotation_amplitude_rad``) at frequency f, with every element's stiffness scaled so that its z stiffness is K
(x and y in the ratio ``payload.six_axis.stiffness_n_m`` sets) and every element's damper at the constant C, the
gimbal's steady-state line of sight is the closed form of `uavdamp.study.transmissibility.gimbal_line_of_sight`
(the isolator's transmissibility, then each stabilised axis's sampled loop). Its criterion is the payload stage's
``los_std``: sqrt(var pitch + var yaw), the rms of a sine being its amplitude / sqrt 2; the roll is kept beside it
(``los_roll``). Per (DOF, f, K): the C that minimises the criterion; per (DOF, K): the one C that minimises its mean
over the frequencies, and the scheduling gain, the mean over the frequencies of the criterion at that C over the
criterion at the best C (1: scheduling C by frequency buys nothing on a mono-frequency input), per band of
``bands_hz``; per (K, C): the isolator's slowest 1/e decay time (how long the steady state takes to be reached:
`uavdamp.study.payload_schedule` chooses among the C that settle).

Choices and assumptions: steady state only (the transient from rest of a sampled loop has no closed form here;
the paper's table scored the start-up); the loop linear (below the torque limit, without the IMU's noise,
quantisation and accelerometer range: `uavdamp.study.payload_runs` runs those); one-way coupling (the motors'
reaction on the isolated body left out); one DOF at a time (on a mixed input the best C weighs the DOFs by their
levels). A DOF whose criterion is zero at every point (a balanced gimbal on a symmetric isolator: y, z and roll
reach only the line of sight's roll) has no optimum (NaN).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from uavdamp.platform.gimbal import AXES, design
from uavdamp.platform.six_axis import DOFS, rigid_body_modes, state_space, transmissibility
from uavdamp.reference_table.criteria import grid_edge
from uavdamp.reference_table.params import Axis
from uavdamp.settings import ConfigError, require, setting
from uavdamp.study import payload_runs as runs
from uavdamp.study.transmissibility import gimbal_line_of_sight

BANDS_HZ = (("helicopter", (3.0, 12.0)), ("multirotor", (80.0, 120.0)))  # Hz, the default bands as pairs
NO_LINE_OF_SIGHT = 1e-9  # 1, a DOF whose largest criterion is below this x the table's largest has none


@dataclass(frozen=True)
class TableSection:
    """The table's axes and input levels (``payload.table``)."""

    freq: Axis = setting("freq_hz", default=Axis(start=2.0, stop=120.0, num=49, spacing="log"))  # Hz
    stiffness: Axis = setting("stiffness_n_m", default=Axis(values=(125.0, 250.0, 500.0, 1000.0, 2000.0)))  # N m-1
    damping: Axis = setting("damping_n_s_m", default=Axis(start=0.1, stop=300.0, num=25, spacing="log"))  # N s m-1
    translation_amplitude: float = setting("translation_amplitude_m", default=1.3e-3)  # m
    rotation_amplitude: float = setting("rotation_amplitude_rad", default=1.0e-3)  # rad
    # Hz, {name: [low, high]}: where the best constant C and the scheduling gain are read (a vehicle's lines)
    bands: dict[str, tuple[float, ...]] = setting("bands_hz", default=BANDS_HZ)

    def validate(self, where: str) -> None:
        for key, axis in (("freq_hz", self.freq), ("stiffness_n_m", self.stiffness), ("damping_n_s_m", self.damping)):
            axis.validate(f"{where}.{key}")
        levels = {
            "translation_amplitude_m": self.translation_amplitude,
            "rotation_amplitude_rad": self.rotation_amplitude,
        }
        for key, value in levels.items():
            require(math.isfinite(value) and value > 0, f"{where}.{key}", f"must be > 0, got {value}")
        require(bool(self.bands), f"{where}.bands_hz", "needs at least one band {name: [low, high]}")
        for name, band in self.named_bands.items():
            ok = len(band) == 2 and band[0] < band[1] and np.any(self.band_mask(band))
            require(ok, f"{where}.bands_hz.{name}", f"needs [low, high] Hz holding a table frequency, got {list(band)}")

    @property
    def named_bands(self) -> dict[str, tuple[float, float]]:
        """{name: (low, high)} Hz (the default is stored as pairs: a dataclass default cannot be a dict)."""
        return {str(name): (float(b[0]), float(b[1])) for name, b in dict(self.bands).items()}

    def band_mask(self, band) -> np.ndarray:
        """(freq,) True where a table frequency lies in [low, high] Hz."""
        f = self.freq.array()
        return (f >= band[0]) & (f <= band[1])


def scaled(section, stiffness: float):
    """`section` (a `uavdamp.study.payload.PayloadSection`) with every element's stiffness scaled so that its z
    stiffness is `stiffness` N m-1, x and y in their configured ratio to z."""
    s = section.six_axis
    factor = stiffness / s.stiffness[2]
    return dataclasses.replace(
        section, six_axis=dataclasses.replace(s, stiffness=tuple(k * factor for k in s.stiffness))
    )


def check(section, where: str = "payload.table") -> None:
    """ConfigError naming the key when a table stiffness cannot carry the payload (a rocking mode unstable under
    its weight), a frequency reaches the gimbal loop's Nyquist frequency, or the six-axis isolator's own z
    stiffness is not in the table (the scheduled law reads the table there), or the scheduled law's
    ``max_decay_time_s`` leaves it no damping."""
    table = section.table
    own = float(section.six_axis.stiffness[2])
    ok = bool(np.any(np.isclose(table.stiffness.array(), own, rtol=1e-9)))
    require(
        ok,
        f"{where}.stiffness_n_m",
        f"must hold payload.six_axis.stiffness_n_m's z, {own} N m-1 (the scheduled law's K)",
    )
    nyquist = section.gimbal.loop_rate_hz / 2
    top = float(table.freq.array()[-1])
    require(top < nyquist, f"{where}.freq_hz", f"must stay below the gimbal loop's Nyquist {nyquist} Hz, got {top}")
    for k in table.stiffness.array():
        try:
            runs.six_axis_isolator(scaled(section, float(k)), 0.0)
        except ValueError as error:
            raise ConfigError(f"{where}.stiffness_n_m: {k} N m-1 cannot carry the payload ({error})") from None
    fastest = min(_decay_time(section, own, float(c)) for c in table.damping.array())
    limit = section.schedule.max_decay_time
    ok = fastest <= limit
    rule = f"({limit} s) leaves no damping of payload.table: the isolator's shortest decay time is {fastest:.3g} s"
    require(ok, "payload.schedule.max_decay_time_s", rule)
    section.anfis.check(table.freq.array())


def amplitudes(table: TableSection) -> np.ndarray:
    """(6,) the input sine's amplitude per DOF of `DOFS`: m for x, y, z, rad for roll, pitch, yaw."""
    return np.array([table.translation_amplitude] * 3 + [table.rotation_amplitude] * 3)


def line_of_sight(section, stiffness: float, damping, freq_hz) -> np.ndarray:
    """|line of sight| (3 axes of `AXES`, 6 DOFs, nc, nf), rad of amplitude per unit amplitude of the mount's DOF,
    of the gimbal on the six-axis isolator at element z stiffness `stiffness` N m-1 and constant C `damping`
    (nc,) N s m-1, at `freq_hz` (nf,): one closed-loop evaluation over every (C, DOF, f)."""
    f, c = np.asarray(freq_hz, dtype=float), np.atleast_1d(np.asarray(damping, dtype=float))
    k_section = scaled(section, stiffness)
    h = np.stack([transmissibility(runs.six_axis_isolator(k_section, float(ci)), f) for ci in c])  # (nc, nf, 6, 6)
    q = np.moveaxis(h, 3, 1).reshape(-1, 6)  # (nc * 6 * nf, 6): the body per unit mount DOF, C-major
    p = runs.gimbal_params(section)
    lever = (0.0, 0.0, runs.gimbal_height(section))
    los = gimbal_line_of_sight(p, design(p), lever, np.tile(f, c.size * 6), q)
    return np.abs(los).reshape(3, c.size, 6, f.size).transpose(0, 2, 1, 3)


def criterion_cube(section) -> tuple[np.ndarray, np.ndarray]:
    """(criterion, roll) (dof, freq, stiffness, damping), rad rms of the table's sine inputs: sqrt(pitch^2 +
    yaw^2) / sqrt 2 and |roll| / sqrt 2 of the amplitudes."""
    t = section.table
    f, ks, cs = t.freq.array(), t.stiffness.array(), t.damping.array()
    scale = amplitudes(t)[:, None, None] / math.sqrt(2)
    crit = np.empty((len(DOFS), f.size, ks.size, cs.size))
    roll = np.empty_like(crit)
    for j, k in enumerate(ks):
        los = line_of_sight(section, float(k), cs, f)  # (3, 6, nc, nf)
        crit[:, :, j, :] = (np.hypot(los[AXES.index("pitch")], los[AXES.index("yaw")]) * scale).transpose(0, 2, 1)
        roll[:, :, j, :] = (los[AXES.index("roll")] * scale).transpose(0, 2, 1)
    return crit, roll


def optimum(crit: np.ndarray, damping: np.ndarray, bands: np.ndarray) -> dict[str, np.ndarray]:
    """The optimum of a criterion cube (dof, freq, stiffness, damping) over the damping grid (N s m-1): damping_opt
    and criterion_opt (dof, freq, stiffness; the smallest C among equal minima) and its `grid_edge` flags; per band
    of the boolean mask `bands` (band, freq): damping_best_constant (dof, stiffness, band), criterion_best_constant
    (dof, freq, stiffness, band; NaN outside the band) and scheduling_gain (dof, stiffness, band). NaN for a DOF
    without a line of sight (`NO_LINE_OF_SIGHT`)."""
    blind = crit.max(axis=(1, 2, 3)) <= NO_LINE_OF_SIGHT * crit.max()
    ic = np.argmin(crit, axis=3)
    best = np.take_along_axis(crit, ic[..., None], axis=3)[..., 0]
    c_const, const, gain = [], [], []
    for mask in bands:
        jc = np.argmin(crit[:, mask].mean(axis=1), axis=2)  # (dof, stiffness)
        at = np.take_along_axis(crit, jc[:, None, :, None], axis=3)[..., 0]
        c_const.append(damping[jc])
        with np.errstate(invalid="ignore"):  # a DOF without a line of sight: 0 / 0, NaN as it should be
            gain.append(np.mean(at[:, mask] / best[:, mask], axis=1))
        const.append(np.where(mask[None, :, None], at, np.nan))
    out = {
        "damping_opt": damping[ic],
        "criterion_opt": best,
        "damping_best_constant": np.stack(c_const, axis=-1),
        "criterion_best_constant": np.stack(const, axis=-1),
        "scheduling_gain": np.stack(gain, axis=-1),
    }
    for value in out.values():
        value[blind] = np.nan
    out["optimum_at_grid_edge"] = np.where(blind[:, None, None], 0, grid_edge(ic, damping, None)).astype(np.int8)
    return out


def modes(section) -> np.ndarray:
    """(stiffness, 6) the six-axis isolator's rigid-body modes, Hz, at each table stiffness (undamped)."""
    ks = section.table.stiffness.array()
    return np.stack([rigid_body_modes(runs.six_axis_isolator(scaled(section, float(k)), 0.0))[0] for k in ks])


def _decay_time(section, stiffness: float, damping: float) -> float:
    """The six-axis isolator's slowest 1/e decay time, s, at element z stiffness and damping: max of -1 / Re(pole)."""
    poles = np.linalg.eigvals(state_space(runs.six_axis_isolator(scaled(section, stiffness), damping)).a)
    return float(np.max(-1.0 / poles.real))


def decay_times(section) -> np.ndarray:
    """(stiffness, damping) the isolator's slowest 1/e decay time, s: max over its poles of -1 / Re(pole), at
    each table stiffness and damping (how long a start-up or a change of C takes to reach the steady state)."""
    t = section.table
    out = np.empty((t.stiffness.array().size, t.damping.array().size))
    for (j, k), (i, c) in itertools.product(enumerate(t.stiffness.array()), enumerate(t.damping.array())):
        out[j, i] = _decay_time(section, float(k), float(c))
    return out


ROWS = {  # name: (dims, units, long_name)
    "criterion": (4, "rad", "line of sight sqrt(var pitch + var yaw), steady state, of the DOF's sine input"),
    "los_roll": (4, "rad", "line-of-sight roll rms, steady state, of the DOF's sine input"),
    "damping_opt": (3, "N s m-1", "damping minimising the criterion at each frequency and stiffness"),
    "criterion_opt": (3, "rad", "criterion at damping_opt"),
    "optimum_at_grid_edge": (
        3,
        "1",
        "damping_opt on an edge of the C grid (payload.table.damping_n_s_m): 1 bottom, 2 top, 0 interior",
    ),
    "damping_best_constant": (
        ("dof", "stiffness", "band"),
        "N s m-1",
        "single damping minimising the criterion's mean over the band's frequencies",
    ),
    "criterion_best_constant": (
        ("dof", "freq", "stiffness", "band"),
        "rad",
        "criterion at damping_best_constant (NaN outside the band)",
    ),
    "scheduling_gain": (
        ("dof", "stiffness", "band"),
        "1",
        "mean over the band's frequencies of criterion_best_constant / criterion_opt (1: scheduling buys nothing)",
    ),
    "mode_frequency": (("stiffness", "mode"), "Hz", "six-axis isolator rigid-body mode (undamped)"),
    "decay_time": (("stiffness", "damping"), "s", "the isolator's slowest 1/e decay time, max of -1 / Re(pole)"),
}
DIMS = {4: ("dof", "freq", "stiffness", "damping"), 3: ("dof", "freq", "stiffness")}


def table_dataset(section) -> xr.Dataset:
    """The table of the module docstring for `section` (a `uavdamp.study.payload.PayloadSection` with its camera)."""
    t = section.table
    f, ks, cs = t.freq.array(), t.stiffness.array(), t.damping.array()
    bands = np.stack([t.band_mask(b) for b in t.named_bands.values()])
    crit, roll = criterion_cube(section)
    values = {"criterion": crit, "los_roll": roll, **optimum(crit, cs, bands), "mode_frequency": modes(section)}
    values["decay_time"] = decay_times(section)
    data = {}
    for name, value in values.items():
        dims, units, long_name = ROWS[name]
        data[name] = (DIMS.get(dims, dims), value, {"units": units, "long_name": long_name})
    low, high = np.array(list(t.named_bands.values()), dtype=float).T
    coords = {
        "dof": ("dof", list(DOFS), {"units": "1", "long_name": "mount DOF driven (x, y, z; rotations about them)"}),
        "freq": ("freq", f, {"units": "Hz", "long_name": "frequency of the mount's sine"}),
        "stiffness": ("stiffness", ks, {"units": "N m-1", "long_name": "each element's z stiffness (x, y scaled)"}),
        "damping": ("damping", cs, {"units": "N s m-1", "long_name": "each element's damping C along x, y, z"}),
        "mode": ("mode", np.arange(len(DOFS)), {"units": "1", "long_name": "rigid-body mode, ascending frequency"}),
        "band": ("band", list(t.named_bands), {"units": "1", "long_name": "frequency band of a vehicle's lines"}),
        "band_low": ("band", low, {"units": "Hz", "long_name": "band's lower edge"}),
        "band_high": ("band", high, {"units": "Hz", "long_name": "band's upper edge"}),
    }
    attrs = {
        "window": "steady state (closed form)",
        "criterion_name": "los_std",
        "translation_amplitude_m": t.translation_amplitude,
        "rotation_amplitude_rad": t.rotation_amplitude,
        "gimbal_axes": " ".join(section.gimbal.axes),
        "stiffness_ratio_xyz": " ".join(f"{k / section.six_axis.stiffness[2]:g}" for k in section.six_axis.stiffness),
        "coupling": "one-way (the gimbal's reaction left out); linear (below the torque limit, no sensor errors)",
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)
