"""Semi-active laws on the gimbal's six-axis isolators (``six_axis`` and ``wire_rope``, the mounts of
`payload_runs.SIX_AXIS_MOUNTS` the config names): the payload comparison's C(t) beside its constant C.

Karnopp's on-off skyhook (`uavdamp.damping.laws.Skyhook`, the law the study runs on the paper's platform) decides
each semi-active element's damping from that element's own velocities: v_rel its stroke rate (payload minus mount at
the element, 3 axes) and v_abs = v_rel + the mount's velocity there, c_on when the damper's force -C v_rel opposes
v_abs (v_abs . v_rel > 0), else c_off; decided at every sample of the run's grid, held over the step
(`uavdamp.platform.six_axis_run.run_batch`, every c_on of an input side by side; on the wire rope
`uavdamp.platform.wire_rope.integrate_scheduled`: exact for the held C), through a damper that follows the demand at
once (``payload.skyhook_lag_s`` 0, the default) or with a first-order lag. The body's motion then feeds the gimbal
as in the constant runs (`uavdamp.study.payload_runs`): coordinates and rates from the run's states, accelerations
their central differences. The scheduled law (`uavdamp.study.payload_schedule`) reads the mount alone: one plan of C
per input, run on each mount (on the wire rope the payload table is its small-amplitude limit's, the rubber-ball
isolator's: an assumption of the law, not of the run).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from uavdamp.camera.criteria import window_mask
from uavdamp.contract import MountMotion
from uavdamp.damping.dampers import V_MAX
from uavdamp.damping.laws import Skyhook
from uavdamp.platform.six_axis import DOFS, SixAxisIsolator, strokes_matrix
from uavdamp.platform.six_axis_run import run_batch
from uavdamp.study import payload_mr
from uavdamp.study.payload_runs import (
    METRICS,
    SIX_AXIS_MOUNTS,
    BodyMotion,
    gimbal_series,
    hysteretic_law_motions,
    isolator,
    metric_attrs,
    run_metrics,
)
from uavdamp.study.payload_schedule import replanned, schedule, scheduled_run


def _at_mount(isolator: SixAxisIsolator, mount_rates: np.ndarray) -> np.ndarray:
    """(n, n_semi, 3): the mount's velocity at each semi-active element, every sample (a 6-DOF motion's translation
    at the elements: `strokes_matrix`), m s-1."""
    semi = np.array(isolator.semi_active, dtype=int)
    return (np.asarray(mount_rates) @ strokes_matrix(isolator).T).reshape(-1, isolator.n_elements, 3)[:, semi]


def _lag(lag_s: float, h: float) -> Callable:
    """(demand, state dict) -> the C a damper of first-order lag lag_s (s) holds over a step h (s): see
    `skyhook_schedule`; the state keeps C at the step's start."""
    decay = math.exp(-h / lag_s) if lag_s > 0 else 0.0
    mean_share = (1.0 - decay) * lag_s / h if lag_s > 0 else 0.0  # of the start's distance to the demand

    def held(demand: np.ndarray, state: dict) -> np.ndarray:
        if lag_s == 0:
            return demand
        start = state.get("c", demand)  # C(t_k); the first sample: settled on its demand
        state["c"] = demand + (start - demand) * decay
        return demand + (start - demand) * mean_share

    return held


def skyhook_schedule(
    isolator: SixAxisIsolator, time: np.ndarray, mount_rates: np.ndarray, law: Skyhook, lag_s: float = 0.0
) -> Callable:
    """The callable schedule (t_k, outputs_k) -> C per semi-active element (N s m-1) of `six_axis_run.run` and
    `wire_rope.integrate_scheduled`: `law.decide_rows(v_abs, v_rel)` (`Skyhook.decide` of each element's own
    velocities), mount_rates (n, 6) the mount's rates at the samples as the run takes them (the slope of the step
    that starts there). lag_s > 0: the damper's C follows the demand d_k (held over
    the step from t_k) with a first-order lag of that time constant, C(t_k+1) = d_k + (C(t_k) - d_k) e, e =
    exp(-h / lag_s), exactly; the run holds each step's mean, d_k + (C(t_k) - d_k) (1 - e) lag_s / h (choice: the
    step's damping impulse), which is d_k for lag_s 0. The damper starts settled on the first demand."""
    n_el, t0, h = isolator.n_elements, float(time[0]), float(time[1] - time[0])
    semi, at_mount = np.array(isolator.semi_active, dtype=int), _at_mount(isolator, mount_rates)
    held, state = _lag(lag_s, h), {}

    def decide(t_k: float, outputs: np.ndarray) -> np.ndarray:
        v_rel = outputs[6 + 3 * n_el :].reshape(n_el, 3)[semi]
        return held(law.decide_rows(v_rel + at_mount[int(round((t_k - t0) / h))], v_rel), state)

    return decide


