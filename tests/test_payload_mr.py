"""The MR damper's runs in the payload stage (`uavdamp.study.payload_mr`): where they run and what they are named,
the scheduled law's C below the damper's range as the damper held off, and the keys a bad damper names."""

from __future__ import annotations

import numpy as np
import pytest
from test_payload import CAMERA, PLATFORM, _section, _time

from uavdamp.contract import MountMotion
from uavdamp.damping.dampers import V_MAX, equivalent_damping
from uavdamp.settings import ConfigError
from uavdamp.study import payload_mr
from uavdamp.study import payload_table as pt
from uavdamp.study.payload import compare_payloads

LAWS = ["skyhook_10", "mr_off", "mr_on", "mr_skyhook"]


def _motion(t: np.ndarray) -> MountMotion:
    """x and pitch at 7 Hz, z at 8 Hz: strokes of about a millimetre."""
    u = np.zeros((6, t.size))
    u[0], u[2] = 1e-3 * np.sin(2 * np.pi * 7.0 * t), 5e-4 * np.sin(2 * np.pi * 8.0 * t)
    u[4] = 1e-3 * np.sin(2 * np.pi * 7.0 * t + 1.0)
    return MountMotion(u[:3], u[3:])


def test_the_mr_runs_are_the_six_axis_isolators_alone_and_carry_their_damping():
    """mounts rigid, six_axis, wire_rope: the MR runs are finite on six_axis only (NaN elsewhere, as every law on
    the rigid mount); mr_skyhook switches (between 5 and 95 % of element-steps at 2.25 V) and its c_on is the
    damper's equivalent damping at 2.25 V at the reference stroke (`dampers.equivalent_damping`, computed here),
    mr_off's and mr_on's at 0 and 2.25 V; the damper matters: mr_off and mr_on differ by over 5 %."""
    section = _section(payloads=["gimbal"], mounts=["rigid", "six_axis", "wire_rope"], duration_s=0.6,
                       settle_s=0.2, damping_n_s_m=[1.0, 10.0])  # fmt: skip
    section = section.with_camera(PLATFORM.structure)
    t = _time(0.7)
    ds = compare_payloads(t, _motion(t), section, PLATFORM, CAMERA)
    assert list(ds.law.values) == LAWS
    los = ds.law_los_std
    assert np.isfinite(los.sel(mount="six_axis")).all()
    assert np.isnan(los.sel(mount="rigid")).all() and np.isnan(los.sel(mount="wire_rope", law=LAWS[1:])).all()
    assert 0.05 < float(ds.law_on_fraction.sel(mount="six_axis", law="mr_skyhook")) < 0.95
    params = payload_mr.spec(section).params
    c_eq = [equivalent_damping(params, v, 0.05, 8.0) for v in (0.0, V_MAX)]
    np.testing.assert_allclose(ds.law_damping_mean.sel(law=["mr_off", "mr_on"]), c_eq, rtol=1e-3)
    assert float(ds.law_c_on.sel(law="mr_skyhook")) == pytest.approx(c_eq[1], rel=1e-3)
    off, on = (float(los.sel(mount="six_axis", law=n)) for n in ("mr_off", "mr_on"))
    assert abs(on / off - 1) > 0.05


def test_a_scheduled_c_below_the_dampers_range_is_the_damper_held_off():
    """The scheduled law left one eligible damping c (tests/test_payload_schedule.py's setup) and the MR damper's
    range above it ([2 c, 10 c]): mr_scheduled's C is clamped to c_off, so its run is mr_off's (to rounding) and
    its mean C is c_off."""
    table = pt.table_dataset(_section(table={"stiffness_n_m": {"values": [500.0]}}))
    decay = table.decay_time.sel(stiffness=500.0).values
    c = float(table.damping.values[decay <= 0.5].min())
    section = _section(
        payloads=["gimbal"],
        mounts=["six_axis"],
        damping_n_s_m=[1.0, c],
        duration_s=1.0,
        settle_s=0.3,
        schedule={"initial_damping_n_s_m": c, "max_decay_time_s": float(decay[table.damping.values == c][0])},
        mr={"damping_range_n_s_m": [2 * c, 10 * c]},
    ).with_camera(PLATFORM.structure)
    t = _time(1.1)
    ds = compare_payloads(t, _motion(t), section, PLATFORM, CAMERA, table)
    laws = ds.sel(mount="six_axis")
    assert "mr_scheduled" in ds.law.values
    for name in ("law_los_std", "law_peak_stroke", "law_los_detrended_std"):
        assert float(laws[name].sel(law="mr_scheduled")) == pytest.approx(float(laws[name].sel(law="mr_off")), rel=1e-9)
    off = float(ds.law_damping_mean.sel(law="mr_off"))
    assert float(ds.law_damping_mean.sel(law="mr_scheduled")) == pytest.approx(off, rel=1e-12)


@pytest.mark.parametrize(
    ("mr", "rule"),
    [
        ({"damping_range_n_s_m": [6.0, 1.0]}, "need 0 < c_off < c_on"),
        ({"max_substep_s": 0.0}, "must be > 0"),
    ],
)
def test_a_bad_mr_damper_is_refused_naming_its_key(mr, rule):
    with pytest.raises(ConfigError, match=f"payload.mr.{next(iter(mr))}: {rule}"):
        _section(mr=mr)


def test_a_range_beyond_the_published_dampers_reach_names_the_key():
    """c_on / c_off = 100: no scaling of the published damper spans it (about 6 at most)."""
    with pytest.raises(ConfigError, match="payload.mr.damping_range_n_s_m: c_max / c_min = 100"):
        payload_mr.spec(_section(mr={"damping_range_n_s_m": [1.0, 100.0]}))
