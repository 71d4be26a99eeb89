"""Stated vibration sources: a mount motion defined by its parameters alone (no upstream run or log).

A source of the config's ``sources`` section (`StatedSource`, one entry per name) is a `kind` and that kind's keys;
`KINDS` maps each kind to its generator and the keys it takes. A study case (``study.cases.NAME.source``) and a
benchmark scenario (``benchmark.sources``) use a source by name, so both experiments share one definition:

    sweep            a linear chirp of amplitude_m over freq_hz = [start, end] (y upwards, z downwards)
    tones            sines of amplitude_m each at freq_y_hz (y) and freq_z_hz (z)
    random           white noise (seeded) band-passed to band_hz (4th-order Butterworth, zero phase), each axis
                     scaled to the RMS of a sine of amplitude_m
    sine_on_random   a helicopter's lines (1/rev, N/rev, 2N, 3N, the tail rotor's 1/rev and N/rev) on a random floor
                     (`uavdamp.sources.profiles.helicopter_source`; every default level is an assumption)
    multirotor       blade-pass lines and a floor scaled to a stated ArduPilot VIBE level
                     (`uavdamp.sources.profiles.multirotor_source`)

`generate(source, duration_s, sample_rate_hz)` returns the source as a dataset in the flight-log layout
(`mount_displacement`, `mount_rotation` over (axis x, y, z; time), m and rad, inertial frame) with its stated
levels in the attributes. The sweep, tones and random kinds are the benchmark's synthetic scenarios
(``benchmark.synthetic`` entries use the same generators at ``benchmark.amplitude_m``).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
import xarray as xr

from uavdamp.contract import MOUNT_AXES, MountMotion
from uavdamp.settings import require, setting
from uavdamp.sources import profiles

# kind -> the keys it takes (beyond kind); a kind's generator is `_GENERATORS[kind]`
KINDS = {
    "sweep": ("freq_hz", "amplitude_m"),
    "tones": ("freq_y_hz", "freq_z_hz", "amplitude_m"),
    "random": ("band_hz", "seed", "amplitude_m"),
    "sine_on_random": ("rotor_hz", "blades", "tail_rotor_hz", "tail_blades", "levels", "seed", "highpass_hz"),
    "multirotor": ("vibe_m_s2", "motor_rpm", "blades", "motors", "spread", "floor_share", "seed", "highpass_hz"),
}
SYNTHETIC = ("sweep", "tones", "random")  # the kinds that move the mount in y and z only, at a stated amplitude
_HELICOPTER_LEVELS = {  # config key under ``levels`` -> `profiles.HELICOPTER_LEVELS` entry
    "one_per_rev_in_s": "1/rev_in_s",
    "n_per_rev_g": "N/rev_g",
    "two_n_per_rev_g": "2N/rev_g",
    "three_n_per_rev_g": "3N/rev_g",
    "tail_one_per_rev_g": "tail_1/rev_g",
    "tail_n_per_rev_g": "tail_N/rev_g",
    "floor_g2_hz": "floor_g2_hz",
    "floor_band_hz": "floor_band_hz",
}


@dataclass(frozen=True)
class HelicopterLevels:
    """The sine-on-random source's levels (``sources.NAME.levels``), 0-peak per axis (x, y, z); every default is
    an assumption (`uavdamp.sources.profiles.HELICOPTER_LEVELS` gives each one's rationale)."""

    one_per_rev_in_s: tuple[float, ...] = setting(length=3)  # in/s, main-rotor 1/rev velocity
    n_per_rev_g: tuple[float, ...] = setting(length=3)  # g, N/rev acceleration
    two_n_per_rev_g: tuple[float, ...] = setting(length=3)  # g
    three_n_per_rev_g: tuple[float, ...] = setting(length=3)  # g
    tail_one_per_rev_g: tuple[float, ...] = setting(length=3)  # g
    tail_n_per_rev_g: tuple[float, ...] = setting(length=3)  # g
    floor_g2_hz: tuple[float, ...] = setting(length=3)  # g^2 Hz-1, one-sided acceleration PSD of the floor
    floor_band_hz: tuple[float, ...] = setting(length=2)  # Hz, the floor's band

    def validate(self) -> None:
        for f in fields(self):
            values = getattr(self, f.name)
            require(min(values) >= 0, f"levels.{f.name}", f"must be >= 0, got {list(values)}")

    def as_profile(self) -> dict:
        """The levels in `uavdamp.sources.profiles`' naming."""
        return {_HELICOPTER_LEVELS[f.name]: tuple(getattr(self, f.name)) for f in fields(self)}


@dataclass(frozen=True)
class StatedSource:
    """One stated source (an entry of ``sources``): a `kind` of `KINDS` and that kind's keys; the others null."""

    kind: str = setting()
    description: str = setting(default="")
    sample_rate_hz: float = setting(default=1000.0)  # Hz, the source's own sampling (a study brings it to its cases')
    amplitude_m: float | None = setting(default=None)  # m, sweep, tones, random
    freq_hz: tuple[float, ...] | None = setting(default=None)  # Hz, sweep: [start, end]
    freq_y_hz: tuple[float, ...] | None = setting(default=None)  # Hz, tones on y
    freq_z_hz: tuple[float, ...] | None = setting(default=None)  # Hz, tones on z
    band_hz: tuple[float, ...] | None = setting(default=None)  # Hz, random: band-pass [low, high]
    seed: int | None = setting(default=None)  # random, sine_on_random, multirotor: the generator's seed
    rotor_hz: float | None = setting(default=None)  # Hz, sine_on_random: main-rotor speed
    blades: int | None = setting(default=None)  # sine_on_random: main-rotor blades; multirotor: blades a propeller
    tail_rotor_hz: float | None = setting(default=None)  # Hz, sine_on_random: tail-rotor speed
    tail_blades: int | None = setting(default=None)  # sine_on_random
    levels: HelicopterLevels | None = setting(default=None)  # sine_on_random
    highpass_hz: float | None = setting(default=None)  # Hz, sine_on_random, multirotor: lowest content kept
    vibe_m_s2: float | None = setting(default=None)  # m s-2, multirotor: ArduPilot VIBE of the largest axis
    motor_rpm: float | None = setting(default=None)  # rev min-1, multirotor: mean motor speed
    motors: int | None = setting(default=None)  # multirotor
    spread: float | None = setting(default=None)  # 1, multirotor: motor speeds spread +- this fraction
    floor_share: float | None = setting(default=None)  # 1, multirotor: share of the variance in the floor

    def validate(self, where: str) -> None:
        require(self.kind in KINDS, f"{where}.kind", f"must be one of {list(KINDS)}, got {self.kind!r}")
        takes = KINDS[self.kind]
        for f in fields(self):
            if f.name in ("kind", "description", "sample_rate_hz"):
                continue
            given = getattr(self, f.name) is not None
            require(given == (f.name in takes), f"{where}.{f.name}", f"kind {self.kind!r} takes {list(takes)}")
        require(self.sample_rate_hz > 0, f"{where}.sample_rate_hz", f"must be > 0, got {self.sample_rate_hz}")
        for key in ("freq_hz", "band_hz"):
            values = getattr(self, key)
            if values is not None:
                ok = len(values) == 2 and 0 < values[0] < values[1]
                require(ok, f"{where}.{key}", f"need 0 < low < high, got {list(values)}")
        if self.amplitude_m is not None:
            require(self.amplitude_m > 0, f"{where}.amplitude_m", f"must be > 0, got {self.amplitude_m}")

    def lines_hz(self) -> np.ndarray:
        """Hz, the frequencies the source puts its content at: a sweep's or a random band's two ends, every tone,
        every stated line of a profile (`profiles.helicopter_lines`, `profiles.multirotor_lines`); sorted."""
        if self.kind in ("sweep", "random"):
            found = list(self.freq_hz if self.kind == "sweep" else self.band_hz)
        elif self.kind == "tones":
            found = [*self.freq_y_hz, *self.freq_z_hz]
        elif self.kind == "sine_on_random":
            lines = profiles.helicopter_lines(self.rotor_hz, self.blades, self.tail_rotor_hz, self.tail_blades)
            found = [line.freq_hz for line in lines]
        else:
            lines = profiles.multirotor_lines(self.motor_rpm, self.blades, self.motors, self.spread)
            found = [line.freq_hz for line in lines]
        return np.sort(np.asarray(found, dtype=float))

    @property
    def synthetic(self) -> bool:
        """True for the kinds that move the mount in y and z only (`SYNTHETIC`)."""
        return self.kind in SYNTHETIC


def synthetic_yz(kind: str, spec, *, duration: float, amplitude: float, time_step: float):
    """(time s, y m, z m) of a sweep, tones or random input (module docstring), sampled every time_step s; `spec`
    has the kind's keys as attributes or mapping entries."""
    from scipy.signal import butter, chirp, sosfiltfilt

    get = spec.get if isinstance(spec, dict) else lambda k: getattr(spec, k)
    t = np.arange(int(round(duration / time_step)) + 1) * time_step
    if kind == "sweep":
        f0, f1 = get("freq_hz")
        y = amplitude * chirp(t, f0, duration, f1, method="linear", phi=-90)
        z = amplitude * chirp(t, f1, duration, f0, method="linear", phi=-90)
    elif kind == "tones":
        y, z = (amplitude * sum(np.sin(2 * np.pi * f * t) for f in get(key)) for key in ("freq_y_hz", "freq_z_hz"))
    elif kind == "random":
        rng = np.random.default_rng(int(get("seed")))
        sos = butter(4, get("band_hz"), btype="bandpass", fs=1.0 / time_step, output="sos")
        y, z = (sosfiltfilt(sos, rng.standard_normal(t.size)) for _ in range(2))
        y, z = (x * amplitude / np.sqrt(2.0) / np.std(x) for x in (y, z))
    else:
        raise ValueError(f"synthetic kind: must be one of {list(SYNTHETIC)}, got {kind!r}")
    return t, y, z


def _profile(source: StatedSource, duration_s: float) -> xr.Dataset:
    if source.kind == "sine_on_random":
        return profiles.helicopter_source(
            source.rotor_hz,
            source.blades,
            tail_hz=source.tail_rotor_hz,
            tail_blades=source.tail_blades,
            levels=source.levels.as_profile(),
            duration_s=duration_s,
            sample_rate_hz=source.sample_rate_hz,
            highpass_hz=source.highpass_hz,
            seed=source.seed,
        )
    return profiles.multirotor_source(
        source.vibe_m_s2,
        motor_rpm=source.motor_rpm,
        blades=source.blades,
        motors=source.motors,
        spread=source.spread,
        floor_share=source.floor_share,
        duration_s=duration_s,
        sample_rate_hz=source.sample_rate_hz,
        highpass_hz=source.highpass_hz,
        seed=source.seed,
    )


LINE_TABLE = ("freq_hz", "accel_g", "velocity_in_s", "displacement_m")  # a profile's stated lines (line, axis)


def motion(source: StatedSource, duration_s: float) -> tuple[np.ndarray, MountMotion, dict]:
    """(time s from 0, mount motion, stated levels: flat attributes and, for a profile, its line table) of a
    source over duration_s s."""
    if source.synthetic:
        amplitude, step = source.amplitude_m, 1.0 / source.sample_rate_hz
        t, y, z = synthetic_yz(source.kind, source, duration=duration_s, amplitude=amplitude, time_step=step)
        return t, MountMotion.planar(y, z), {"stated_amplitude_m": amplitude}
    ds = _profile(source, duration_s)
    stated = {k: v for k, v in ds.attrs.items() if isinstance(v, str | int | float)}
    stated["lines"] = ds[[v for v in (*LINE_TABLE, "vibe_m_s2") if v in ds]].rename(mount_axis="axis")
    return ds.time.values - ds.time.values[0], profiles.mount_motion(ds), stated


def generate(source: StatedSource, name: str, duration_s: float) -> xr.Dataset:
    """The source as a dataset in the flight-log layout (module docstring): mount_displacement, mount_rotation
    (axis, time), m and rad, with `source_kind`, `description` and the stated levels as attributes."""
    t, moved, attrs = motion(source, duration_s)
    lines = attrs.pop("lines", None)
    frame = "inertial: x forward, y left, z up"
    data = {
        "mount_displacement": (
            ("axis", "time"),
            moved.translation,
            {"units": "m", "long_name": "translation of the platform mount", "frame": frame},
        ),
        "mount_rotation": (
            ("axis", "time"),
            moved.rotation,
            {"units": "rad", "long_name": "rotation vector of the platform mount", "frame": frame},
        ),
    }
    coords = {
        "axis": ("axis", list(MOUNT_AXES), {"units": "1", "long_name": "mount axis (x forward, y left, z up)"}),
        "time": ("time", t, {"units": "s", "long_name": "time"}),
    }
    attrs = {**attrs, "source": name, "kind": source.kind, "description": source.description}
    ds = xr.Dataset(data, coords=coords, attrs=attrs)
    return ds if lines is None else ds.merge(lines)
