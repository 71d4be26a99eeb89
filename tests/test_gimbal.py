"""The gyro-stabilised gimbal: inertias, the gain design, the loop's sensitivity, saturation and imbalance, each
against a closed form or an independent computation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uavdamp.platform.gimbal import GimbalParams, axis_inertia, axis_model, design, imbalance_torque, plant_tf
from uavdamp.platform.gimbal_loop import design_report, sensitivity
from uavdamp.platform.gimbal_sim import simulate, simulate_many
from uavdamp.platform.imu import ImuParams
from uavdamp.settings import ConfigError

P = GimbalParams()
G = design(P)


def _fit(time, y, freq_hz, start):
    """Amplitude of the freq_hz sine in y over time >= start (least squares with an offset)."""
    sel = time >= start
    w = 2 * np.pi * freq_hz
    m = np.column_stack([np.sin(w * time[sel]), np.cos(w * time[sel]), np.ones(sel.sum())])
    c, *_ = np.linalg.lstsq(m, y[sel], rcond=None)
    return math.hypot(c[0], c[1])


def _zeros(time):
    return np.zeros((3, time.size))


def test_axis_inertias_from_the_camera_box_and_the_brackets():
    """Camera 0.9 kg box 0.10 x 0.06 x 0.06 m: m/12 (b^2 + c^2) = 5.4e-4 (x), m/12 (a^2 + c^2) = 1.02e-3 (y, z)
    kg m2, plus the stated brackets at and inside each axis."""
    assert axis_inertia(P, "pitch") == pytest.approx(1.02e-3 + 2.0e-4, rel=1e-12)
    assert axis_inertia(P, "roll") == pytest.approx(5.4e-4 + 1.5e-4 + 6.0e-4, rel=1e-12)
    assert axis_inertia(P, "yaw") == pytest.approx(1.02e-3 + 2.0e-4 + 5.0e-4 + 8.0e-4, rel=1e-12)
    two_axis = GimbalParams(axes=("roll", "pitch"))
    assert axis_inertia(two_axis, "roll") == pytest.approx(5.4e-4 + 1.5e-4 + 6.0e-4, rel=1e-12)
    offset = GimbalParams(imbalance_m=(0.0, 0.0, 0.01))  # parallel axes: + m r^2 about x and y, not z
    assert axis_inertia(offset, "pitch") - axis_inertia(P, "pitch") == pytest.approx(0.9e-4, rel=1e-9)
    assert axis_inertia(offset, "yaw") == pytest.approx(axis_inertia(P, "yaw"), rel=1e-12)


def test_imbalance_torque_signs():
    """At rest the specific force is +g z: a centre of mass forward of the axes (r_x > 0) pitches the camera nose
    down (positive pitch) with m g r_x; one to the left (r_y > 0) rolls it right (negative roll)."""
    g = np.array([0.0, 0.0, 9.81])
    forward, left = GimbalParams(imbalance_m=(0.01, 0, 0)), GimbalParams(imbalance_m=(0, 0.01, 0))
    assert imbalance_torque(forward, "pitch", g) == pytest.approx(0.9 * 9.81 * 0.01)
    assert imbalance_torque(left, "roll", g) == pytest.approx(-0.9 * 9.81 * 0.01)


def _zoh_by_poisson_sum(num_s, den_s, freq_hz, period, terms=200_000):
    """Zero-order-hold equivalent of a strictly proper P(s) at z = e^{j w T}, independently of any
    discretisation routine: (1 - e^{-j w T}) (1/T) sum_k P(j w_k) / (j w_k), w_k = w + 2 pi k / T (impulse
    modulation of the step response, continuous at 0)."""
    w = 2 * np.pi * freq_hz + 2 * np.pi * np.arange(-terms, terms + 1) / period
    s = 1j * w
    p = np.polyval(num_s, s) / np.polyval(den_s, s)
    return (1 - np.exp(-2j * np.pi * freq_hz * period)) / period * np.sum(p / s)


@pytest.mark.parametrize("axis", ["roll", "pitch", "yaw"])
def test_the_rate_loop_meets_its_specified_crossover_and_phase_margin(axis):
    """The rate loop z^-1 PI(z) P_g(z) built independently (gyro / torque = F(s) / (J s + c), F the 256 Hz
    first-order filter, zero-order hold by the Poisson sum) has |L| = 1 at the specified 40 Hz with 180 + arg L =
    the specified 50 deg, and |L| crosses 1 nowhere else in 1-400 Hz."""
    i = ("roll", "pitch", "yaw").index(axis)
    g, period = G[axis], P.period
    j, c = axis_inertia(P, axis), P.friction
    wf = 2 * np.pi * 256.0
    num_s, den_s = [wf], np.polymul([j, c], [1.0, wf])

    def loop(f):
        z = np.exp(2j * np.pi * f * period)
        pi = g.kp + g.ki * period * z / (z - 1)
        return pi / z * _zoh_by_poisson_sum(num_s, den_s, f, period)

    f_c, pm = P.rate_crossover_hz[i], P.phase_margin_deg[i]
    assert abs(loop(f_c)) == pytest.approx(1.0, abs=1e-5)
    assert 180 + math.degrees(np.angle(loop(f_c))) == pytest.approx(pm, abs=1e-3)
    grid = np.geomspace(1.0, 400.0, 60)
    above = np.array([abs(loop(f)) > 1 for f in grid])
    assert np.all(above[grid < 0.98 * f_c]) and not np.any(above[grid > 1.02 * f_c])


def test_the_report_gives_the_achieved_margins():
    """The report's margins, found on the discrete loops: the rate loop's as specified, the attitude loop's
    crossover the stated fraction, the whole loop stable."""
    r = design_report(P)
    assert np.allclose(r.rate_crossover_hz, 40.0, rtol=1e-6)
    assert np.allclose(r.rate_phase_margin_deg, 50.0, atol=1e-4)
    assert np.allclose(r.attitude_crossover_hz, 0.2 * 40.0, rtol=1e-6)
    assert bool(r.stable.all())
    assert r.sensitivity_magnitude.attrs["units"] == "1"


def _sine_rotation(axis_index, freq_hz, amplitude, time):
    w = 2 * np.pi * freq_hz
    rotation, rate = _zeros(time), _zeros(time)
    rotation[axis_index] = amplitude * np.sin(w * time)
    rate[axis_index] = amplitude * w * np.cos(w * time)
    return rotation, rate


@pytest.mark.parametrize("freq_hz", [5.0, 28.0, 80.0])
def test_stabilised_axis_response_to_base_rotation_is_the_loop_sensitivity(freq_hz):
    """A sine base rotation about pitch reaches the camera through the joint's friction: with the motor off the
    camera follows c / (J s + c) of it (J theta'' = -c (theta' - omega_b)); the stabilised camera follows
    S(e^{j w T}) times that. Simulated (noise off) within 1 % of |S| |c / (J j w + c)|, S from the designed
    loop's scipy dlti."""
    h = P.period / 20
    time = np.arange(0.0, 2.0, h)
    amplitude = 1e-3
    rotation, rate = _sine_rotation(1, freq_hz, amplitude, time)
    ds = simulate(P, time, rotation, rate, _zeros(time), sensor_errors=False)
    response = _fit(time, ds.line_of_sight.sel(axis="pitch").values, freq_hz, 1.0) / amplitude
    w = 2 * np.pi * freq_hz
    open_loop = abs(P.friction / (1.22e-3 * 1j * w + P.friction))  # J_pitch by hand (test above)
    _, s = sensitivity(P, G["pitch"]).freqresp(w=[w * P.period])
    assert response == pytest.approx(abs(s[0]) * open_loop, rel=0.01)
    assert int(ds.saturation_count.sum()) == 0


def test_a_big_base_step_saturates_and_is_flagged_a_small_one_is_not():
    """A 10 g lateral step on a camera 5 mm forward of the yaw axis needs m r a = 0.44 N m > the 0.24 N m limit;
    0.1 g needs 4.4 mN m."""
    p = GimbalParams(imbalance_m=(0.005, 0.0, 0.0))
    time = np.arange(0.0, 0.3, p.period / 5)
    for accel, saturated in ((98.1, True), (0.981, False)):
        acceleration = _zeros(time)
        acceleration[1] = np.where(time > 0.05, accel, 0.0)
        ds = simulate(p, time, _zeros(time), _zeros(time), acceleration, sensor_errors=False)
        assert bool(ds.attrs["saturated"]) is saturated
        assert (int(ds.saturation_count.sel(axis="yaw")) > 0) is saturated
        assert float(abs(ds.motor_torque).max()) <= p.torque_limit * (1 + 1e-12)
        assert ds.torque_saturated.any().item() is saturated


def test_a_balanced_gimbal_does_not_see_translation_through_torque():
    """Balanced (r = 0), gyro-only estimator: any base translation leaves the line of sight at exactly 0; with
    the accelerometer aiding, a vertical one still does (atan2 of no lateral force)."""
    time = np.arange(0.0, 0.3, P.period / 5)
    acceleration = _zeros(time)
    acceleration[:, time > 0.05] = np.array([[3.0], [-2.0], [5.0]])
    gyro_only = GimbalParams(estimator_crossover_hz=0.0)
    ds = simulate(gyro_only, time, _zeros(time), _zeros(time), acceleration, sensor_errors=False)
    assert float(abs(ds.line_of_sight).max()) == 0.0
    vertical = _zeros(time)
    vertical[2] = acceleration[2]
    ds = simulate(P, time, _zeros(time), _zeros(time), vertical, sensor_errors=False)
    assert float(abs(ds.line_of_sight).max()) == 0.0


@pytest.mark.parametrize("freq_hz", [1.0, 2.0])
def test_an_imbalanced_gimbal_at_low_frequency(freq_hz):
    """Camera 5 mm forward of the yaw axis, lateral base acceleration a_y = sin(w t) m s-2: torque -m r_x a_y on
    yaw, and theta = m r a / (J s^2 + c s + (K_p + K_i / s)(s + K_a)) with the cascade's continuous equivalent.
    The discrete loop departs from it by its delays and holds, relative error of order w T: within w T."""
    p = GimbalParams(imbalance_m=(0.005, 0.0, 0.0))
    g = design(p)["yaw"]
    time = np.arange(0.0, 2.0, p.period / 10)
    acceleration = _zeros(time)
    w = 2 * np.pi * freq_hz
    acceleration[1] = np.sin(w * time)
    ds = simulate(p, time, _zeros(time), _zeros(time), acceleration, sensor_errors=False)
    amplitude = _fit(time, ds.line_of_sight.sel(axis="yaw").values, freq_hz, 1.0)
    s = 1j * w
    j = 1.02e-3 + 2.0e-4 + 5.0e-4 + 8.0e-4 + 0.9 * 0.005**2  # + m r_x^2 about z
    expected = 0.9 * 0.005 / abs(j * s * s + p.friction * s + (g.kp + g.ki / s) * (s + g.ka))
    assert amplitude == pytest.approx(expected, rel=w * p.period)


def test_accelerometer_aiding_reads_lateral_acceleration_as_tilt():
    """Balanced, crossover f_x = 0.5 Hz, a slow fore-aft acceleration a_x: the estimate theta - LP(s) a_x / g is
    held at 0, so the camera pitches by (a_x / g) / (1 + s tau), tau = 1 / (2 pi f_x); the attitude loop's error
    at f is about f / f_a of it (f_a = 8 Hz): within 2 f / f_a."""
    p = GimbalParams(estimator_crossover_hz=0.5)
    freq_hz = 0.2
    time = np.arange(0.0, 12.0, p.period)
    acceleration = _zeros(time)
    w = 2 * np.pi * freq_hz
    acceleration[0] = np.sin(w * time)
    ds = simulate(p, time, _zeros(time), _zeros(time), acceleration, sensor_errors=False)
    amplitude = _fit(time, ds.line_of_sight.sel(axis="pitch").values, freq_hz, 2.0)
    tau = 1 / (2 * np.pi * 0.5)
    expected = 1.0 / p.gravity / abs(1 + 1j * w * tau)
    assert amplitude == pytest.approx(expected, rel=2 * freq_hz / 8.0)


def test_plant_transfer_is_strictly_proper():
    num, den = plant_tf(axis_model(P, "pitch"), "gyro", P.period)
    assert num[0] == 0.0 and den[0] == 1.0


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"axes": ("roll",)}, "gimbal.axes"),
        ({"axes": ("roll", "tilt")}, "gimbal.axes"),
        ({"friction": -1.0}, "gimbal.friction"),
        ({"rate_crossover_hz": (40.0, 300.0, 40.0)}, "gimbal.rate_crossover_hz"),
    ],
)
def test_bad_gimbal_parameters_name_the_key(kwargs, key):
    with pytest.raises(ConfigError, match=key):
        GimbalParams(**kwargs)


