"""uavdamp: semi-active vibration isolation of a UAV camera platform (after Marichal et al. 2014)."""

__version__ = "0.1.0"
