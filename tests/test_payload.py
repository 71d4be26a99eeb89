"""The payload comparison (`uavdamp.study.payload`): the gimbal against its loop's closed form, balance, the
six-axis isolator against the single-degree-of-freedom closed form, the config section's refusals and the
dataset's metadata, NaN pattern and repeatability."""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest
import xarray as xr
from conftest import load_config, platform_params
from test_gimbal import _fit

from uavdamp.camera.optics import CameraModel
from uavdamp.contract import MountMotion
from uavdamp.platform.gimbal import design
from uavdamp.platform.gimbal_loop import base_to_los
from uavdamp.platform.six_axis import mass_matrix, total_stiffness
from uavdamp.platform.six_axis_run import run as six_axis_run
from uavdamp.settings import ConfigError, parse
from uavdamp.sources.stated import StatedSource
from uavdamp.study import payload_runs
from uavdamp.study.payload import (
    PayloadInput,
    PayloadSection,
    compare_inputs,
    compare_payloads,
    gimbal_params,
    inputs,
    six_axis_isolator,
)
from uavdamp.study.payload_design import design_dataset

H = 5.0e-4  # s, the runs' grid
CAMERA = parse(CameraModel, load_config()["camera"], "camera")
PLATFORM = platform_params()


def _section(**keys) -> PayloadSection:
    return parse(PayloadSection, keys, "payload")


def _time(duration: float) -> np.ndarray:
    return np.arange(int(round(duration / H)) + 1) * H


@pytest.mark.parametrize("axis, row", [("pitch", 1), ("yaw", 2)])
def test_gimbal_on_a_rotating_rigid_mount_follows_its_loop_closed_form(axis, row):
    """A base rotation sine A sin(2 pi f t) about one axis, ideal sensors, the gimbal's axes on the mount point
    (com_height_m 0: no lever arm): the line of sight is a sine of amplitude |B(e^{j w T})| A, B the sampled-data
    closed form of `gimbal_loop.base_to_los` (S times the motor-off angle per base rotation: the base reaches the
    camera through friction alone, so |S| A itself would overstate it); its rms over whole periods is that / sqrt 2,
    within 2 %."""
    f, amplitude = 5.0, 1.0e-2
    section = _section(
        payloads=["gimbal"],
        mounts=["rigid"],
        duration_s=2.0,
        settle_s=1.0,
        damping_n_s_m=[1.0],
        gimbal={"sensor_errors": False},
        six_axis={"com_height_m": 0.0},
    )
    t = _time(2.0)
    rotation = np.zeros((3, t.size))
    rotation[row] = amplitude * np.sin(2 * np.pi * f * t)
    ds = compare_payloads(t, MountMotion(np.zeros((3, t.size)), rotation), section, PLATFORM, CAMERA)
    p = gimbal_params(section)
    expected = abs(base_to_los(p, design(p)[axis], f)[0]) * amplitude / math.sqrt(2)
    assert float(ds.los_std.sel(payload="gimbal", mount="rigid", damping=1.0)) == pytest.approx(expected, rel=0.02)


def test_a_sideways_mount_moves_the_unbalanced_head_and_not_the_balanced_gimbal():
    """A pure y translation (1 mm at 7 Hz) on the rigid mount, ideal sensors: the balanced gimbal's yaw and pitch
    do not move (below 1e-9 rad: its lateral specific force reaches only the roll axis's tilt), the balanced head's
    neither, while the paper's head, its camera's centre of mass forward of the yaw axis and above the tilt axis,
    swings (more than 1 mrad rms)."""
    section = _section(
        mounts=["rigid"], duration_s=1.0, settle_s=0.5, damping_n_s_m=[1.0], gimbal={"sensor_errors": False}
    )
    t = _time(1.0)
    ds = compare_payloads(t, MountMotion.planar(1e-3 * np.sin(2 * np.pi * 7.0 * t), 0 * t), section, PLATFORM, CAMERA)
    los = ds.los_std.sel(mount="rigid", damping=1.0)
    assert float(los.sel(payload="gimbal")) < 1e-9
    assert float(los.sel(payload="balanced_head")) < 1e-9
    assert float(los.sel(payload="paper_head")) > 1e-3