def test_an_infeasible_margin_names_the_key():
    """85 deg at 200 Hz: the delays alone take more phase than the PI can leave."""
    with pytest.raises(ConfigError, match="gimbal.phase_margin_deg"):
        design(GimbalParams(rate_crossover_hz=(200.0, 200.0, 200.0), phase_margin_deg=(85.0, 85.0, 85.0)))


def test_the_time_step_must_divide_the_loop_period():
    time = np.arange(0.0, 0.01, 0.0003)
    with pytest.raises(ValueError, match="whole multiple"):
        simulate(P, time, _zeros(time), _zeros(time), _zeros(time))


@pytest.mark.parametrize("height", [0.005, -0.005])
def test_gravity_on_an_offset_camera_is_a_pendulum(height):
    """Motor off, no friction: a centre of mass h above the pitch axis is an inverted pendulum, poles
    +/- sqrt(m g h / J) (real, one unstable); below it, a pendulum at sqrt(m g |h| / J) rad s-1."""
    p = GimbalParams(imbalance_m=(0.0, 0.0, height), friction=0.0)
    model = axis_model(p, "pitch")
    poles = np.linalg.eigvals(model.a[:2, :2])
    rate = math.sqrt(0.9 * p.gravity * abs(height) / (1.22e-3 + 0.9 * height**2))
    expected = [-rate, rate] if height > 0 else [-1j * rate, 1j * rate]
    assert np.allclose(np.sort_complex(poles), np.sort_complex(np.array(expected, dtype=complex)), rtol=1e-12)


