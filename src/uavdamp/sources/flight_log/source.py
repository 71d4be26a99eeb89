"""One configured flight log (``flight_logs.NAME``): what the flight_log stage calls `read_flight_log` with."""

from __future__ import annotations

from dataclasses import dataclass

from uavdamp.settings import require, setting
from uavdamp.sources.flight_log.records import POLICIES


@dataclass(frozen=True)
class FlightLogSource:
    """One measured flight of the config (``flight_logs.NAME``): what `read_flight_log` is called with."""

    path: str = setting()  # the log file, relative to the run directory (where Snakemake runs: the repository's root)
    band_hz: tuple[float, ...] = setting(length=2)  # Hz, the integration band
    window_s: tuple[float, ...] | None = setting(default=None, length=2)  # s of the log's clock; None: all of it
    imu_to_mount_m: tuple[float, ...] = setting(default=(0.0, 0.0, 0.0), length=3)  # m, mount minus IMU, body axes
    upsample: int = setting(default=1)  # the output every log interval / upsample (read_flight_log)
    on_aliasing: str = setting(default="refuse")  # a vehicle line above the stream's Nyquist: refuse or record
    on_ground: str = setting(default="refuse")  # a window not wholly airborne: refuse or record
    on_bad_samples: str = setting(default="refuse")  # beyond full scale, spikes, corrupt messages: refuse or record
    blades: int = setting(default=2)  # per rotor, for blade-pass lines from logged rotor speeds
    description: str = setting(default="")

    def validate(self, where: str) -> None:
        low, high = self.band_hz
        require(0 < low < high, f"{where}.band_hz", f"needs 0 < low < high, got {list(self.band_hz)}")
        require(self.upsample >= 1, f"{where}.upsample", f"must be >= 1, got {self.upsample}")
        require(self.blades >= 1, f"{where}.blades", f"must be >= 1, got {self.blades}")
        for key in ("on_aliasing", "on_ground", "on_bad_samples"):
            value = getattr(self, key)
            require(value in POLICIES, f"{where}.{key}", f"one of {list(POLICIES)}, got {value!r}")
        if self.window_s is not None:
            ok = 0 <= self.window_s[0] < self.window_s[1]
            require(ok, f"{where}.window_s", f"needs 0 <= start < end, got {list(self.window_s)}")

    def reader_options(self) -> dict:
        """The keyword arguments of `read_flight_log` this entry sets."""
        keys = ("window_s", "imu_to_mount_m", "upsample", "on_aliasing", "on_ground", "on_bad_samples", "blades")
        return {"band_hz": self.band_hz} | {k: getattr(self, k) for k in keys}