def test_six_axis_vertical_transmissibility_matches_the_single_degree_closed_form():
    """Four elements of k_z = 500 N/m and C = 10 N s/m each under the 1.5 kg payload (0.9 kg camera + 0.3 kg
    mechanism + 0.3 kg plate), the centre of mass above the square's centre: the vertical motion decouples, so a
    30 Hz vertical sine of the mount (five times the 5.8 Hz mode) reaches the payload by
    |(k + j w c) / (k - m w^2 + j w c)| with k = 2000 N/m, c = 40 N s/m (within 2 %); the payload's coordinates
    are those of `six_axis_run.run`, and its acceleration is -w^2 times its displacement."""
    f, amplitude, c = 30.0, 1.0e-4, 10.0
    section = _section()
    t = _time(2.0)
    mount = MountMotion(np.stack([0 * t, 0 * t, amplitude * np.sin(2 * np.pi * f * t)]), np.zeros((3, t.size)))
    isolator = six_axis_isolator(section, c)
    body = payload_runs.isolated_motion(isolator, t, mount)
    w, k, damping, m = 2 * np.pi * f, 4 * 500.0, 4 * c, 1.5
    expected = abs((k + 1j * w * damping) / (k - m * w**2 + 1j * w * damping))
    assert _fit(t, body.coordinates[2], f, 1.0) / amplitude == pytest.approx(expected, rel=0.02)
    acceleration = _fit(t, body.accelerations[2], f, 1.0)
    assert acceleration == pytest.approx(w**2 * _fit(t, body.coordinates[2], f, 1.0), rel=0.01)
    reference = six_axis_run(isolator, t, mount.translation, mount.rotation)
    np.testing.assert_allclose(body.coordinates[:3], reference.payload_translation.values, atol=1e-12)
    assert body.peak_stroke == pytest.approx(float(np.abs(reference.element_stroke).max()), rel=1e-9)


def test_design_dataset_holds_the_modes_and_the_loops():
    """The six-axis mount's vertical mode sqrt(4 k_z / m) / 2 pi = sqrt(2000 / 1.5) / 2 pi = 5.81 Hz and the Y-Z
    mount's y, z modes sqrt(1000 / 1.5) / 2 pi = 4.11 Hz (closed forms), the rigid mount's NaN; the gimbal's rate
    loops cross at the specified 40 Hz with the specified 50 deg."""
    ds = design_dataset(_section())
    six = ds.sel(mount="six_axis")
    vertical = float(six.mode_frequency[list(six.mode_dofs.values).index("z")])
    assert vertical == pytest.approx(math.sqrt(2000.0 / 1.5) / (2 * math.pi), rel=1e-9)
    yz = ds.sel(mount="yz")
    assert sorted(yz.mode_dofs.values[:2]) == ["y", "z"]
    np.testing.assert_allclose(yz.mode_frequency.values[:2], math.sqrt(1000.0 / 1.5) / (2 * math.pi), rtol=1e-9)
    assert np.isnan(ds.mode_frequency.sel(mount="rigid")).all()
    # the wire rope: below yield the six-axis modes; fully yielded, the lateral elements at alpha k = 0.5 k keep the
    # vertical mode (a lateral change cannot move it) and lower none above its own (less stiffness, same mass)
    wire = ds.sel(mount="wire_rope")
    np.testing.assert_array_equal(wire.mode_frequency.values, six.mode_frequency.values)
    yielded = wire.post_yield_mode_frequency.values
    assert np.isclose(yielded, vertical, rtol=1e-9).any()
    assert np.all(yielded <= six.mode_frequency.values + 1e-9) and yielded[0] < 0.9 * six.mode_frequency.values[0]
    assert np.isnan(ds.post_yield_mode_frequency.sel(mount=["rigid", "yz", "six_axis"])).all()
    assert list(ds.mount.values) == ["rigid", "yz", "six_axis", "wire_rope"]  # the config's order
    # mode shapes: the vertical mode pure z, each shape an eigenvector K phi = w^2 M phi (the isolator's own
    # matrices), its largest coordinate +1
    iso = six_axis_isolator(_section(), float(ds.attrs["damping_N_s_m"]))
    k, m = total_stiffness(iso), mass_matrix(iso.payload)
    for j in range(6):
        phi, w = six.mode_shape.isel(mode=j).values, 2 * math.pi * float(six.mode_frequency.isel(mode=j))
        np.testing.assert_allclose(k @ phi, w**2 * m @ phi, rtol=0, atol=1e-9 * np.abs(k @ phi).max())
        assert np.abs(phi).max() == pytest.approx(1.0) and phi[np.argmax(np.abs(phi))] == pytest.approx(1.0)
    np.testing.assert_allclose(six.mode_shape.sel(mode=list(six.mode_dofs.values).index("z")), [0, 0, 1, 0, 0, 0],
                               atol=1e-12)  # fmt: skip
    # the isolator maker's curves: the wire rope's vertical (linear by default) is the closed form's at any amplitude
    curves = ds.wire_rope_transmissibility
    assert curves.dims == ("excitation_amplitude", "direction", "isolator_frequency")
    np.testing.assert_allclose(curves.sel(direction="z"), ds.six_axis_transmissibility.sel(direction="z").values
                               * np.ones((curves.excitation_amplitude.size, 1)), rtol=1e-2)  # fmt: skip
    np.testing.assert_allclose(ds.rate_crossover.values, 40.0, rtol=1e-3)
    np.testing.assert_allclose(ds.rate_phase_margin.values, 50.0, atol=0.1)
    _assert_metadata(ds)


