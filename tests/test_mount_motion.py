"""The platform under 6-DOF mount motion and gravity: closed forms of rigid-body kinematics and statics.

Every expected value is a closed form: a rotation of the mount turns a rotationally rigid platform's line of sight
by the same angle; the isolator's spring sags m g / K under the weight and deflects m g sin(phi) / K laterally at
a roll phi; the servos' integral terms remove a static error; the masses are summed from the config.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import PLATFORM, platform_params, sine_yz

from uavdamp.contract import MountMotion
from uavdamp.damping.laws import Constant
from uavdamp.platform import ExudynPlant, LinearPlant
from uavdamp.platform.params import StrokeBudget
from uavdamp.platform.stroke import manoeuvre_stroke, static_sag, stroke_budget

G = 9.80665
MASS = sum(PLATFORM["structure"][k] for k in ("base_mass_kg", "intermediate_mass_kg", "pitch_body_mass_kg"))
MASS += PLATFORM["structure"]["camera_mass_kg"]  # kg: everything the isolator carries


def _rotation(axis: int, angle: np.ndarray) -> MountMotion:
    rotation = np.zeros((3, angle.size))
    rotation[axis] = angle
    return MountMotion(np.zeros_like(rotation), rotation)


def _settle_then_hold(time: np.ndarray, value: float, ramp_s: float = 2.0) -> np.ndarray:
    """0 -> value over ramp_s with zero rate at both ends (half cosine), then held."""
    s = np.clip(time / ramp_s, 0.0, 1.0)
    return value * 0.5 * (1 - np.cos(np.pi * s))


# ------------------------------------------------------------------------------ rotation reaches the line of sight


@pytest.mark.parametrize("mount", ["rigid", "isolated"])
@pytest.mark.parametrize(("axis", "variable", "sign"), [(2, "camera_yaw", 1.0), (1, "camera_pitch", 1.0)])
def test_mount_rotation_turns_the_line_of_sight_one_to_one(mount, axis, variable, sign):
    """Without gravity, a 0.2 Hz rotation (1/20 of the lowest mode, 4.5 Hz): the camera's inertial line of sight
    turns with the mount within the quasi-static bound (0.2 / 4.5)^2 = 0.2 %, isolated or not (the isolator is
    rotationally rigid). Yaw about z turns the azimuth; pitch about y (x towards -z) the elevation, positive down."""
    p = platform_params(gravity_m_s2=0.0)
    time = np.arange(0.0, 10.0 + 1e-9, p.time_step)
    angle = 1e-3 * np.sin(2 * np.pi * 0.2 * time)
    law = {} if mount == "rigid" else {"stiffness": 1000.0, "law": Constant(20.0)}
    ds = ExudynPlant(p, mount=mount).run(time, _rotation(axis, angle), **law)
    error = np.abs(ds[variable].values - sign * angle).max()
    assert error < (0.2 / 4.5) ** 2 * 1e-3, error  # measured 1.2e-6 (yaw), 1.8e-6 rad (pitch)
    other = "camera_pitch" if variable == "camera_yaw" else "camera_yaw"
    assert np.abs(ds[other].values).max() < 1e-2 * 1e-3  # the other angle moves at second order only


def test_mount_roll_leaves_the_line_of_sight_and_turns_the_weight():
    """A static roll phi (about the line of sight, x) leaves the line of sight where it was; with gravity the
    isolator, turning with the mount, sees the weight's lateral part m g sin(phi): stroke y = -m g sin(phi) / K."""
    p = platform_params()
    time = np.arange(0.0, 12.0 + 1e-9, p.time_step)
    phi, k = 0.01, 1000.0
    c = 2 * np.sqrt(k * MASS)  # critically damped: settled within the run
    ds = ExudynPlant(p).run(time, _rotation(0, _settle_then_hold(time, phi)), stiffness=k, law=Constant(c))
    late = time > 8.0
    stroke_y = ds.isolator_stroke.sel(axis="y").values[late]
    np.testing.assert_allclose(stroke_y, -MASS * G * np.sin(phi) / k, rtol=0.01)
    # the yaw servo's integral term removes the weight's yaw torque on the camera (its COM forward of the axis)
    assert np.abs(ds.camera_yaw.values[late]).max() < 0.05 * phi