def skyhook_batch(
    isolator: SixAxisIsolator, time: np.ndarray, mount_rates: np.ndarray, laws: list[Skyhook], lag_s: float = 0.0
) -> Callable:
    """`skyhook_schedule` of several laws in one call (`six_axis_run.run_batch`'s decision): (t_k, outputs (B,
    n_out)) -> C (B, n_semi) N s m-1, run b under laws[b] (`Skyhook.decide_batch`), each through its own lagged
    damper."""
    n_el, t0, h = isolator.n_elements, float(time[0]), float(time[1] - time[0])
    semi, at_mount = np.array(isolator.semi_active, dtype=int), _at_mount(isolator, mount_rates)
    held, state = _lag(lag_s, h), {}

    def decide(t_k: float, outputs: np.ndarray) -> np.ndarray:
        v_rel = outputs[:, 6 + 3 * n_el :].reshape(len(laws), n_el, 3)[:, semi]
        return held(Skyhook.decide_batch(laws, v_rel + at_mount[int(round((t_k - t0) / h))], v_rel), state)

    return decide


def _mount_rates(time: np.ndarray, mount: MountMotion) -> np.ndarray:
    """The mount's rates (n, 6) at the samples as the runs take them: the slope of the step that starts there (the
    last sample: the step that ends there)."""
    u = np.vstack([np.asarray(mount.translation, dtype=float), np.asarray(mount.rotation, dtype=float)])
    slopes = np.diff(u, axis=1) / float(time[1] - time[0])
    return np.hstack([slopes, slopes[:, -1:]]).T


def _on_share(applied: np.ndarray, c_on: float, c_off: float) -> float:
    """The share of element-steps (the last sample's decision acts over no step) whose C is nearer c_on."""
    return float(np.mean(applied[:-1] > 0.5 * (c_on + c_off))) if c_on != c_off else 1.0


def skyhook_motions(
    isolator: SixAxisIsolator,
    time: np.ndarray,
    mount: MountMotion,
    c_ons: list[float],
    c_off: float,
    lag_s: float = 0.0,
) -> list[tuple[BodyMotion, float]]:
    """Per c_on: (the payload's motion under on-off skyhook between c_on and c_off N s m-1 through a damper of lag
    lag_s s, the share of element-steps whose applied C is nearer c_on than c_off); the runs side by side
    (`six_axis_run.run_batch`, `skyhook_batch`)."""
    h = float(time[1] - time[0])
    decide = skyhook_batch(isolator, time, _mount_rates(time, mount), [Skyhook(c, c_off, h) for c in c_ons], lag_s)
    runs = run_batch(isolator, time, mount.translation, mount.rotation, decide, len(c_ons))
    return [(body_motion(ds, h), _on_share(ds.damping.values.T, c, c_off)) for ds, c in zip(runs, c_ons, strict=True)]


def body_motion(ds, h: float) -> BodyMotion:
    """The payload's `BodyMotion` from a `six_axis_run.run` dataset on a grid of step h s: its coordinates and
    rates, the accelerations their central differences, the peak |element stroke|."""
    coordinates = np.vstack([ds.payload_translation.values, ds.payload_rotation.values])
    body_rates = np.vstack([ds.payload_velocity.values, ds.payload_angular_rate.values])
    accelerations = np.gradient(body_rates, h, axis=1, edge_order=2)
    return BodyMotion(coordinates, body_rates, accelerations, float(np.abs(ds.element_stroke.values).max()))


def law_mounts(section) -> list[str]:
    """The mounts the laws run on: those of `payload_runs.SIX_AXIS_MOUNTS` the section names, in its order ([]
    without the gimbal)."""
    return [m for m in section.mounts if m in SIX_AXIS_MOUNTS] if "gimbal" in section.payloads else []


