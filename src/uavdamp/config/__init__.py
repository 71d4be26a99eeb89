"""The config layer: the sections as typed options (`load`), the cross-key checks before any job (`checks`), the
compute budget (`budget`), the config files read strictly (`files`) and the key reference generated from the
schema (`docs`)."""

from uavdamp.config.load import Config, benchmark_options, load, study_options

__all__ = ["Config", "benchmark_options", "load", "study_options"]
