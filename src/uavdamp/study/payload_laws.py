"""Semi-active laws on the gimbal's six-axis isolator: the payload comparison's C(t) beside its constant C.

Karnopp's on-off skyhook (`uavdamp.damping.laws.Skyhook`, the law the study runs on the paper's platform) decides
each semi-active element's damping from that element's own velocities: v_rel its stroke rate (payload minus
mount at the element, 3 axes) and v_abs = v_rel + the mount's velocity there, c_on when the damper's force
-C v_rel opposes v_abs (v_abs . v_rel > 0), else c_off; decided at every sample of the run's grid, held over the
step (`uavdamp.platform.six_axis_run.run`, exact for the held C), through a damper that follows the demand at once
(``payload.skyhook_lag_s`` 0, the default) or with a first-order lag. The body's motion then feeds the gimbal as in the
constant runs (`uavdamp.study.payload_runs`): coordinates and rates from the run's states, accelerations their
central differences.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from uavdamp.camera.criteria import window_mask
from uavdamp.contract import MountMotion
from uavdamp.damping.laws import Skyhook
from uavdamp.platform.six_axis import DOFS, SixAxisIsolator, strokes_matrix
from uavdamp.platform.six_axis_run import run
from uavdamp.study.payload_runs import BodyMotion, gimbal_series, metric_attrs, run_metrics, six_axis_isolator
from uavdamp.study.payload_schedule import schedule, scheduled_run


def skyhook_schedule(
    isolator: SixAxisIsolator, time: np.ndarray, mount_rates: np.ndarray, law: Skyhook, lag_s: float = 0.0
) -> Callable:
    """The callable schedule (t_k, outputs_k) -> C per semi-active element (N s m-1) of `six_axis_run.run`:
    `law.decide(v_abs, v_rel)` per element, mount_rates (n, 6) the mount's rates at the samples as the run takes
    them (the slope of the step that starts there). lag_s > 0: the damper's C follows the demand d_k (held over
    the step from t_k) with a first-order lag of that time constant, C(t_k+1) = d_k + (C(t_k) - d_k) e, e =
    exp(-h / lag_s), exactly; the run holds each step's mean, d_k + (C(t_k) - d_k) (1 - e) lag_s / h (choice: the
    step's damping impulse), which is d_k for lag_s 0. The damper starts settled on the first demand."""
    n_el, t0, h = isolator.n_elements, float(time[0]), float(time[1] - time[0])
    at_elements = strokes_matrix(isolator)  # (3 n_el, 6): a 6-DOF motion's translation at each element
    decay = math.exp(-h / lag_s) if lag_s > 0 else 0.0
    mean_share = (1.0 - decay) * lag_s / h if lag_s > 0 else 0.0  # of the start's distance to the demand
    state: dict[str, np.ndarray] = {}

    def decide(t_k: float, outputs: np.ndarray) -> np.ndarray:
        k = int(round((t_k - t0) / h))
        v_rel = outputs[6 + 3 * n_el :].reshape(n_el, 3)
        v_abs = v_rel + (at_elements @ mount_rates[k]).reshape(n_el, 3)
        demand = np.array([law.decide(v_abs[i], v_rel[i]) for i in isolator.semi_active])
        start = state.get("c", demand)  # C(t_k); the first sample: settled on its demand
        state["c"] = demand + (start - demand) * decay
        return demand + (start - demand) * mean_share

    return decide


def skyhook_motion(
    isolator: SixAxisIsolator, time: np.ndarray, mount: MountMotion, c_on: float, c_off: float, lag_s: float = 0.0
) -> tuple[BodyMotion, float]:
    """(the payload's motion under on-off skyhook between c_on and c_off N s m-1 through a damper of lag lag_s s
    (`skyhook_schedule`), the share of element-steps whose applied C is nearer c_on than c_off)."""
    h = float(time[1] - time[0])
    u = np.vstack([np.asarray(mount.translation, dtype=float), np.asarray(mount.rotation, dtype=float)])
    slopes = np.diff(u, axis=1) / h
    rates = np.hstack([slopes, slopes[:, -1:]]).T  # (n, 6), as `run` takes them
    law = Skyhook(c_on, c_off, h)
    ds = run(isolator, time, u[:3], u[3:], skyhook_schedule(isolator, time, rates, law, lag_s))
    on = float(np.mean(ds.damping.values[:, :-1] > 0.5 * (c_on + c_off))) if c_on != c_off else 1.0
    return body_motion(ds, h), on


def body_motion(ds, h: float) -> BodyMotion:
    """The payload's `BodyMotion` from a `six_axis_run.run` dataset on a grid of step h s: its coordinates and
    rates, the accelerations their central differences, the peak |element stroke|."""
    coordinates = np.vstack([ds.payload_translation.values, ds.payload_rotation.values])
    body_rates = np.vstack([ds.payload_velocity.values, ds.payload_angular_rate.values])
    accelerations = np.gradient(body_rates, h, axis=1, edge_order=2)
    return BodyMotion(coordinates, body_rates, accelerations, float(np.abs(ds.element_stroke.values).max()))


