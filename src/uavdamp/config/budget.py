"""What a config will cost before anything runs: grid points, simulated seconds and an estimate of CPU time.

The constants are measured on the 2-core development machine (config `budget`, with their source in the config
comments) and are estimates, not guarantees: they scale the counts, they do not model a machine. A flight run's
seconds (trim, release, record) count FLIGHT_COST vacuum seconds each in the helicopter's simulated seconds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uavdamp.benchmark.scenarios import scenario_specs, split
from uavdamp.benchmark.tuning import TUNED
from uavdamp.settings import ConfigError, require, setting


@dataclass(frozen=True)
class Budget:
    """The config section ``budget``."""

    max_cpu_hours: float = setting()  # h: an estimate above this refuses the run
    seconds_per_point_linear: float = setting("seconds_per_point_linear_s")  # s of CPU per grid point
    seconds_per_point_exudyn: float = setting("seconds_per_point_exudyn_s")  # s of CPU per 5 s grid point
    helicopter_cpu_per_simulated_s: float = setting()  # s of CPU per simulated s of the rotorcraft
    platform_cpu_per_simulated_s: float = setting()  # s of CPU per simulated s of the Exudyn platform

    def validate(self) -> None:
        for name in ("max_cpu_hours", "helicopter_cpu_per_simulated_s", "platform_cpu_per_simulated_s"):
            require(getattr(self, name) > 0, f"budget.{name}", f"must be > 0, got {getattr(self, name)}")


FLIGHT_COST = 5.0  # 1, flight run CPU per simulated s over a vacuum run's (bench_helicopter.py --flight: 4.8-5.8)


def flight_seconds(heli, duration: float) -> float:
    """Vacuum-equivalent simulated seconds of one flight run of `duration` s: its trim (settle, 6 Jacobian phases
    and up to max_iterations Newton phases, each step_settle plus two revolutions), release and record, at
    FLIGHT_COST."""
    trim = heli.flight.trim
    revolutions = 2 * 2 * 3.141592653589793 / heli.main_rotor.omega_rad_s
    phases = 6 + trim.max_iterations
    return FLIGHT_COST * (trim.settle + phases * (trim.step_settle + revolutions) + heli.flight.release + duration)


# a run with the Spencer MR damper over another damper's, 1 (the default benchmark, 2026-12-05: 145 against 86 s)
MR_COST = 1.7


def benchmark_runs(config) -> dict[str, int]:
    """Platform runs of the benchmark target: every scenario x controller x damper x stiffness (those with the MR
    damper apart: MR_COST each), and the tuning's at most (rigid, then per tuning criterion every tuned parameter of
    a configured controller: n_candidates + max_refine values, hybrid's per hybrid_alpha) per tuning scenario and K."""

    bench = config.benchmark
    names = sorted(scenario_specs(bench))
    tuning = sum(role == "tuning" for role in split(names, bench.split.tuning_fraction, bench.split.seed).values())
    per_damper = len(names) * len(bench.controllers) * len(bench.stiffness)
    t = bench.tuning
    searches = sum(
        len(t.hybrid_alpha) if key == "hybrid_gain" else 1
        for key, (controller, _, _) in TUNED.items()
        if controller in bench.controllers
    )
    per_k = 1 + len(t.criteria) * searches * (t.n_candidates + t.max_refine)
    return {
        "runs": per_damper * sum(d != "mr" for d in bench.dampers),
        "mr_runs": per_damper * ("mr" in bench.dampers),
        "tuning_runs": tuning * len(bench.stiffness) * per_k,
    }


def estimate(config, benchmark: bool = False) -> dict[str, float]:
    """Counts and estimated CPU seconds of the heavy stages of a typed `uavdamp.config.load.Config` (with `benchmark`,
    of the benchmark target's runs too: `benchmark_runs`)."""
    b, heli, study, grid = config.budget, config.helicopter, config.study, config.reference_table
    flight = heli.aerodynamics.enabled
    runs_s = 3 * heli.solver.duration + (2 * flight_seconds(heli, heli.solver.duration) if flight else 0.0)
    n_sensitivity = 1 + sum(len(v) for v in heli.sensitivity.parameters.values())
    duration = heli.sensitivity.duration
    each = duration if heli.sensitivity.flight == "vacuum" else flight_seconds(heli, duration)
    heli_s = runs_s + n_sensitivity * each
    per_point = b.seconds_per_point_linear if config.platform.backend == "linear" else b.seconds_per_point_exudyn
    grid_points = int(np.prod([axis.array().size for axis in (grid.freq_y, grid.freq_z, grid.stiffness, grid.damping)]))
    # study: per case and K, every strategy and the best-constant search (its candidates, up to 20 refinements);
    # an upper bound: the isolated runs on the linear plant cost less than this Exudyn rate
    study_runs = len(study.cases) * len(study.stiffness) * (len(study.strategies) + study.optimal_candidates + 20)
    cpu = {
        "grid": grid_points * per_point,
        "verification": grid.verify.n_points * b.seconds_per_point_exudyn * grid.duration / 5.0,
        "helicopter": heli_s * b.helicopter_cpu_per_simulated_s,
        "study": study_runs * study.duration_s * b.platform_cpu_per_simulated_s,
    }
    runs = benchmark_runs(config) if benchmark else {"runs": 0, "mr_runs": 0, "tuning_runs": 0}
    weighted = runs["runs"] + MR_COST * runs["mr_runs"] + runs["tuning_runs"]
    cpu["benchmark"] = weighted * config.benchmark.duration_s * b.platform_cpu_per_simulated_s
    return {
        "benchmark_runs": runs["runs"] + runs["mr_runs"] + runs["tuning_runs"],
        "grid_points": grid_points,
        "helicopter_simulated_s": heli_s,
        "study_runs": study_runs,
        **{f"cpu_s_{k}": v for k, v in cpu.items()},
        "cpu_s": sum(cpu.values()),
        "max_cpu_s": 3600.0 * b.max_cpu_hours,
    }


def check(config, benchmark: bool = False) -> dict[str, float]:
    """The estimate (`benchmark`: with the benchmark target's runs); ConfigError naming budget.max_cpu_hours and the
    numbers when it is above the budget."""
    e = estimate(config, benchmark)
    if e["cpu_s"] > e["max_cpu_s"]:
        raise ConfigError(
            f"budget.max_cpu_hours: the run is estimated at {e['cpu_s'] / 3600:.3g} CPU hours "
            f"(grid {e['grid_points']:,} points: {e['cpu_s_grid'] / 3600:.3g} h; helicopter "
            f"{e['helicopter_simulated_s']:g} simulated s: {e['cpu_s_helicopter'] / 3600:.3g} h; study "
            f"{e['study_runs']} runs: {e['cpu_s_study'] / 3600:.3g} h; benchmark {e['benchmark_runs']} runs: "
            f"{e['cpu_s_benchmark'] / 3600:.3g} h), above the budget of "
            f"{e['max_cpu_s'] / 3600:g} h. To run it anyway, raise budget.max_cpu_hours in a config file "
            "passed with --configfile"
        )
    return e


def summary(e: dict[str, float]) -> str:
    return (
        f"uavdamp plan: {e['grid_points']:,} grid points, {e['helicopter_simulated_s']:g} simulated s of "
        f"helicopter, {e['study_runs']} study runs"
        + (f", {e['benchmark_runs']} benchmark runs" if e["benchmark_runs"] else "")
        + f": about {e['cpu_s'] / 60:.3g} CPU min "
        f"(budget {e['max_cpu_s'] / 3600:g} h)"
    )
