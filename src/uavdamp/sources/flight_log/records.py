"""What a reader hands on: the IMU's samples, the streams it came from, and what else the log says about the
vehicle (its vibration lines, higher-rate streams, the airborne evidence, corruption found on the way)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from uavdamp.contract import STANDARD_GRAVITY, XYZ

AXES = XYZ  # the log's sensor axes
G0 = STANDARD_GRAVITY  # m s-2
# full scales assumed when the log does not state them (assumption: the common MEMS IMU settings of PX4 and
# ArduPilot autopilots, 16 g and 2000 deg/s); PX4's FIFO topics state theirs (int16 samples times `scale`)
DEFAULT_ACC_RANGE_M_S2 = 16.0 * G0
DEFAULT_GYRO_RANGE_RAD_S = np.deg2rad(2000.0)
POLICIES = ("refuse", "record")


class FlightLogError(ValueError):
    """A flight log that cannot be used; the message names the file and what is wrong."""

    def __init__(self, path, problem: str):
        super().__init__(f"{path}: {problem}")


@dataclass(frozen=True)
class Line:
    """A vibration line the log itself shows: `source` (e.g. "sensor_gyro_fft"), axis, frequency (Hz), the
    time it was estimated at (s, log clock) and whether it is a rotor's rotation rate."""

    source: str
    axis: str
    freq_hz: float
    time_s: float = float("nan")  # when the log states it (nan: the whole log)
    per_rev: bool = False  # a rotor's rotation rate: its blade-pass line is blades x freq_hz


@dataclass(frozen=True)
class Stream:
    """Another inertial stream of the same log (e.g. a higher-rate gyro stream): name, times (s), FRD (3, n)."""

    name: str
    time_s: np.ndarray
    values: np.ndarray


@dataclass(frozen=True)
class Evidence:
    """Airborne evidence: `source` (e.g. "vehicle_land_detected"), times (s) and a flag per time (True:
    airborne), each holding until the next time; `notes`: what else the log says (altitude, throttle)."""

    source: str
    time_s: np.ndarray
    airborne: np.ndarray
    notes: str = ""


@dataclass(frozen=True)
class ImuRecord:
    """One IMU's samples as logged: gyro times and accelerometer times (s, log clock; the two streams may
    differ in rate and count), FRD vectors (3, n), where they came from, and what else the log holds."""

    time_s: np.ndarray  # angular-rate sample times
    acc_time_s: np.ndarray  # acceleration sample times
    acceleration: np.ndarray  # m s-2, specific force, FRD
    angular_rate: np.ndarray  # rad s-1, FRD
    messages: str
    clipped: np.ndarray | None = None  # True where the log flags accelerometer clipping
    acc_stream: str = ""  # the stream the acceleration came from (e.g. "sensor_accel_fifo")
    gyro_stream: str = ""
    acc_range_m_s2: float = DEFAULT_ACC_RANGE_M_S2  # the sensor's full scale
    gyro_range_rad_s: float = DEFAULT_GYRO_RANGE_RAD_S
    range_source: str = "assumed (16 g, 2000 deg/s)"
    lines: tuple[Line, ...] = ()  # the vehicle's lines as the log shows them
    streams: tuple[Stream, ...] = ()  # other inertial streams of the log (the aliasing check reads them)
    evidence: tuple[Evidence, ...] = ()  # airborne evidence
    corrupt: tuple[tuple[int, int], ...] = ()  # (byte offset, bytes skipped) per corrupt region
    attitude_rates: Stream | None = None  # body rates (rad s-1, FRD) from the logged attitude, for the unit check
    notes: dict = field(default_factory=dict)  # what the reader also found (info only)


def step_intervals(time_s: np.ndarray, flags: np.ndarray, end_s: float) -> list[tuple[float, float]]:
    """[(start, end), ...] s where a step signal (each flag holds from its time to the next, the last to end_s)
    is True."""
    out, start = [], None
    for t, on in zip(np.append(time_s, end_s), np.append(flags, False), strict=True):
        if on and start is None:
            start = float(t)
        elif not on and start is not None:
            if t > start:
                out.append((start, float(t)))
            start = None
    return out