def law_c_on(section) -> list[float]:
    """The skyhook runs' c_on, N s m-1: every damping candidate above c_off (`PayloadSection.c_off`, a choice):
    the choice of c_on swept over the candidates; [] when the section compares no gimbal on a six-axis mount."""
    if not law_mounts(section):
        return []
    return [float(c) for c in sorted(section.damping) if c > section.c_off]


def law_names(section) -> list[str]:
    """The law runs' names, skyhook_C for each C of `law_c_on`."""
    return [f"skyhook_{c:g}" for c in law_c_on(section)]


def _mount_laws(section, mount: str, t: np.ndarray, moved: MountMotion, planned: list) -> tuple[list, list[float]]:
    """(the payload's `BodyMotion` on `mount` under each skyhook run of `law_c_on`, then under each planned C
    per sample (n,) N s m-1 of `planned` (the scheduled law's, the ANFIS's); each run's share of element-steps at
    c_on, NaN for the planned)."""
    c_off, lag, h, c_ons = section.c_off, section.skyhook_lag, float(t[1] - t[0]), law_c_on(section)
    found = isolator(section, mount, c_off)
    if mount == "six_axis":
        pairs = skyhook_motions(found, t, moved, c_ons, c_off, lag) if c_ons else []
        bodies = [b for b, _ in pairs] + [body_motion(scheduled_run(found, t, moved, c), h) for c in planned]
        return bodies, [on for _, on in pairs] + [math.nan] * len(planned)
    rates = _mount_rates(t, moved)
    schedules: list = [skyhook_schedule(found, t, rates, Skyhook(c, c_off, h), lag) for c in c_ons]
    schedules += [np.broadcast_to(c, (len(found.semi_active), t.size)) for c in planned]
    bodies, applied = hysteretic_law_motions(section, c_off, schedules, t, moved)
    shares = [_on_share(applied[b], c, c_off) for b, c in enumerate(c_ons)]
    return bodies, shares + [math.nan] * len(planned)


def _mr_laws(section, t: np.ndarray, moved: MountMotion, per_sample) -> tuple[list, list[dict]]:
    """`payload_mr.mr_motions` with its skyhook on the voltage (2.25 V or 0 V by Karnopp's rule on the six-axis
    isolator's elements); ([], []) without ``payload.mr.enabled`` or the six_axis mount."""
    if not (section.mr.enabled and "six_axis" in law_mounts(section)):
        return [], []
    on_off = Skyhook(V_MAX, 0.0, float(t[1] - t[0]))
    skyhook = skyhook_schedule(isolator(section, "six_axis", section.c_off), t, _mount_rates(t, moved), on_off)
    return payload_mr.mr_motions(section, t, moved, skyhook, per_sample)


