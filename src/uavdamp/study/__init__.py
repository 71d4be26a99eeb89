"""The closed-loop study: every case x stiffness x damping strategy (`comparison`), the strategies it compares
(`strategies`) and the metrics it applies to each run (`metrics`)."""

from uavdamp.study.comparison import StudyOptions, StudySection, run_study

__all__ = ["StudyOptions", "StudySection", "run_study"]
