"""numba on first use: a module's kernels are plain functions until a caller first needs them, then compiled with
``numba.njit(cache=True)`` in place (machine code kept beside the source, so a later process loads it). A process
that never steps a kernel (most of the workflow's jobs) neither imports numba (0.17 s) nor loads its cache."""

from __future__ import annotations


def jit(namespace: dict, names: tuple[str, ...]) -> None:
    """Replace each function `names` of a module's `namespace` (its ``globals()``) by its numba compilation, callees
    before their callers (a compiled function finds the others by their global names); once per process."""
    if namespace.get("_numba_compiled"):
        return
    from numba import njit

    for name in names:
        namespace[name] = njit(cache=True)(namespace[name])
    namespace["_numba_compiled"] = True