def test_the_gimbal_carries_the_platforms_camera():
    """One camera on every payload: `with_camera` gives the gimbal the platform's camera mass, which moves the
    isolated payload's mass one for one (0.9 + 0.3 + 0.3 = 1.5 kg; a 1.8 kg camera: 2.4 kg) and the six-axis
    vertical mode to sqrt(4 k_z / m) / 2 pi (closed form); the camera is not a payload key (seen failing with
    `with_camera` returning the section unchanged: 1.5 kg)."""
    camera = PLATFORM.structure
    section = _section().with_camera(camera)
    assert (gimbal_params(section).camera_mass, gimbal_params(section).camera_size) == (0.9, (0.10, 0.06, 0.06))
    heavy = _section().with_camera(dataclasses.replace(camera, camera_mass=1.8))
    assert gimbal_params(heavy).camera_mass == 1.8
    six = design_dataset(heavy).sel(mount="six_axis")
    assert six.attrs["gimbal_payload_mass_kg"] == pytest.approx(2.4, rel=1e-12)
    vertical = float(six.mode_frequency[list(six.mode_dofs.values).index("z")])
    assert vertical == pytest.approx(math.sqrt(2000.0 / 2.4) / (2 * math.pi), rel=1e-9)
    with pytest.raises(ConfigError, match="camera_mass"):
        _section(gimbal={"camera_mass_kg": 1.8})


@pytest.mark.parametrize(
    "keys, where",
    [
        ({"time_step_s": 3.0e-4}, "payload.time_step_s"),
        ({"mounts": ["rigid", "tilted"]}, "payload.mounts"),
        ({"damping_n_s_m": []}, "payload.damping_n_s_m"),
        ({"payloads": ["gimbal", "gimbal"]}, "payload.payloads"),
        ({"settle_s": 5.0}, "payload.settle_s"),
        ({"gimbal": {"phase_margin_deg": [50.0, 95.0, 50.0]}}, "payload.gimbal.phase_margin_deg"),
        ({"six_axis": {"kind": "spring"}}, "payload.six_axis.kind"),
        ({"six_axis": {"com_height_m": 1.0}}, "payload.six_axis"),
        ({"loop_rate_hz": 1000.0}, "payload.loop_rate_hz"),
    ],
)
def test_bad_keys_are_refused_naming_the_key(keys, where):
    with pytest.raises(ConfigError, match="^" + re.escape(where) + ":"):
        _section(**keys)


def _assert_metadata(ds: xr.Dataset) -> None:
    for name in [*ds.data_vars, *ds.coords]:
        assert {"units", "long_name"} <= set(ds[name].attrs), name


