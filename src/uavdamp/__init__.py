"""uavdamp: semi-active vibration isolation of a UAV camera platform (after Marichal et al. 2014)."""

__version__ = "0.1.0"


def __getattr__(name: str):
    """Lazy `uavdamp.read_flight_log` (its readers import pyulog and pymavlink; `import uavdamp` stays cheap)."""
    if name == "read_flight_log":
        from uavdamp.sources.flight_log import read_flight_log

        return read_flight_log
    raise AttributeError(f"module 'uavdamp' has no attribute {name!r}")
