"""The force-coupled linear plant's exact step, compiled with numba: `uavdamp.platform.force_coupling`'s steps for a
damper whose step mean force is linear in the stroke (the viscous and the lagged damper: `rate_gain`), over the steps
a law's demand is held.

Per step n (module docstring of `force_coupling`): the free state and its stroke and rate at the step's end,
free = free_map z_n + free_drive_n (ns + 4); the step's mean damper force F solving (I + k G) F = k (x_free - x_n),
G the stroke's response to a unit force held over the step (Cramer's rule on the 2 x 2 system); then
(z_{n+1}, end_{n+1}) = free - force_rows F. The products are written out as sums (the order differs from BLAS's, so
the last bits of a run can differ from the same steps in numpy; tests/test_force_coupling.py compares both).

One call steps the whole held interval: a law decided every 0.5 s on a 2 ms step is 250 steps in one call, where
the loop in Python cost 6-12 us a step, the compiled one about 1.6 us (measured 2026-12-07, the machine noisy:
`benchmarks/bench_coupling.py`).
"""

from __future__ import annotations

import numpy as np

from uavdamp import compiled

COMPILED = ("_linear_steps",)  # numba on first use (`uavdamp.compiled`)


def linear_steps(z, end, free_map, free_drive, force_rows, gains, start: int, force) -> None:
    """Step the plant from grid point `start` over gains.size steps, in place: z (steps + 1, ns) the states (z[start]
    given), end (4,) the stroke (y, z) m and its rate m s-1 at z[start] on entry and at the last step's end on return,
    force (steps + 1, 2) N each step's mean damper force. free_map (ns + 4, ns), free_drive (steps, ns + 4),
    force_rows (ns + 4, 2): `force_coupling.run`'s; gains (m,) N m-1: each step's k (the damper's `rate_gain`)."""
    compiled.jit(globals(), COMPILED)
    _linear_steps(z, end, free_map, free_drive, force_rows, np.ascontiguousarray(gains, dtype=float), int(start), force)


def _linear_steps(z, end, free_map, free_drive, force_rows, gains, start, force):
    ns, rows = z.shape[1], free_map.shape[0]
    g00, g01, g10, g11 = force_rows[ns, 0], force_rows[ns, 1], force_rows[ns + 1, 0], force_rows[ns + 1, 1]
    free = np.empty(rows)
    for j in range(gains.size):
        n = start + j
        for r in range(rows):
            total = free_drive[n, r]
            for c in range(ns):
                total += free_map[r, c] * z[n, c]
            free[r] = total
        k = gains[j]
        r0, r1 = k * (free[ns] - end[0]), k * (free[ns + 1] - end[1])
        a00, a01, a10, a11 = 1.0 + k * g00, k * g01, k * g10, 1.0 + k * g11
        det = a00 * a11 - a01 * a10
        f0, f1 = (a11 * r0 - a01 * r1) / det, (a00 * r1 - a10 * r0) / det
        force[n, 0], force[n, 1] = f0, f1
        for r in range(ns):
            z[n + 1, r] = free[r] - (force_rows[r, 0] * f0 + force_rows[r, 1] * f1)
        for r in range(4):
            end[r] = free[ns + r] - (force_rows[ns + r, 0] * f0 + force_rows[ns + r, 1] * f1)