def _whole(seed_runs: int = 2) -> list[xr.Dataset]:
    section = _section(duration_s=0.6, settle_s=0.3, damping_n_s_m=[3.0, 30.0])
    t = _time(0.7)
    translation = np.stack([0 * t, 1e-3 * np.sin(2 * np.pi * 7 * t), 1e-3 * np.sin(2 * np.pi * 8 * t)])
    rotation = np.stack([2e-3 * np.sin(2 * np.pi * 9 * t), 2e-3 * np.sin(2 * np.pi * 11 * t), 0 * t])
    mount = MountMotion(translation, rotation)
    return [compare_payloads(t + 3.0, mount, section, PLATFORM, CAMERA) for _ in range(seed_runs)]


def test_the_dataset_has_metadata_nan_where_not_modelled_and_repeats():
    """Every variable and coordinate has units and long_name; NaN exactly where there is no model (a head on a
    six-axis mount, linear or wire rope; the torque limit of a head; the stroke and the best C of the rigid mount),
    the rigid mount's values the same at every C; two runs identical (the gimbal's noise seeded), with a noise
    floor above 0."""
    first, second = _whole()
    _assert_metadata(first)
    xr.testing.assert_identical(first, second)
    head = first.payload.isin(["paper_head", "balanced_head"])
    for name in ("los_std", "los_roll_rms", "los_peak_to_peak", "jitter_within_exposure", "drift_frame_to_frame",
                 "mtf_nyquist", "skew_px", "blur_p95"):  # fmt: skip
        v = first[name]
        expected = head & first.mount.isin(["six_axis", "wire_rope"])
        np.testing.assert_array_equal(np.isnan(v.values), expected.broadcast_like(v).values, err_msg=name)
        rigid = v.sel(mount="rigid").values
        np.testing.assert_array_equal(rigid, rigid[..., :1].repeat(rigid.shape[-1], axis=-1), err_msg=name)
    saturated = first.torque_saturated
    np.testing.assert_array_equal(np.isnan(saturated.values), head.broadcast_like(saturated).values)
    stroke = first.peak_stroke
    no_stroke = (first.mount == "rigid") | (head & first.mount.isin(["six_axis", "wire_rope"]))
    np.testing.assert_array_equal(np.isnan(stroke.values), no_stroke.broadcast_like(stroke).values)
    best = first.best_damping
    np.testing.assert_array_equal(np.isnan(best.values), no_stroke.broadcast_like(best).values)
    assert set(best.values[np.isfinite(best.values)]) <= {3.0, 30.0}
    assert float(first.floor_los_std.sel(payload="gimbal")) > 0
    np.testing.assert_array_equal(first.floor_los_std.sel(payload=["paper_head", "balanced_head"]).values, 0.0)


def test_inputs_from_cases_and_stated_sources_stack_over_input():
    """The study's cases and the named stated sources become the `input` dimension, with their descriptions."""
    t = _time(1.0)
    cases = xr.Dataset(
        {
            "mount_displacement": (("case", "mount_axis", "time"), np.zeros((1, 3, t.size))),
            "mount_rotation": (("case", "mount_axis", "time"), np.zeros((1, 3, t.size))),
            "description": (("case",), ["still"]),
        },
        coords={"case": ["case1"], "time": t},
    )
    tones = {"kind": "tones", "amplitude_m": 1e-3, "freq_y_hz": [7.0], "freq_z_hz": [8.0], "description": "two"}
    sources = {"tones": parse(StatedSource, tones, "sources.tones")}
    section = _section(
        payloads=["gimbal"], mounts=["rigid"], duration_s=0.5, settle_s=0.2, damping_n_s_m=[3.0], sources=["tones"]
    )
    ds = compare_inputs(inputs(cases, sources, section), section, PLATFORM, CAMERA)
    assert list(ds.input.values) == ["case1", "tones"]
    assert list(ds.input_description.values) == ["still", "two"]
    assert ds.floor_los_std.dims == ("payload",)
    drift = ds.drift_frame_to_frame.sel(payload="gimbal", mount="rigid", damping=3.0)
    assert float(drift.sel(input="tones")) > 3 * float(drift.sel(input="case1"))  # 0.1 px image sines on 0.03 px
    _assert_metadata(ds)
    with pytest.raises(ConfigError, match=r"^payload\.sources\[0\]"):
        inputs(cases, {}, section)


