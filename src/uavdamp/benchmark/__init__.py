"""The controller benchmark: scenarios (`scenarios`), the runner of a law under a damper on its plants and the
per-criterion tuning (`tuning`), the scores (`scoring`) and the loop over scenarios x laws x stiffness (`loop`)."""

from uavdamp.benchmark.loop import BenchmarkOptions, gather, run_scenario

__all__ = ["BenchmarkOptions", "gather", "run_scenario"]