def test_the_simulation_dataset_names_its_units_and_axes():
    """A two-axis gimbal reports its two axes; every variable carries units and long_name; a seeded generator
    gives the same noisy run twice, another seed another run."""
    p = GimbalParams(axes=("pitch", "roll"))
    time = np.arange(0.0, 0.05, p.period / 2)
    rotation, rate = _sine_rotation(0, 10.0, 1e-3, time)

    def run(seed):
        return simulate(p, time, rotation, rate, _zeros(time), rng=np.random.default_rng(seed))

    ds = run(4)
    assert list(ds.axis.values) == ["roll", "pitch"]
    for name in ds.data_vars:
        assert {"units", "long_name"} <= set(ds[name].attrs), name
    assert ds.line_of_sight.attrs["units"] == "rad"
    assert np.array_equal(ds.line_of_sight, run(4).line_of_sight)
    assert not np.array_equal(ds.line_of_sight, run(5).line_of_sight)


def test_a_gyro_bias_drifts_yaw_and_tilts_roll_and_pitch_by_the_filters_time_constant():
    """A constant gyro bias b on a still mount, no other sensor error. The rate PI holds the reading at the
    attitude loop's command -K_a theta_est, so at rest theta_est = -b / K_a. Yaw has no reference: its estimate
    integrates the reading, which is then zero, so the camera turns at -b (slope within 1 %). Roll and pitch are
    aided by the accelerometer below f_x: the estimate settles at the true tilt plus b tau, tau = 1 / (2 pi f_x),
    so the camera settles at -b (tau + 1 / K_a) (within 1 % after 10 tau)."""
    b = math.radians(0.05)
    imu = ImuParams(gyro_noise_density=0.0, accel_noise_density=0.0, bits=0, gyro_bias=(b, b, b))
    p = GimbalParams(estimator_crossover_hz=0.5, imu=imu)
    time = np.arange(0.0, 4.0, p.period)
    ds = simulate(p, time, _zeros(time), _zeros(time), _zeros(time), sensor_errors=True)
    late = time >= 3.0
    yaw = ds.line_of_sight.sel(axis="yaw").values[late]
    assert np.polyfit(time[late], yaw, 1)[0] == pytest.approx(-b, rel=0.01)
    tau, gains = 1 / (2 * np.pi * 0.5), design(p)
    for axis in ("roll", "pitch"):
        expected = -b * (tau + 1 / gains[axis].ka)
        assert ds.line_of_sight.sel(axis=axis).values[late].mean() == pytest.approx(expected, rel=0.01), axis