@pytest.mark.parametrize("step_s, f", [(5e-3, 7.0), (1e-3, 100.0)], ids=["helicopter_case", "multirotor"])
def test_the_input_is_resampled_band_limited_so_its_acceleration_is_the_motions(step_s, f):
    """A 1.3 mm line (7 Hz sampled every 5 ms, a study case's; 100 Hz every 1 ms, a multirotor source's) onto the
    0.5 ms grid: the second difference of the resampled motion is the closed form -(2 pi f)^2 A sin within 1 % of
    its amplitude away from the ends. Seen failing with the linear interpolation (`uavdamp.contract.on_grid`),
    whose second difference is spikes at the input's samples, and with scipy's default resampling filter (86 %
    at 7 Hz: its images, differentiated twice)."""
    from uavdamp.study.payload import resampled

    a, h = 1.3e-3, 5e-4
    t = np.arange(0.0, 2.0 + 1e-9, step_s)
    line = a * np.sin(2 * np.pi * f * t)
    zeros = np.zeros_like(t)
    grid, moved = resampled(t, MountMotion(np.stack([zeros, line, zeros]), np.zeros((3, t.size))), h)
    assert grid[1] - grid[0] == pytest.approx(h) and grid[-1] == pytest.approx(2.0)
    acc = np.diff(moved.translation[1], 2) / h**2
    inner = slice(400, -400)  # 0.2 s from either end (the filter's edge)
    expected = -((2 * np.pi * f) ** 2) * a * np.sin(2 * np.pi * f * grid[1:-1])
    peak = (2 * np.pi * f) ** 2 * a
    assert np.max(np.abs(acc[inner] - expected[inner])) < 0.01 * peak


def test_the_resampling_ratio_is_one_of_integers_up_to_1000_or_none():
    """The polyphase filter's up / down from an input's step to the runs' (`payload_runs.resample_ratio`, the rule
    the config checks apply to a measured scenario before the benchmark): the quadrotor log's 199.6 Hz x 10 on a
    0.5 ms grid is 500 / 499 (1 / 1996 s over 1 / 2000 s), the vtol log's 0.4888 ms grid 611 / 625 on 0.5 ms and
    611 / 1250 on 1 ms, whose denominator is over 1000: none, and `resampled` refuses it naming the key."""
    from fractions import Fraction

    assert payload_runs.resample_ratio(5e-3, 5e-4) == Fraction(10)
    assert payload_runs.resample_ratio(1 / 1996, 5e-4) == Fraction(500, 499)
    assert payload_runs.resample_ratio(0.4888e-3, 5e-4) == Fraction(611, 625)
    assert payload_runs.resample_ratio(0.4888e-3, 1e-3) is None
    t = np.arange(100) * 0.4888e-3
    with pytest.raises(ValueError, match=r"^payload\.time_step_s: 0\.001 s is not a rational fraction"):
        payload_runs.resampled(t, MountMotion(np.zeros((3, t.size)), np.zeros((3, t.size))), 1e-3)


def test_the_inputs_give_the_same_numbers_on_one_and_two_workers():
    """payload.threads fans the inputs out over joblib workers (`uavdamp.parallel.run`): the dataset is identical
    on 1 and 2, sensor noise included (each run draws from its own seeded Generator)."""
    section = _section(
        payloads=["gimbal"], mounts=["rigid", "six_axis"], duration_s=0.6, settle_s=0.2, damping_n_s_m=[1.0, 10.0]
    )
    t = _time(0.6)
    found = [
        PayloadInput(f"line{f:g}", "", t, MountMotion.planar(1e-4 * np.sin(2 * np.pi * f * t), 0 * t))
        for f in (7.0, 13.0)
    ]
    one, two = (compare_inputs(found, dataclasses.replace(section, threads=n), PLATFORM, CAMERA) for n in (1, 2))
    xr.testing.assert_identical(one, two)
    assert one.sizes["input"] == 2 and list(one.law.values) == ["skyhook_10", "mr_off", "mr_on", "mr_skyhook"]


def test_the_gyro_bias_key_reaches_the_gimbals_imu():
    """payload.gimbal.gyro_bias_rad_s is the IMU's gyro bias (rad s-1, camera x, y, z); none by default."""
    section = _section()
    assert section.gimbal.params().imu.gyro_bias == (0.0, 0.0, 0.0)
    biased = dataclasses.replace(section.gimbal, gyro_bias=(1e-4, 2e-4, 3e-4))
    assert biased.params().imu.gyro_bias == (1e-4, 2e-4, 3e-4)


