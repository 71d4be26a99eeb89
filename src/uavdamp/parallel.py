"""Independent tasks fanned out over joblib's loky workers, the results in the tasks' order: one BLAS/OpenMP thread
per worker, and in-process with one BLAS thread when ``n_jobs`` is 1, so the numbers do not depend on the thread
count (the ANFIS's cross-validation fits, the payload comparison's inputs).
"""

from __future__ import annotations

import numpy as np
from joblib import Parallel, delayed, parallel_config
from joblib.externals.loky import get_reusable_executor
from threadpoolctl import threadpool_limits


def run(tasks: list, n_jobs: int, costs=None) -> list:
    """[function(*args) for (function, args) in tasks], in order, on n_jobs loky workers (one thread each).

    ``costs`` (one per task, any unit) only orders the work, costliest first (so the longest tasks do not end the
    run on one worker): the results come back in the tasks' order whatever the order of work or n_jobs.
    """
    order = np.argsort(-np.asarray(costs, float), kind="stable") if costs is not None else np.arange(len(tasks))
    if n_jobs == 1 or len(tasks) <= 1:
        with threadpool_limits(limits=1):
            done = [tasks[k][0](*tasks[k][1]) for k in order]
    else:
        with parallel_config(backend="loky", inner_max_num_threads=1):
            done = Parallel(n_jobs=n_jobs)(delayed(tasks[k][0])(*tasks[k][1]) for k in order)
        get_reusable_executor().shutdown(wait=True)  # no workers left behind by the job
    out = [None] * len(tasks)
    for k, result in zip(order, done, strict=True):
        out[k] = result
    return out
