"""The wire-rope isolator's step, compiled with numba: the scheme of `uavdamp.platform.wire_rope` (module docstring:
the payload's exact step map for the held mount and e, z advanced in the stroke by Heun's rule, a fixed-point pass
for the coupling) for every run of a batch, over many steps in one call.

`wire_rope._steps` calls `advance` over the whole run when every run's step map is held (`wire_rope.integrate`) and
one step at a time when a schedule decides C at every sample (`wire_rope.integrate_scheduled`);
`tests/test_wire_rope_kernel.py` checks it against the scheme written out with numpy arrays (the loop it replaced).
Compiled once per machine (``cache=True``: numba keeps the machine code beside this file).
"""

from __future__ import annotations

import numpy as np

from uavdamp import compiled

COMPILED = ("_sign", "_phi", "_one_step", "advance")  # numba on first use (`uavdamp.compiled`), callees first


def _sign(value):
    return 1.0 if value > 0 else (-1.0 if value < 0 else 0.0)


def _phi(z, direction, shape):
    """dz/ds (1) at the hysteretic displacement z (m) for a stroke moving in `direction` (+1, -1, 0); shape: (beta
    m^-n, gamma m^-n, n) (`WireRope.phi`)."""
    magnitude = abs(z) if shape[2] == 1.0 else abs(z) ** shape[2]
    return 1.0 - (shape[0] * direction * _sign(z) + shape[1]) * magnitude


def _one_step(c, k, maps, ge1, p, h_rows, u, slopes, mount_strokes, w, z, s_k, de, shape, iterations, work):
    """Run c's step from sample k to k + 1 in place (w, z at k + 1; its stroke s_k and e's increment de)."""
    n_h = z.shape[2]
    inputs, base, d0, ds, dz = work
    for i in range(12):
        inputs[i] = w[c, k, i]
    for i in range(n_h):
        inputs[12 + i] = s_k[c, i] - z[c, k, i]
    for i in range(6):
        inputs[12 + n_h + i] = u[c, k, i]
        inputs[18 + n_h + i] = slopes[c, k, i]
    for r in range(12):
        total = 0.0
        for j in range(inputs.size):
            total += maps[c, r, j] * inputs[j]
        base[r] = total
    for i in range(n_h):
        total = 0.0
        for j in range(6):
            total += base[j] * h_rows[i, j]
        d0[i] = total - mount_strokes[c, k + 1, i] - s_k[c, i]
    for _ in range(iterations):
        for i in range(n_h):  # every stroke from the previous pass's increments
            total = d0[i]
            for j in range(n_h):
                total += p[c, i, j] * de[c, j]
            ds[i] = total
        for i in range(n_h):
            direction, zk = _sign(ds[i]), z[c, k, i]
            slope0 = _phi(zk, direction, shape)
            dz[i] = 0.5 * ds[i] * (slope0 + _phi(zk + ds[i] * slope0, direction, shape))
            de[c, i] = ds[i] - dz[i]
    for r in range(12):
        total = base[r]
        for j in range(n_h):
            total += ge1[c, r, j] * de[c, j]
        w[c, k + 1, r] = total
    for i in range(n_h):
        z[c, k + 1, i] = z[c, k, i] + dz[i]
        s_k[c, i] += ds[i]


def advance(maps, ge1, p, h_rows, u, slopes, mount_strokes, w, z, s_k, de, shape, iterations, work, k0, k1):
    """Every run c of the batch from sample k0 to k1 at its held step map (maps (B, 12, 24 + n_h), ge1 (B, 12,
    n_h), p (B, n_h, n_h): `wire_rope._Bank.take`), in place: states w (B, n, 12), z (B, n, n_h) m, the strokes at
    the step's start s_k (B, n_h) m and e's last increment de (B, n_h) m; u (B, n, 6) the mount's coordinates, slopes
    (B, n - 1, 6) their slopes, mount_strokes (B, n, n_h) m their hysteretic strokes H u; h_rows (n_h, 6);
    shape as `_phi`'s; `iterations` fixed-point passes a step; work: `workspace`'s arrays."""
    for c in range(w.shape[0]):
        for k in range(k0, k1):
            _one_step(c, k, maps, ge1, p, h_rows, u, slopes, mount_strokes, w, z, s_k, de, shape, iterations, work)


def workspace(n_h: int) -> tuple[np.ndarray, ...]:
    """The scratch arrays of a step (one set per batch, reused by every call of `advance`)."""
    return np.empty(24 + n_h), np.empty(12), np.empty(n_h), np.empty(n_h), np.empty(n_h)


def compile_now() -> None:
    """Compile the kernels (once per process; `uavdamp.compiled`)."""
    compiled.jit(globals(), COMPILED)
