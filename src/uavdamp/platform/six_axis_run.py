"""A time-domain run of the six-axis isolator's linear model under a prescribed mount motion and a damping schedule.

The mount's translation and rotation are taken piecewise linear between their samples (first-order hold) and
their rates as the slopes on each step; each step with the semi-active elements' damping held (piecewise
constant) is then solved exactly by one matrix exponential (`uavdamp.platform.statespace.discretise`). The run
starts with the payload moving with the mount (q = u, q' = the first slope: no stroke). The outputs at a sample
take the mount's rate there as the slope of the step that starts there (the last sample: the step that ends there).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import xarray as xr

from uavdamp.platform.six_axis import AXES, SixAxisIsolator, output_names, state_space
from uavdamp.platform.statespace import Discrete, discretise, lift, propagate


def mount_grid(time, translation, rotation) -> tuple[np.ndarray, float, np.ndarray]:
    """(time s, step s, the mount's coordinates (n, 6)) of a run's time (s, uniform, any start) and translation and
    rotation ((3, n) m and rad each), checked."""
    t = np.asarray(time, dtype=float)
    if t.ndim != 1 or t.size < 2 or not np.all(np.isfinite(t)):
        raise ValueError(f"time: must be a 1-D finite array of at least 2 samples, got shape {t.shape}")
    h = float(t[1] - t[0])
    if not h > 0 or not np.allclose(np.diff(t), h, rtol=1e-9, atol=0):
        raise ValueError("time: must be uniformly spaced and increasing")
    u = np.vstack([np.asarray(translation, dtype=float), np.asarray(rotation, dtype=float)])
    if u.shape != (6, t.size) or not np.all(np.isfinite(u)):
        raise ValueError(f"translation, rotation: must be finite (3, {t.size}) arrays, got {u.shape[0]} rows")
    return t, h, u.T


def schedule_array(isolator: SixAxisIsolator, schedule, n: int) -> np.ndarray | None:
    """A damping schedule (n_semi,) or (n_semi, n) N s m-1 as (n, n_semi) (None: a callable, decided during the
    run), checked."""
    n_semi = len(isolator.semi_active)
    if callable(schedule):
        return None
    c = np.asarray(schedule, dtype=float)
    if c.shape not in ((n_semi,), (n_semi, n)):
        raise ValueError(f"damping schedule: must have shape ({n_semi},) or ({n_semi}, {n}), got {c.shape}")
    if not np.all(np.isfinite(c)) or c.min(initial=0.0) < 0:
        raise ValueError("damping schedule: values must be finite and >= 0 N s m-1")
    return np.broadcast_to(c[:, None] if c.ndim == 1 else c, (n_semi, n)).T.copy()


def run(
    isolator: SixAxisIsolator,
    time,
    translation,
    rotation,
    schedule: np.ndarray | Callable | None = None,
) -> xr.Dataset:
    """The payload's response to a mount motion: translation (3, n) m and rotation (3, n) rad on `time` (s,
    uniform), the semi-active elements' damping (N s m-1) from `schedule`: None (their own), an array (n_semi,)
    or (n_semi, n) of values acting from each sample on, or a callable (t_k, outputs_k) -> (n_semi,) called at
    every sample with the outputs (`uavdamp.platform.six_axis.output_names`) there. A scheduled C replaces the
    element's damping along its damper axes (`uavdamp.platform.six_axis.Element`)."""
    if callable(schedule):
        return run_batch(isolator, time, translation, rotation, lambda t_k, y: [schedule(t_k, y[0])], 1)[0]
    t, h, u = mount_grid(time, translation, rotation)
    n = t.size
    slopes = np.diff(u, axis=0) / h  # (n - 1, 6), the mount rate on each step
    rates = np.vstack([slopes, slopes[-1:]])  # at each sample: the step starting there (the last: ending there)
    own = schedule is None  # the semi-active elements keep their own damping (reported as NaN)
    plan = np.zeros((n, len(isolator.semi_active))) if own else schedule_array(isolator, schedule, n)
    z = np.zeros((n, 12))
    z[0, :6], z[0, 6:] = u[0], rates[0]
    steps: dict[tuple, Discrete] = {}  # the step map of each C the plan takes, built once
    # constant stretches of the plan: one step map and one lifted propagation each
    change = np.flatnonzero(np.any(np.diff(plan, axis=0) != 0, axis=1)) + 1
    bounds = [0, *change.tolist(), n - 1]
    for start, stop in zip(bounds[:-1], bounds[1:], strict=True):
        if stop > start:
            key = tuple(plan[start].tolist())
            if key not in steps:
                steps[key] = discretise(state_space(isolator, None if own else plan[start]), h)
            step = steps[key]
            lifted = lift(step.phi) if stop - start > 64 else None
            z[start : stop + 1] = propagate(step, z[start], u[start:stop], slopes[start:stop], lifted)
    return _dataset(isolator, t, u, rates, z, np.full_like(plan, np.nan) if own else plan)