def test_the_pitch_servo_integral_term_brings_the_camera_to_the_mount_pitch():
    """With gravity, a tilted mount tilts the weight on the pitch link (COM above the axis): the P term alone would
    leave a static error; the I term removes it, so the line of sight settles at the mount's pitch."""
    p = platform_params()
    time = np.arange(0.0, 30.0 + 1e-9, p.time_step)
    theta = 0.02
    ds = ExudynPlant(p, mount="rigid").run(time, _rotation(1, _settle_then_hold(time, theta)))
    pitch = ds.camera_pitch.values
    assert np.abs(pitch[time > 25.0] - theta).max() < 0.01 * theta
    assert np.abs(pitch - theta)[(time > 2.0) & (time < 4.0)].max() > 0.02 * theta  # before the I term acts


# ------------------------------------------------------------------------------------------------------ gravity


def test_static_forces_carry_the_weight_of_each_joint():
    """The isolator z joint carries the whole platform (m g), the structural spring everything above the base."""
    model = ExudynPlant(platform_params()).model
    forces, idx = model.static_forces, model.link_index
    s = PLATFORM["structure"]
    assert forces[idx["iso_z"]] == pytest.approx(MASS * G, rel=1e-9)
    above = s["intermediate_mass_kg"] + s["pitch_body_mass_kg"] + s["camera_mass_kg"]
    assert forces[idx["displacement"]] == pytest.approx(above * G, rel=1e-9)
    assert forces[idx["iso_y"]] == 0.0


def test_the_spring_sags_m_g_over_k_when_it_carries_the_weight():
    """Without the static support on the isolator, the platform settles m g / K lower: the sag the stroke budget
    reports for weight_support: spring."""
    p, k = platform_params(), 1000.0
    sim = ExudynPlant(p)
    forces = sim.model.static_forces.copy()
    forces[sim.model.link_index["iso_z"]] = 0.0
    sim.model.static_forces = forces
    time = np.arange(0.0, 4.0 + 1e-9, p.time_step)
    ds = sim.run(time, MountMotion.planar(0 * time, 0 * time), stiffness=k, law=Constant(2 * np.sqrt(k * MASS)))
    settled = ds.isolator_stroke.sel(axis="z").values[time > 3.0]
    np.testing.assert_allclose(settled, -MASS * G / k, rtol=1e-3)
    budget = StrokeBudget(weight_support="spring", max_stroke=0.05, manoeuvre_g=0.1)
    assert static_sag(budget, p, k) == pytest.approx(MASS * G / k, rel=1e-12)


def test_gravity_leaves_the_planar_response_unchanged_to_second_order():
    """About the static equilibrium the weight is carried by constant joint forces and the pitch servo's gain holds
    the pendulum term, so a planar run with gravity equals one without up to terms of second order in the angles."""
    time, y, z = sine_yz(7.0, 8.0, 1.3e-3, 2.0, 2e-3)
    runs = [
        ExudynPlant(platform_params(gravity_m_s2=g)).run(
            time, MountMotion.planar(y, z), stiffness=100.0, law=Constant(5.0)
        )
        for g in (0.0, G)
    ]
    angle = float(max(np.abs(runs[0].camera_pitch).max(), np.abs(runs[0].camera_yaw).max()))  # rad, ~4e-3
    for name in ("camera_displacement", "camera_pitch", "camera_yaw", "isolator_stroke"):
        peak = float(np.abs(runs[0][name]).max())
        assert float(np.abs(runs[1][name] - runs[0][name]).max()) < angle * peak, name  # measured <= 6e-5 peak


# ------------------------------------------------------------------------------------ the linear plant, 6-DOF


def _six_dof(time: np.ndarray, scale: float) -> MountMotion:
    lines = [(6.5, 0.3e-3, 0.3), (7.0, 1.3e-3, 0.0), (8.0, 1.3e-3, 0.7)]
    translation = np.stack([a * np.sin(2 * np.pi * f * time + ph) for f, a, ph in lines])
    rotation = np.stack([2e-4 * np.sin(2 * np.pi * f * time + ph) for f, ph in ((7.2, 0.1), (6.8, 1.0), (7.5, 2.0))])
    return MountMotion(scale * translation, scale * rotation)