def law_values(setup, t: np.ndarray, moved: MountMotion) -> dict[str, np.ndarray]:
    """Per mount of the section and law, the gimbal on that mount under the gridded input: every metric of
    `payload_runs.METRICS` and ``on_fraction`` (mount, law), NaN where a law has no run (a mount not in
    `law_mounts`; the MR runs on a mount but six_axis); ``c_on`` and ``damping_mean`` (law,) (N s m-1; NaN where a
    law has none); ``name`` (law,): the skyhook runs of `law_names`, then ``scheduled``
    (`uavdamp.study.payload_schedule`) when the setup has a payload table, its decisions as ``schedule`` (a
    `Schedule`, the same on every mount), then ``anfis`` (`uavdamp.study.payload_anfis`) when it also has the
    payload ANFIS, its decisions as ``anfis_schedule``, then the MR damper's runs on the six-axis isolator
    (`uavdamp.study.payload_mr`) with ``payload.mr.enabled``; {} without laws. `setup`: the payload comparison's.
    Every law body of every mount feeds the gimbal side by side."""
    s = setup.section
    if not law_c_on(s):
        return {}
    plan = schedule(t, moved, setup.table, s.schedule) if setup.table is not None else None
    per_sample = None if plan is None else plan.per_sample
    learnt = replanned(plan, t, setup.anfis, s.schedule) if plan is not None and setup.anfis is not None else None
    planned = {name: p for name, p in (("scheduled", plan), ("anfis", learnt)) if p is not None}
    names = law_names(s) + list(planned)
    settled = window_mask(t, s.settle_s, s.duration_s)
    c_on = law_c_on(s) + [math.nan] * len(planned)
    mean = [math.nan] * len(law_names(s)) + [float(np.mean(p.per_sample[settled])) for p in planned.values()]
    cells, bodies, shares = [], [], []
    for mount in law_mounts(s):
        found, on = _mount_laws(s, mount, t, moved, [p.per_sample for p in planned.values()])
        cells += [(s.mounts.index(mount), k) for k in range(len(names))]
        bodies, shares = bodies + found, shares + on
    found, rows = _mr_laws(s, t, moved, per_sample)
    cells += [(s.mounts.index("six_axis"), len(names) + k) for k in range(len(found))]
    names += payload_mr.mr_names(plan is not None) if found else []
    bodies, shares = bodies + found, shares + [r["on_fraction"] for r in rows]
    c_on, mean = c_on + [r["c_on"] for r in rows], mean + [r["damping_mean"] for r in rows]
    errors = s.gimbal.sensor_errors
    series = gimbal_series(setup.gimbal, setup.gains, t, bodies, setup.lever, sensor_errors=errors, seed=s.seed)
    out = {name: np.full((len(s.mounts), len(names)), math.nan) for name in (*METRICS, "on_fraction")}
    for cell, found, on in zip(cells, series, shares, strict=True):
        for name, value in run_metrics(t, found, setup.camera, s.settle_s, s.duration_s).items():
            out[name][cell] = value
        out["on_fraction"][cell] = on
    out |= {"c_on": np.array(c_on), "damping_mean": np.array(mean), "name": np.array(names)}
    return out | ({"schedule": plan} if plan is not None else {}) | ({"anfis_schedule": learnt} if learnt else {})


def _on_mounts(attrs: dict) -> dict:
    """A law metric's attributes, its long name saying where it is NaN."""
    where = "NaN: no such run on this mount (rigid and Y-Z have none; the MR runs are six_axis's)"
    return attrs | {"long_name": f"{attrs['long_name']} ({where})"}


def law_variables(values: dict[str, np.ndarray], section) -> tuple[dict, dict]:
    """(data variables law_NAME (mount, law) or (law,), the law coordinate) of `law_values`' output for a dataset."""
    if not values:
        return {}, {}
    extra = ("on_fraction", "c_on", "damping_mean", "name", "schedule", "anfis_schedule")
    data = {f"law_{k}": (("mount", "law"), v, _on_mounts(metric_attrs(k))) for k, v in values.items() if k not in extra}
    data["law_on_fraction"] = (
        ("mount", "law"),
        values["on_fraction"],
        _on_mounts({"units": "1", "long_name": "share of element-steps at c_on (skyhook; mr_skyhook: at 2.25 V)"}),
    )
    data["law_c_on"] = (
        ("law",),
        values["c_on"],
        {"units": "N s m-1", "long_name": "skyhook's on damping (mr_skyhook: the MR damper's at 2.25 V)"},
    )
    text = (
        "the law's mean damping over the settled window: the scheduled law's C; mr_off, mr_on: the MR damper's "
        "equivalent damping at its voltage; mr_scheduled: its C clamped to the MR damper's range (MR: at the "
        "reference stroke)"
    )
    data["law_damping_mean"] = (("law",), values["damping_mean"], {"units": "N s m-1", "long_name": text})
    lag = f", damper lag {section.skyhook_lag:g} s" if section.skyhook_lag > 0 else ", ideal damper"
    text = (
        "semi-active law on a six-axis isolator's elements (six_axis, wire_rope), the gimbal on it: on-off skyhook "
        f"between c_on and c_off {section.c_off:g} N s m-1{lag}; scheduled: C from the tracked lines through the "
        "payload table; anfis: the payload ANFIS's C from two DOFs' tracked frequencies; mr_*: a Spencer MR "
        "damper along each element's x, y, z (payload.mr; six_axis only), held at 0 or 2.25 V, on-off skyhook on "
        "the voltage, or the scheduled law's C as a voltage"
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
    if "anfis_schedule" in values:
        data["anfis_damping"] = (
            ("update_time",),
            values["anfis_schedule"].damping,
            {"units": "N s m-1", "long_name": "the payload ANFIS's C from this update on (every element)"},
        )
    return data, coords
