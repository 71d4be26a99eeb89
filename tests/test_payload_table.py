"""The payload table (`uavdamp.study.payload_table`): its criterion against the simulated gimbal on an isolator built
here by hand, the best damping's limits from the base-excited oscillator's closed form, the optimum's arithmetic on
a cube of hand values, and the refusals of its config keys."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_payload import _section, _time
from test_transmissibility import _amplitude

from uavdamp.contract import MountMotion
from uavdamp.platform.gimbal import design
from uavdamp.platform.six_axis import square_layout
from uavdamp.settings import ConfigError
from uavdamp.study import payload_runs as runs
from uavdamp.study import payload_table as pt

ANY_C = {"max_decay_time_s": 100.0}  # the scheduled law may take any C of a small table (none settles in 0.5 s)
SMALL = {
    "freq_hz": {"values": [7.0]},
    "stiffness_n_m": {"values": [500.0, 1000.0]},
    "damping_n_s_m": {"values": [3.0]},
    "bands_hz": {"helicopter": [3.0, 12.0]},
}
AT_7_HZ = {"freq_hz": {"values": [7.0]}}  # the payload ANFIS's reference within SMALL's one frequency


@pytest.mark.parametrize(("dof", "amplitude"), [(0, 1e-5), (4, 1e-4), (5, 1e-4)])
def test_the_criterion_is_the_simulated_gimbal_on_a_stiffer_isolator(dof, amplitude):
    """One table point (x, pitch or yaw of the mount at 7 Hz; elements at K = 1000 N/m in z, twice the config's, x
    and y likewise; C = 3 N s/m) against the time-domain gimbal on an isolator built here from the same numbers:
    sqrt(a_pitch^2 + a_yaw^2) / sqrt 2 of the fitted amplitudes, at the table's amplitude (the loop is linear),
    within 1 % (the transmissibility's own agreement, tests/test_transmissibility.py)."""
    section = _section(
        gimbal={"sensor_errors": False}, table={**SMALL, "rotation_amplitude_rad": 2e-3}, schedule=ANY_C, anfis=AT_7_HZ
    )
    isolator = square_layout(
        runs.gimbal_payload(section),
        section.six_axis.half_spacing,
        (500.0, 500.0, 1000.0),
        (3.0, 3.0, 3.0),
        kind=section.six_axis.kind,
        semi_active=True,
        gravity=runs.gimbal_params(section).gravity,
    )
    t = _time(4.0)
    u = np.zeros((6, t.size))
    u[dof] = amplitude * np.sin(2 * np.pi * 7.0 * t)
    body = runs.isolated_motion(isolator, t, MountMotion(u[:3], u[3:]))
    p = runs.gimbal_params(section)
    lever = (0.0, 0.0, runs.gimbal_height(section))
    (series,) = runs.gimbal_series(p, design(p), t, [body], lever, sensor_errors=False, seed=1)
    pitch, yaw = (_amplitude(t, getattr(series, a), 7.0, 2.0) / amplitude for a in ("pitch", "yaw"))
    table = pt.table_dataset(section)
    level = pt.amplitudes(section.table)[dof]
    assert level == (1.3e-3 if dof < 3 else 2e-3)
    expected = math.hypot(pitch, yaw) * level / math.sqrt(2)
    assert float(table.criterion.isel(dof=dof).sel(stiffness=1000.0).squeeze()) == pytest.approx(expected, rel=0.01)


def test_the_best_damping_locks_below_the_modes_and_frees_well_above_them():
    """A base-excited oscillator's transmissibility falls with damping below sqrt 2 times its natural frequency and
    rises with it above: on the coupled isolator, below the lowest mode the best C is the grid's largest and from
    four times the highest mode on its smallest, for every DOF the gimbal sees and every stiffness. (Coupled modes
    spread the crossover: at three times, K = 2000 N/m's pitch still wants 0.19 N s/m at 51 Hz.)"""
    section = _section()
    table = pt.table_dataset(section)
    c = table.damping.values
    seen = [d for d in table.dof.values if np.isfinite(table.scheduling_gain.sel(dof=d)).all()]
    assert seen == ["x", "ry", "rz"]  # a balanced gimbal on a symmetric square: y, z, roll reach only its roll
    below, above = [], []
    for k in table.stiffness.values:
        modes = table.mode_frequency.sel(stiffness=k).values
        best = table.damping_opt.sel(stiffness=k, dof=seen)
        below.append(best.sel(freq=table.freq[table.freq < modes.min()]).values.ravel())
        above.append(best.sel(freq=table.freq[table.freq >= 4 * modes.max()]).values.ravel())
    below, above = np.concatenate(below), np.concatenate(above)
    assert below.size >= 30 and above.size >= 200  # the softest K's modes lie below the grid's 2 Hz
    assert np.all(below == c[-1]) and np.all(above == c[0])


def test_the_optimum_of_a_cube_of_hand_values():
    """Two DOFs (the second blind: zero everywhere), three frequencies, one stiffness, three dampings; band A holds
    the first two frequencies, band B all three."""
    crit = np.zeros((2, 3, 1, 3))
    crit[0, :, 0, :] = [[1.0, 2.0, 4.0], [4.0, 1.0, 2.0], [9.0, 9.0, 1.0]]
    damping = np.array([0.5, 5.0, 50.0])
    bands = np.array([[True, True, False], [True, True, True]])
    out = pt.optimum(crit, damping, bands)
    np.testing.assert_array_equal(out["damping_opt"][0, :, 0], [0.5, 5.0, 50.0])
    np.testing.assert_array_equal(out["criterion_opt"][0, :, 0], [1.0, 1.0, 1.0])
    # band A: means 2.5, 1.5, 3 -> C = 5; band B: means 14/3, 4, 7/3 -> C = 50
    np.testing.assert_array_equal(out["damping_best_constant"][0, 0], [5.0, 50.0])
    np.testing.assert_allclose(out["scheduling_gain"][0, 0], [(2.0 + 1.0) / 2, (4.0 + 2.0 + 1.0) / 3])
    np.testing.assert_array_equal(out["criterion_best_constant"][0, :, 0, 0], [2.0, 1.0, np.nan])
    np.testing.assert_array_equal(out["optimum_at_grid_edge"][0, :, 0], [1, 0, 2])
    for name in ("damping_opt", "damping_best_constant", "scheduling_gain"):
        assert np.all(np.isnan(out[name][1])), name
    assert np.all(out["optimum_at_grid_edge"][1] == 0)


@pytest.mark.parametrize(
    ("table", "key"),
    [
        ({"stiffness_n_m": {"values": [5.0, 500.0]}}, "payload.table.stiffness_n_m"),  # rocks over under its weight
        (
            {"freq_hz": {"values": [10.0, 600.0]}, "bands_hz": {"all": [10.0, 600.0]}},
            "payload.table.freq_hz",
        ),  # above the 1 kHz loop's Nyquist
        ({"bands_hz": {"helicopter": [12.1, 12.9]}}, "payload.table.bands_hz.helicopter"),  # no table frequency
        ({"rotation_amplitude_rad": 0.0}, "payload.table.rotation_amplitude_rad"),
        ({"stiffness_n_m": {"values": [250.0, 1000.0]}}, "payload.table.stiffness_n_m"),  # not the isolator's 500
        ({"freq_hz": {"values": [3.0, 100.0]}}, "payload.anfis.freq_hz"),  # the ANFIS's reference reaches 2-120 Hz
    ],
)
def test_a_table_key_that_cannot_work_is_refused_by_name(table, key):
    with pytest.raises(ConfigError, match=key.replace(".", r"\.")):
        _section(table=table)


def test_a_settling_limit_that_leaves_the_law_no_damping_is_refused_before_any_job():
    """The default isolator's fastest decay on the table's grid is 0.107 s (at 20.8 N s/m): 0.05 s leaves none."""
    with pytest.raises(ConfigError, match=r"payload\.schedule\.max_decay_time_s.*0\.107 s"):
        _section(schedule={"max_decay_time_s": 0.05})
    _section(schedule={"max_decay_time_s": 0.11})


def test_the_dataset_says_its_units():
    table = pt.table_dataset(_section(table=SMALL, schedule=ANY_C, anfis=AT_7_HZ))
    for name, (_, units, _) in pt.ROWS.items():
        assert table[name].attrs["units"] == units and table[name].attrs["long_name"], name
    assert table.freq.attrs["units"] == "Hz" and table.stiffness.attrs["units"] == "N m-1"
    assert table.attrs["criterion_name"] == "los_std"
