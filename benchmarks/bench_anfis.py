"""Fit time of the ANFIS: 8, 27 and 64 grid rules on 1000 and 10000 rows, default BLAS threads vs one thread.

Columns: "default threads" is ``ANFIS.fit`` as shipped, called with the process's default BLAS
threads; "one thread" is the same fit called inside ``threadpoolctl.threadpool_limits(1)``;
"no internal limit" is the default-threads fit with fit's own one-thread limit lifted
(``uavdamp.anfis.threadpool_limits`` replaced by a no-op), i.e. a fit without its own thread limit.

Run: PYTHONPATH=src python benchmarks/bench_anfis.py [--repeats 3] [--epochs 50]
Target: default threads never slower than one thread (ratio <= 1 up to timing noise).
"""

from __future__ import annotations

import argparse
import contextlib
import statistics
import time
from unittest import mock

import numpy as np
from threadpoolctl import threadpool_info, threadpool_limits

from uavdamp.anfis import estimator as anfis
from uavdamp.anfis.estimator import ANFIS

LO = np.array([5.0, 5.0, 10.0])  # f_y [Hz], f_z [Hz], K [N/m]
HI = np.array([30.0, 30.0, 1000.0])


def data(n_rows: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Inputs uniform in the box LO..HI and a smooth positive output (as in tests/test_anfis.py)."""
    X = LO + (HI - LO) * np.random.default_rng(seed).random((n_rows, 3))
    return X, 2 + np.sin(X[:, 0] / 5) + 0.5 * (X[:, 1] / 20) ** 2 + np.exp(-X[:, 2] / 500)


def fit_seconds(X: np.ndarray, y: np.ndarray, repeats: int, **params) -> float:
    """Median wall time of `repeats` fits (after one warm-up fit)."""
    ANFIS(**{**params, "epochs": 2}).fit(X, y)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        ANFIS(**params).fit(X, y)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="fits per configuration (median reported)")
    parser.add_argument("--epochs", type=int, default=50, help="epochs per fit")
    args = parser.parse_args()
    pools = ", ".join(f"{p['internal_api']} x{p['num_threads']}" for p in threadpool_info())
    print(f"ANFIS fit time, 3 inputs, grid init, {args.epochs} epochs, median of {args.repeats}; BLAS pools: {pools}")
    print(
        f"{'rules':>6}{'rows':>7}{'default threads [s]':>21}{'one thread [s]':>16}{'ratio':>7}"
        f"{'no internal limit [s]':>23}"
    )
    no_limit = mock.patch.object(anfis, "threadpool_limits", lambda **_: contextlib.nullcontext())
    for n_rows in (1000, 10000):
        X, y = data(n_rows)
        for n_mfs in (2, 3, 4):
            params = dict(n_mfs=n_mfs, epochs=args.epochs)
            default = fit_seconds(X, y, args.repeats, **params)
            with threadpool_limits(limits=1, user_api="blas"):
                one = fit_seconds(X, y, args.repeats, **params)
            with no_limit:
                unlimited = fit_seconds(X, y, args.repeats, **params)
            print(f"{n_mfs**3:>6}{n_rows:>7}{default:>21.3f}{one:>16.3f}{default / one:>7.2f}{unlimited:>23.3f}")


if __name__ == "__main__":
    main()
