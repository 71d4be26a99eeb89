"""Real flight logs -> the camera mount's motion: PX4 ULog, ArduPilot DataFlash and a plain CSV.

`read_flight_log` reads the log's highest-rate inertial measurement unit (IMU) stream (`px4`, `ardupilot`,
`formats.read_csv`; the attributes `acc_stream`, `gyro_stream`, `acc_rate_hz`, `gyro_rate_hz` say which),
turns its axes into uavdamp's (x forward, y left, z up; the logs' FRD y and z negated), resamples it onto a
uniform grid at the log's median rate (cubic spline), moves the acceleration from the IMU to the mount by
rigid-body kinematics, and integrates acceleration and body rates in a band (`uavdamp.signals.inertial.band_integrate`)
to the mount's displacement and small-angle rotation. Formats are told apart by content (the file's extension,
if .ulg, .bin or .csv, must agree).

Refused with `FlightLogError` (a ValueError naming the file): an unknown or mislabelled format, a truncated file
(one cut on a message boundary reads as a shorter flight: neither ULog nor DataFlash has an end marker), a missing
topic/message/column, non-finite values, timestamps that do not increase, units that cannot be SI (`checks`), a
window outside the log, a median sample rate below 2 f_high, any sample interval in the window longer than
1 / (2 f_high), a window shorter than `inertial.min_duration_s(band_hz)` = 8 / f_low; and, unless asked to record
them instead: a vehicle line (PX4's gyro FFT, rotor speeds, a higher-rate stream) above the stream's Nyquist
frequency (`aliasing`), a window not wholly airborne by the log's evidence (`airborne`), samples beyond the
sensor's full scale, isolated spikes and corrupt DataFlash messages (`checks`, `ardupilot`).

`python -m uavdamp.sources.flight_log PATH` prints what a log holds (`info`).
"""

from uavdamp.sources.flight_log.ardupilot import imu_from_messages, read_dataflash
from uavdamp.sources.flight_log.formats import (
    CSV_COLUMNS,
    DATAFLASH_HEAD,
    EXTENSIONS,
    FORMAT_NAMES,
    ULOG_MAGIC,
    detect_format,
    read_csv,
    ulog_truncation,
)
from uavdamp.sources.flight_log.motion import READERS, log_span, read_flight_log, read_record
from uavdamp.sources.flight_log.px4 import RELATIVE_TIMESTAMP_INVALID, read_ulog
from uavdamp.sources.flight_log.records import AXES, FlightLogError, ImuRecord
from uavdamp.sources.flight_log.source import FlightLogSource

__all__ = [
    "AXES",
    "CSV_COLUMNS",
    "DATAFLASH_HEAD",
    "EXTENSIONS",
    "FORMAT_NAMES",
    "READERS",
    "RELATIVE_TIMESTAMP_INVALID",
    "ULOG_MAGIC",
    "FlightLogError",
    "FlightLogSource",
    "ImuRecord",
    "detect_format",
    "imu_from_messages",
    "log_span",
    "read_csv",
    "read_dataflash",
    "read_flight_log",
    "read_record",
    "read_ulog",
    "ulog_truncation",
]