def run_batch(isolator: SixAxisIsolator, time, translation, rotation, decide: Callable, n_runs: int) -> list:
    """`run`'s datasets of n_runs runs under one mount motion, each with its semi-active elements' C decided at every
    sample by one call for them all: decide(t_k, outputs (n_runs, n_out)) -> n_runs rows of (n_semi,) N s m-1
    (outputs as `run`'s callable sees them). Each run is stepped as `run` steps it alone."""
    t, h, u = mount_grid(time, translation, rotation)
    n, n_semi = t.size, len(isolator.semi_active)
    slopes = np.diff(u, axis=0) / h  # (n - 1, 6), the mount rate on each step
    rates = np.vstack([slopes, slopes[-1:]])  # at each sample: the step starting there (the last: ending there)
    outputs = state_space(isolator)  # the outputs do not depend on the damping
    driven = u @ outputs.du.T + rates @ outputs.dv.T  # the inputs' share of the outputs, every sample at once
    held = np.hstack([u[:-1], slopes])  # each step's (u, u')
    maps: dict[tuple, np.ndarray] = {}  # (12, 24) on (z, u, u') per C
    z = np.zeros((n_runs, n, 12))
    z[:, 0, :6], z[:, 0, 6:] = u[0], rates[0]
    applied = np.zeros((n_runs, n, n_semi))
    for k in range(n):
        y = np.stack([outputs.c @ z[b, k] + driven[k] for b in range(n_runs)])
        for b, c in enumerate(decide(float(t[k]), y)):
            applied[b, k] = c = np.asarray(c, dtype=float).ravel()
            if k < n - 1:
                key = tuple(c.tolist())
                if key not in maps:
                    step = discretise(state_space(isolator, c), h)
                    maps[key] = np.hstack([step.phi, step.gamma_u, step.gamma_v])
                z[b, k + 1] = maps[key] @ np.concatenate([z[b, k], held[k]])
    return [_dataset(isolator, t, u, rates, z[b], applied[b]) for b in range(n_runs)]


def _dataset(isolator: SixAxisIsolator, t, u, rates, z, applied) -> xr.Dataset:
    """`run_dataset` of a run's states z (n, 12) under the mount coordinates u and rates (n, 6)."""
    plant = state_space(isolator)  # the outputs do not depend on the damping
    y = z @ plant.c.T + u @ plant.du.T + rates @ plant.dv.T
    return run_dataset(isolator, t, u, y, applied, z[:, 6:])


def run_dataset(isolator: SixAxisIsolator, t, u, y, applied, body_rates) -> xr.Dataset:
    """The run's dataset: mount and payload motion, element strokes and rates, applied damping (N s m-1, NaN: the
    element's own) on `time`, from the mount coordinates u (n, 6), outputs y (`output_names`) and rates (n, 6)."""
    n_el = isolator.n_elements
    names = output_names(isolator)
    assert len(names) == y.shape[1]
    strokes = y[:, 6 : 6 + 3 * n_el].reshape(-1, n_el, 3).transpose(1, 2, 0)
    rates = y[:, 6 + 3 * n_el :].reshape(-1, n_el, 3).transpose(1, 2, 0)
    frame = "mount axes (x forward, y left, z up), from rest"
    variables = {
        "payload_translation": (
            ("axis", "time"),
            y[:, :3].T,
            "m",
            f"payload translation at its reference point, {frame}",
        ),
        "payload_rotation": (("axis", "time"), y[:, 3:6].T, "rad", f"payload small rotation, {frame}"),
        "payload_velocity": (("axis", "time"), body_rates[:, :3].T, "m s-1", "payload velocity at its reference point"),
        "payload_angular_rate": (("axis", "time"), body_rates[:, 3:].T, "rad s-1", "payload angular rate"),
        "mount_translation": (("axis", "time"), u[:, :3].T, "m", "prescribed mount translation"),
        "mount_rotation": (("axis", "time"), u[:, 3:].T, "rad", "prescribed mount small rotation"),
        "element_stroke": (("element", "axis", "time"), strokes, "m", "element stroke (payload relative to mount)"),
        "element_stroke_rate": (("element", "axis", "time"), rates, "m s-1", "element stroke rate"),
        "damping": (
            ("semi_active_element", "time"),
            applied.T,
            "N s m-1",
            "semi-active element damping applied from this time on (NaN: the element's own)",
        ),
    }
    return xr.Dataset(
        {
            name: (dims, values, {"units": unit, "long_name": text})
            for name, (dims, values, unit, text) in variables.items()
        },
        coords={
            "time": ("time", t, {"units": "s", "long_name": "time"}),
            "axis": ("axis", list(AXES), {"units": "1", "long_name": "mount axis"}),
            "element": ("element", np.arange(n_el), {"units": "1", "long_name": "isolator element"}),
            "semi_active_element": (
                "semi_active_element",
                np.array(isolator.semi_active, dtype=int),
                {"units": "1", "long_name": "isolator element with a semi-active damper"},
            ),
            "kind": ("element", [e.kind for e in isolator.elements], {"units": "1", "long_name": "element kind"}),
        },
        attrs={"title": "Six-axis isolator: payload response to a prescribed mount motion (exact linear model)"},
    )