def test_the_detrended_line_of_sight_leaves_a_drift_out_and_keeps_the_vibration():
    """A ramp and a quadratic (a gyro bias's drift) plus a 7 Hz sine of 100 urad on yaw, a 50 urad sine on pitch,
    over 4 s (28 whole cycles): the detrended rms is the sines' sqrt(100^2 + 50^2) / sqrt(2) urad within 0.5 % (a
    sine's residual projection on a quadratic over whole cycles is small); the drift alone leaves 0."""
    t = np.arange(1.0, 5.0, 5e-4)
    drift = 1e-3 * (t - 1.0) + 2e-4 * (t - 1.0) ** 2
    yaw = drift + 100e-6 * np.sin(2 * np.pi * 7.0 * t)
    pitch = -drift + 50e-6 * np.cos(2 * np.pi * 7.0 * t)
    expected = math.hypot(100e-6, 50e-6) / math.sqrt(2)
    assert payload_runs.detrended_std(t, yaw, pitch) == pytest.approx(expected, rel=5e-3)
    assert payload_runs.detrended_std(t, drift, -drift) == pytest.approx(0.0, abs=1e-15)


def _wire_rope_runs(alpha: float, yield_stroke_m: float) -> xr.Dataset:
    """The gimbal on the six-axis and the wire-rope mounts under case 1's lines at 1.3 mm (strokes of mm)."""
    wire = {"alpha": alpha, "yield_stroke_m": yield_stroke_m}
    section = _section(duration_s=1.0, settle_s=0.3, damping_n_s_m=[3.0, 30.0], payloads=["gimbal"],
                       mounts=["six_axis", "wire_rope"], wire_rope=wire, mr={"enabled": False})  # fmt: skip
    t = _time(1.1)
    translation = np.stack([1.3e-3 * np.sin(2 * np.pi * 7.07 * t), 0.65e-3 * np.sin(2 * np.pi * 8.05 * t), 0 * t])
    rotation = np.stack([0 * t, 1.3e-3 * np.sin(2 * np.pi * 7.07 * t + 1.0), 0 * t])
    return compare_payloads(t, MountMotion(translation, rotation), section, PLATFORM, CAMERA)


def test_the_wire_rope_mount_is_the_six_axis_isolator_without_hysteresis_and_differs_with_it():
    """alpha = 1 (no hysteretic force) gives the six-axis mount's numbers: the stage runs the wire rope on the same
    elements, damping and gimbal (the two integrations agree to rounding, 1e-12 of the line of sight: tests/
    test_wire_rope.py; 1e-9 here leaves room for the IMU's quantisation to round a sample the other way); at
    alpha = 0.3 and a 0.2 mm yield stroke, below the strokes, the light damper's line of sight moves by over 5 %, and
    so does skyhook's. The same holds for the laws: at alpha = 1 the wire rope's skyhook cells are the six-axis
    isolator's (the same decisions, element-step by element-step)."""
    same = _wire_rope_runs(1.0, 1e-3)
    for name in ("los_std", "peak_stroke", "mtf_nyquist", "los_detrended_std"):
        v = same[name].sel(payload="gimbal")
        np.testing.assert_allclose(v.sel(mount="wire_rope"), v.sel(mount="six_axis"), rtol=1e-9, err_msg=name)
        law = same[f"law_{name}"]  # skyhook_30 on each mount (c_off 3)
        np.testing.assert_allclose(law.sel(mount="wire_rope"), law.sel(mount="six_axis"), rtol=1e-9, err_msg=name)
    on = same.law_on_fraction
    np.testing.assert_array_equal(on.sel(mount="wire_rope"), on.sel(mount="six_axis"))
    assert 0.2 < on.sel(mount="six_axis").item() < 0.8  # the law switches
    moved = _wire_rope_runs(0.3, 2e-4)
    constant = moved.los_std.sel(payload="gimbal", damping=3.0)
    assert abs(float(constant.sel(mount="wire_rope") / constant.sel(mount="six_axis")) - 1) > 0.05
    law = moved.law_los_std.sel(law="skyhook_30")
    assert abs(float(law.sel(mount="wire_rope") / law.sel(mount="six_axis")) - 1) > 0.05
