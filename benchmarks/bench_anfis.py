"""Fit time of the ANFIS estimator: 3 inputs x 2 MFs (8 rules, grid init) on 300 rows.

Run: PYTHONPATH=src python benchmarks/bench_anfis.py [--repeats 5]
Target (issue 5): under 0.05 s per 100 epochs.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from uavdamp.anfis import ANFIS

LO = np.array([5.0, 5.0, 10.0])  # f_y [Hz], f_z [Hz], K [N/m]
HI = np.array([30.0, 30.0, 1000.0])


def data(n_rows: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Inputs uniform in the box LO..HI and a smooth positive output (as in tests/test_anfis.py)."""
    X = LO + (HI - LO) * np.random.default_rng(seed).random((n_rows, 3))
    return X, 2 + np.sin(X[:, 0] / 5) + 0.5 * (X[:, 1] / 20) ** 2 + np.exp(-X[:, 2] / 500)


def fit_seconds(X: np.ndarray, y: np.ndarray, repeats: int, **params) -> float:
    """Median wall time of `repeats` fits (after one warm-up fit)."""
    ANFIS(**{**params, "epochs": 5}).fit(X, y)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        ANFIS(**params).fit(X, y)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="fits per configuration (median reported)")
    parser.add_argument("--rows", type=int, default=300, help="training rows")
    args = parser.parse_args()
    X, y = data(args.rows)
    cases = [
        ("grid 3x2 (8 rules)", dict(n_mfs=2), 100),
        ("grid 3x2 (8 rules)", dict(n_mfs=2), 500),
        ("fcm, 2 rules", dict(init="fcm", n_rules=2), 100),
        ("fcm, 2 rules", dict(init="fcm", n_rules=2), 500),
        ("grid 3x3 (27 rules)", dict(n_mfs=3), 100),
    ]
    print(f"ANFIS fit time, {args.rows} rows x 3 inputs, median of {args.repeats}")
    print(f"{'model':<22}{'epochs':>8}{'fit [s]':>10}{'s / 100 epochs':>16}")
    for label, params, epochs in cases:
        seconds = fit_seconds(X, y, args.repeats, epochs=epochs, **params)
        print(f"{label:<22}{epochs:>8}{seconds:>10.4f}{100 * seconds / epochs:>16.4f}")


if __name__ == "__main__":
    main()