def law_c_on(section) -> list[float]:
    """The skyhook runs' c_on, N s m-1: every damping candidate above c_off (`PayloadSection.c_off`, a choice):
    the choice of c_on swept over the candidates; [] when the section compares no gimbal on a six-axis isolator."""
    if "gimbal" not in section.payloads or "six_axis" not in section.mounts:
        return []
    return [float(c) for c in sorted(section.damping) if c > section.c_off]


def law_names(section) -> list[str]:
    """The law runs' names, skyhook_C for each C of `law_c_on`."""
    return [f"skyhook_{c:g}" for c in law_c_on(section)]


def law_values(setup, t: np.ndarray, moved: MountMotion) -> dict[str, np.ndarray]:
    """Per law, the gimbal on the six-axis isolator under the gridded input: every metric of
    `payload_runs.METRICS`, ``on_fraction``, ``c_on`` and ``damping_mean`` (N s m-1; NaN where a law has none),
    each (law,), and ``name``: the skyhook runs of `law_names`, then ``scheduled`` (`uavdamp.study.
    payload_schedule`) when the setup has a payload table, its decisions as ``schedule`` (a `Schedule`); {}
    without laws. `setup`: the payload comparison's."""
    s = setup.section
    c_off, bodies, rows = s.c_off, [], []
    for c_on in law_c_on(s):
        body, on = skyhook_motion(six_axis_isolator(s, c_off), t, moved, c_on, c_off, s.skyhook_lag)
        bodies.append(body)
        rows.append({"on_fraction": on, "c_on": c_on, "damping_mean": math.nan, "name": f"skyhook_{c_on:g}"})
    plan = None
    if law_c_on(s) and setup.table is not None:
        plan = schedule(t, moved, setup.table, s.schedule)
        bodies.append(body_motion(scheduled_run(six_axis_isolator(s, c_off), t, moved, plan.per_sample), t[1] - t[0]))
        mean = float(np.mean(plan.per_sample[window_mask(t, s.settle_s, s.duration_s)]))
        rows.append({"on_fraction": math.nan, "c_on": math.nan, "damping_mean": mean, "name": "scheduled"})
    if bodies:  # the gimbal on every law's body, side by side
        errors = s.gimbal.sensor_errors
        found = gimbal_series(setup.gimbal, setup.gains, t, bodies, setup.lever, sensor_errors=errors, seed=s.seed)
        rows = [
            run_metrics(t, series, setup.camera, s.settle_s, s.duration_s) | row
            for series, row in zip(found, rows, strict=True)
        ]
    out = {k: np.array([r[k] for r in rows]) for k in rows[0]} if rows else {}
    return out | ({"schedule": plan} if plan is not None else {})


def law_variables(values: dict[str, np.ndarray], section) -> tuple[dict, dict]:
    """(data variables law_NAME (law), the law coordinate) of `law_values`' output for a dataset."""
    if not values:
        return {}, {}
    extra = ("on_fraction", "c_on", "damping_mean", "name", "schedule")
    data = {f"law_{k}": (("law",), v, metric_attrs(k)) for k, v in values.items() if k not in extra}
    data["law_on_fraction"] = (
        ("law",),
        values["on_fraction"],
        {"units": "1", "long_name": "share of element-steps at c_on (skyhook)"},
    )
    data["law_c_on"] = (("law",), values["c_on"], {"units": "N s m-1", "long_name": "skyhook's on damping"})
    data["law_damping_mean"] = (
        ("law",),
        values["damping_mean"],
        {"units": "N s m-1", "long_name": "scheduled law's mean damping over the settled window"},
    )
    lag = f", damper lag {section.skyhook_lag:g} s" if section.skyhook_lag > 0 else ", ideal damper"
    text = (
        "semi-active law on the six-axis isolator's elements, the gimbal on it: on-off skyhook between c_on and "
        f"c_off {section.c_off:g} N s m-1{lag}; scheduled: C from the tracked lines through the payload table"
    )
    coords = {"law": ("law", [str(n) for n in values["name"]], {"units": "1", "long_name": text})}
    if "schedule" in values:
        plan = values["schedule"]
        coords["update_time"] = ("update_time", plan.times, {"units": "s", "long_name": "scheduled law's update time"})
        coords["dof"] = ("dof", list(DOFS), {"units": "1", "long_name": "mount DOF (x, y, z; rotations about them)"})
        data["scheduled_damping"] = (
            ("update_time",),
            plan.damping,
            {"units": "N s m-1", "long_name": "scheduled law's C from this update on (every element)"},
        )
        data["scheduled_line_freq"] = (
            ("update_time", "dof"),
            plan.lines[:, :, 0],
            {"units": "Hz", "long_name": "dominant line of the mount's DOF the law tracked (NaN: none yet)"},
        )
        data["scheduled_line_amplitude"] = (
            ("update_time", "dof"),
            plan.lines[:, :, 1],
            {"units": "1", "long_name": "its amplitude: m (x, y, z), rad (rotations)"},
        )
    return data, coords