def test_runs_side_by_side_are_their_own_runs():
    """`simulate_many` steps the cascades of several runs together: each is its own `simulate` (IMU without
    quantisation, so that the loop is continuous in its inputs: only the order of a matrix product's sums may differ,
    and its rounding, accumulated over 1600 steps and cancelled in the line of sight (the base's angle less the gimbal's
    correction), measured 2.7e-12 of a signal's range at worst: 1e-9 allowed), saturation included (the strongest
    run reaches the torque limit, the others stay below it: a camera 5 mm forward of the yaw axis under 1, 10 and
    100 m s-2 of lateral acceleration needs up to 4.4 mN m, 44 mN m and 0.44 N m against the 0.24 N m limit); and it
    asks for one generator per run."""
    p = GimbalParams(imbalance_m=(0.005, 0.0, 0.0))
    time = np.arange(1601) * p.period / 5
    bases = []
    for k, level in enumerate((1.0, 10.0, 100.0)):
        rotation = np.zeros((3, time.size))
        rotation[0] = 1e-3 * np.sin(2 * np.pi * (6 + 3 * k) * time)
        rotation[1] = 1e-3 * np.sin(2 * np.pi * (11 - k) * time + 0.3)
        rate = np.gradient(rotation, time, axis=1)
        acceleration = np.zeros((3, time.size))
        acceleration[1] = level * np.sin(2 * np.pi * 7 * time)
        bases.append((rotation, rate, acceleration))
    together = simulate_many(p, time, bases, sensor_errors=False, rngs=[np.random.default_rng(0) for _ in bases])
    saturated = []
    for base, ds in zip(bases, together, strict=True):
        alone = simulate(p, time, *base, sensor_errors=False)
        for name in ("line_of_sight", "motor_torque", "attitude_estimate"):
            scale = float(np.ptp(alone[name].values)) + 1e-300
            assert float(np.abs(ds[name] - alone[name]).max()) <= 1e-9 * scale, name
        np.testing.assert_array_equal(ds.torque_saturated.values, alone.torque_saturated.values)
        saturated.append(int(ds.attrs["saturated"]))
    assert saturated == [0, 0, 1]
    with pytest.raises(ValueError, match="one generator per base motion"):
        simulate_many(p, time, bases, rngs=[np.random.default_rng(0)])