def test_linear_plant_matches_exudyn_under_6dof_mount_motion():
    """Translation on three axes and rotation about three (0.2 mrad), 0.5 ms step (Exudyn's step error small):
    every output within 1 % + the largest camera angle (rad: the size of Exudyn's geometric nonlinearity relative
    to the linear terms) of its peak, and at a quarter of the amplitude the largest gap about 4 times smaller:
    what is left is the nonlinearity (measured 0.65 % then 0.16 %, camera yaw)."""
    p = platform_params(time_step_s=5e-4)
    time = np.arange(0.0, 2.0 + 1e-9, p.time_step)
    sim = ExudynPlant(p)
    plant = LinearPlant(sim.model)
    names = ("camera_displacement", "camera_yaw", "camera_pitch", "base_displacement", "isolator_stroke")
    worst = []
    for scale in (1.0, 0.25):
        ref, lin = (q.run(time, _six_dof(time, scale), stiffness=100.0, law=Constant(5.0)) for q in (sim, plant))
        angle = float(max(np.abs(ref.camera_pitch).max(), np.abs(ref.camera_yaw).max()))
        gaps = {n: float(np.abs(lin[n] - ref[n]).max() / np.abs(ref[n]).max()) for n in names}
        if scale == 1.0:
            for name, value in gaps.items():
                assert value < 0.01 + angle, (name, value, angle)
        worst.append(max(gaps.values()))
    assert worst[1] < worst[0] / 2.5, worst


# ------------------------------------------------------------------------------------------- the stroke budget


@pytest.mark.parametrize("support", ["spring", "preloaded"])
def test_stroke_budget_adds_sag_manoeuvre_and_the_dynamic_stroke(support):
    import xarray as xr

    p = platform_params()
    budget = StrokeBudget(weight_support=support, max_stroke=0.05, manoeuvre_g=0.1)
    stiffness = xr.DataArray([10.0, 1000.0], dims="stiffness", coords={"stiffness": [10.0, 1000.0]})
    peak = xr.DataArray(
        [[[1e-3, 2e-3], [np.nan, np.nan]], [[1e-3, 2e-3], [np.nan, np.nan]]],
        dims=("stiffness", "strategy", "axis"),
        coords={"stiffness": [10.0, 1000.0], "strategy": ["passive", "rigid"], "axis": ["y", "z"]},
    )
    ds = stroke_budget(budget, p, stiffness, peak)
    sag = MASS * G / stiffness.values if support == "spring" else np.zeros(2)
    manoeuvre = MASS * 0.1 * G / stiffness.values
    np.testing.assert_allclose(ds.static_sag.values, sag, rtol=1e-12)
    np.testing.assert_allclose(manoeuvre_stroke(budget, p, stiffness.values), manoeuvre, rtol=1e-12)
    needed = ds.stroke_needed.sel(strategy="passive")
    np.testing.assert_allclose(needed.sel(axis="y"), manoeuvre + 1e-3, rtol=1e-12)
    np.testing.assert_allclose(needed.sel(axis="z"), sag + manoeuvre + 2e-3, rtol=1e-12)
    # K = 10 N/m: 0.157 m for a 0.1 g manoeuvre alone, infeasible either way; K = 1000 N/m fits
    assert ds.stroke_feasible.sel(strategy="passive").values.tolist() == [0.0, 1.0]
    assert np.isnan(ds.stroke_feasible.sel(strategy="rigid")).all()  # no isolator, no stroke
    for var in ds.data_vars.values():
        assert {"units", "long_name"} <= set(var.attrs)


def test_steady_stroke_is_the_linear_plants_steady_state_amplitude():
    """The frequency response's bound (the sum of what each input drives on a stroke axis) against the steady state
    of an exact time-domain run of the same plant: least-squares amplitudes at f_y and f_z over the last 2 s."""
    from uavdamp.platform.stroke import steady_stroke

    p = platform_params(time_step_s=1e-3)
    plant, k, c, fy, fz, a = LinearPlant.from_params(p), 1000.0, 20.0, 23.0, 31.0, 1e-5
    time, y, z = sine_yz(fy, fz, a, 6.0, p.time_step)
    ds = plant.run(time, MountMotion.planar(y, z), stiffness=k, law=Constant(c))
    late = time > 4.0  # 2 m / C = 0.16 s decay time: the start-up is gone
    t = time[late]
    basis = np.column_stack([f(2 * np.pi * q * t) for q in (fy, fz) for f in (np.sin, np.cos)])
    measured = []
    for axis in ("y", "z"):
        coef = np.linalg.lstsq(basis, ds.isolator_stroke.sel(axis=axis).values[late], rcond=None)[0]
        measured.append(np.hypot(*coef[:2]) + np.hypot(*coef[2:]))
    np.testing.assert_allclose(steady_stroke(plant, k, c, fy, fz, a), measured, rtol=1e-3)
