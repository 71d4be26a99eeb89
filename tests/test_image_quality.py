"""Image metrics against closed forms: blur, frame windows, frame jitter, MTF, line of sight."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uavdamp.camera import image_quality as iq
from uavdamp.camera.optics import CameraModel

T = 4.0e-3  # s, exposure
FPS = 25.0  # Hz: a frame period of 0.04 s, a whole number of samples at the steps used below


def _camera(**change) -> CameraModel:
    values = dict(
        focal_length_m=6.0e-3,
        pixel_pitch_m=2.9e-6,
        image_width_px=1920,
        image_height_px=1080,
        exposure_s=T,
        frame_rate_hz=FPS,
        scene_distance_m=20.0,
    )
    values.update(change)
    return CameraModel(**values)


CAM = _camera()
F = CAM.focal_px


def _time(n_frames: int, dt: float) -> np.ndarray:
    """Samples from 0 to the end of the n-th frame's exposure, step dt."""
    return np.arange(round(((n_frames - 1) / FPS + T) / dt) + 1) * dt


def _response(time, yaw=0.0, pitch=0.0, y=0.0, z=0.0):
    full = [np.broadcast_to(np.asarray(x, dtype=float), time.shape) for x in (yaw, pitch, y, z)]
    return time, np.stack(full[2:]), full[0], full[1]


def test_constant_angular_rate_gives_f_omega_t():
    """Yaw (and pitch) at constant rate w: every frame's blur is f_px w T; at 10 mrad the tan(w t) of the
    exact projection makes it f_px (tan(w (t_k + T)) - tan(w t_k)), within sec^2(10 mrad) - 1 = 1e-4 of
    f_px w T here. Monotone motion: the path length equals the extent."""
    time, w = _time(6, 1e-4), 0.05  # rad s-1; 0.05 x 0.204 s = 10 mrad at the end
    t_k = np.arange(6) / FPS
    for angles in ({"yaw": w * time}, {"pitch": -w * time}):
        frames = iq.frame_metrics(*_response(time, **angles), CAM)
        assert frames.blur_px == pytest.approx(np.full(6, F * w * T), rel=1.2e-4)
        assert frames.blur_px == pytest.approx(F * (np.tan(w * (t_k + T)) - np.tan(w * t_k)), rel=1e-9)
        assert frames.path_px == pytest.approx(frames.blur_px, rel=1e-12)


def test_linear_image_motion_blur_jitter_centroid_exact():
    """u = r t: blur r T, centroid r (t_k + T/2), consecutive centroids r / fps apart, smear r T, sigma 0."""
    time, r = _time(5, 1e-4), 300.0  # px s-1
    frames = iq.frames_from_image_path(time, r * time, np.zeros_like(time), CAM)
    t_k = np.arange(5) / FPS
    assert frames.start_s == pytest.approx(t_k, abs=1e-12)
    assert frames.blur_px == pytest.approx(np.full(5, r * T), rel=1e-9)
    assert frames.centroid_px[:, 0] == pytest.approx(r * (t_k + T / 2), rel=1e-9)
    assert frames.smear_px == pytest.approx(np.full(5, r * T), rel=1e-9)
    assert frames.sigma_px == pytest.approx(np.zeros(5), abs=1e-9)
    summary = iq.frame_summary(frames, 1.0)
    assert summary["frame_jitter_rms"][0] == pytest.approx(r / FPS, rel=1e-9)
    assert summary["centroid_std"][0] == pytest.approx(r / FPS * np.std(np.arange(5)), rel=1e-9)


def test_fast_sinusoidal_jitter_extent_is_two_a_f():
    """Yaw A cos(2 pi f_j (t - T/2)), f_j = 1 kHz >> 1/T: each 4 ms exposure holds 4 whole periods.

    The image point u = f_px tan(psi) ~ f_px A cos(...) sweeps between -f_px A and +f_px A, so the streak
    it leaves (our headline blur, the extent) is 2 A f_px: the issue's "close to 2 A f_px" is this
    extent-type blur. The path length runs 4 A f_px per period, here 16 A f_px, and grows with the
    exposure. Samples (10 us) fall on every extremum, so both are exact up to tan(A) = A (1 + 3e-9).
    """
    time, amp, f_j = _time(5, 1e-5), 1.0e-4, 1000.0
    yaw = amp * np.cos(2 * np.pi * f_j * (time - T / 2))
    frames = iq.frame_metrics(*_response(time, yaw=yaw), CAM)
    assert frames.blur_px == pytest.approx(np.full(5, 2 * amp * F), rel=1e-6)
    assert frames.path_px == pytest.approx(np.full(5, 4 * amp * F * f_j * T), rel=1e-6)


def test_pure_translation_gives_f_d_over_d():
    """The camera moves d = (1, 2) mm in (y, z) during each exposure: blur f_px |d| / D (exact at zero angles)."""
    time, d = _time(4, 1e-4), np.array([1e-3, 2e-3])
    phase = np.clip((time * FPS) % 1.0 / (T * FPS), 0.0, 1.0) + np.floor(time * FPS + 1e-9)  # ramps in exposures
    frames = iq.frame_metrics(*_response(time, y=d[0] * phase, z=d[1] * phase), CAM)
    assert frames.blur_px == pytest.approx(np.full(4, F * np.hypot(*d) / CAM.scene_distance_m), rel=1e-6)


@pytest.mark.parametrize("nu", [0.5, 0.25])
def test_mtf_forms_against_their_formulas(nu):
    d, sigma = 1.3, 0.4  # px
    assert iq.motion_mtf(nu, d) == pytest.approx(abs(math.sin(math.pi * nu * d) / (math.pi * nu * d)), rel=1e-12)
    assert iq.jitter_mtf(nu, sigma) == pytest.approx(math.exp(-2 * math.pi**2 * sigma**2 * nu**2), rel=1e-12)
    assert iq.motion_mtf(nu, 0.0) == 1.0 and iq.jitter_mtf(nu, 0.0) == 1.0


def test_frame_mtf_of_pure_smear_and_pure_jitter():
    """Smear of 1 px, no jitter: MTF(0.5) = sinc(0.5) = 2/pi. A cosine of a = 0.5 px symmetric about each
    exposure's middle over whole periods: no linear part, sigma = a / sqrt(2), MTF = exp(-pi^2 a^2 / 4)."""
    time = _time(5, 1e-5)
    smear = iq.frames_from_image_path(time, time / T, np.zeros_like(time), CAM)
    assert smear.mtf_nyquist == pytest.approx(np.full(5, 2 / np.pi), rel=1e-9)
    a = 0.5
    v = a * np.cos(2 * np.pi * 1000.0 * (time - T / 2))
    jitter = iq.frames_from_image_path(time, np.zeros_like(time), v, CAM)
    assert jitter.smear_px == pytest.approx(np.zeros(5), abs=1e-9)
    assert jitter.sigma_px == pytest.approx(np.full(5, a / np.sqrt(2)), rel=1e-9)
    assert jitter.mtf_nyquist == pytest.approx(np.full(5, np.exp(-(np.pi**2) * a**2 / 4)), rel=1e-9)


def _steps(blurs, dt=1e-4):
    """u rises by blurs[k] during frame k's exposure and stays put between exposures."""
    time = _time(len(blurs), dt)
    knots_t = np.ravel([[k / FPS, k / FPS + T] for k in range(len(blurs))])
    knots_u = np.ravel([[s - b, s] for s, b in zip(np.cumsum(blurs), blurs, strict=True)])
    return time, np.interp(time, knots_t, knots_u)


def test_sharp_fraction_and_percentiles_on_constructed_frames():
    """Blurs 0.5, 0.99, 1.01, 2.0 px: half are sharp at 1 px; p95 = 1.01 + 0.85 (2.0 - 1.01) (linear rank);
    frame jitter the RMS of the centroid steps."""
    time, u = _steps([0.5, 0.99, 1.01, 2.0])
    frames = iq.frames_from_image_path(time, u, np.zeros_like(time), CAM)
    assert frames.blur_px == pytest.approx([0.5, 0.99, 1.01, 2.0], rel=1e-9)
    summary = iq.frame_summary(frames, 1.0)
    assert summary["sharp_fraction"][0] == 0.5
    assert summary["blur_median"][0] == pytest.approx(1.0, rel=1e-9)
    assert summary["blur_p95"][0] == pytest.approx(1.01 + 0.85 * 0.99, rel=1e-9)
    assert summary["blur_max"][0] == pytest.approx(2.0, rel=1e-9)
    # each exposure's centroid sits mid-ramp, so consecutive centroids are (b_k + b_k+1) / 2 apart
    steps = np.array([0.5 + 0.99, 0.99 + 1.01, 1.01 + 2.0]) / 2
    assert summary["frame_jitter_rms"][0] == pytest.approx(np.sqrt(np.mean(steps**2)), rel=1e-9)
    # a blur exactly at the threshold counts as sharp
    assert iq.frame_summary(frames, float(frames.blur_px[1]))["sharp_fraction"][0] == 0.5


def test_frame_windowing_and_partial_frames():
    """Frames at k / fps; a frame counts when its exposure ends inside the record or window."""
    time = np.arange(10001) * 1e-4  # 0 .. 1 s
    assert iq.frame_starts(time, CAM).size == 25  # (1 - T) * 25 = 24.9: frames 0..24
    exact = _time(7, 1e-4)  # ends exactly at 6 / fps + T: the 7th frame is complete
    assert iq.frame_starts(exact, CAM).size == 7
    assert iq.frame_starts(exact[:-1], CAM).size == 6  # one sample short: the 7th is partial, dropped
    # 30 fps, 1/250 s, 1/3000 s steps: sample 312 lies 1.4e-17 s before 3/30 + 1/250 (rounding): 4 frames
    assert iq.frame_starts(np.arange(313) / 3000.0, _camera(frame_rate_hz=30.0, exposure_s=1 / 250)).size == 4
    starts = iq.frame_starts(time, CAM, start_s=0.5, end_s=0.7)
    assert starts == pytest.approx(0.5 + np.arange(5) / FPS)  # 0.5 + 4/25 + T = 0.664 <= 0.7 < 0.704
    with pytest.raises(ValueError, match=r"shorter than one frame's exposure"):
        iq.frame_starts(time, CAM, start_s=0.5, end_s=0.5 + T / 2)
    with pytest.raises(ValueError, match=r"must lie within the record"):
        iq.frame_starts(time, CAM, start_s=0.5, end_s=1.5)


def test_rolling_shutter_delays_the_centre_row_and_skews_the_frame():
    """Line time L, H rows, u = r t: the centre row starts L (H-1)/2 late, so its centroid shifts by
    r L (H-1)/2; first and last rows see the image r L (H-1) apart; the frame needs L (H-1) + T."""
    line, rows, r = 20e-6, 1080, 300.0
    cam = _camera(line_time_s=line)
    time = _time(4, 1e-5)
    assert iq.frame_starts(time, cam).size == 3  # the 4th frame's last row ends after the record
    frames = iq.frames_from_image_path(time, r * time, np.zeros_like(time), cam)
    t_k = np.arange(3) / FPS
    assert frames.centroid_px[:, 0] == pytest.approx(r * (t_k + line * (rows - 1) / 2 + T / 2), rel=1e-9)
    assert frames.skew_px == pytest.approx(np.full(3, r * line * (rows - 1)), rel=1e-9)
    assert frames.blur_px == pytest.approx(np.full(3, r * T), rel=1e-9)


def test_line_of_sight_stats_of_sines():
    """Yaw A sin, pitch B cos over whole periods: std A/sqrt2, B/sqrt2, combined sqrt(A^2+B^2)/sqrt2;
    peaks A, B; the off-axis angle of (psi, 0) is psi, so with B << A the combined peak is A (1 + O(B^2/A^2))."""
    time = np.arange(2001) * 1e-3  # 2 s
    a, b = 2e-3, 1e-3
    yaw, pitch = a * np.sin(2 * np.pi * 5 * time), b * np.cos(2 * np.pi * 5 * time)
    stats = iq.line_of_sight_stats(time[:-1], yaw[:-1], pitch[:-1])  # 10 whole periods
    assert stats["los_yaw_std"][0] == pytest.approx(a / np.sqrt(2), rel=1e-9)
    assert stats["los_pitch_std"][0] == pytest.approx(b / np.sqrt(2), rel=1e-9)
    assert stats["los_std"][0] == pytest.approx(np.hypot(a, b) / np.sqrt(2), rel=1e-9)
    assert stats["los_yaw_peak"][0] == pytest.approx(a, rel=1e-9)
    assert stats["los_pitch_peak"][0] == pytest.approx(b, rel=1e-9)
    only_yaw = iq.line_of_sight_stats(time, yaw, 0 * pitch)
    assert only_yaw["los_peak"][0] == pytest.approx(a, rel=1e-9)
    # window: the first eighth of a period holds yaw rising 0 -> A sin(pi/4), pitch falling from B
    part = iq.line_of_sight_stats(time, yaw, pitch, start_s=0.0, end_s=0.025)
    assert part["los_yaw_peak"][0] == pytest.approx(a * np.sin(np.pi / 4), rel=1e-9)
    assert part["los_pitch_peak"][0] == b


def test_image_metrics_names_units_and_values():
    time = _time(6, 1e-4)  # yaw rate 0.05 rad s-1: 0.41 px per frame, all sharp
    out = iq.image_metrics(*_response(time, yaw=0.05 * time), CAM)
    for name, (value, units, long_name) in out.items():
        assert isinstance(value, float) and units in ("rad", "1") and long_name, name
        assert units == "rad" or "pixels" in long_name or name in ("sharp_fraction", "mtf_nyquist_median"), name
    assert out["blur_p95"][0] == pytest.approx(F * 0.05 * T, rel=1e-4)
    assert out["sharp_fraction"] == (1.0, "1", "fraction of frames with smear extent <= 1 px")
    assert out["rolling_shutter_skew_p95"][0] == 0.0


@pytest.mark.parametrize(
    ("time", "u", "message"),
    [
        (np.array([0.0, 1e-3, 3e-3]), np.zeros(3), "strictly increasing and uniform"),
        (np.arange(3) * 1e-3, np.zeros(4), r"u_px has shape \(4,\), time has \(3,\)"),
        (np.arange(3) * 1e-3, np.array([0.0, np.nan, 0.0]), "u_px holds non-finite values"),
        (np.array([0.0]), np.zeros(1), ">= 2 samples"),
    ],
)
def test_bad_series_are_refused(time, u, message):
    with pytest.raises(ValueError, match=message):
        iq.frames_from_image_path(time, u, np.zeros_like(time), CAM)


def test_response_shape_is_checked():
    time = _time(2, 1e-4)
    with pytest.raises(ValueError, match=r"camera_displacement must be \(axis=\(y, z\), time\)"):
        iq.image_metrics(time, np.zeros((3, time.size)), np.zeros_like(time), np.zeros_like(time), CAM)


def test_the_linear_fit_is_weighted_least_squares_and_its_residual_the_principal_axis():
    """Per frame, the slope is the trapezoid-weighted least-squares line through the exposure's points and sigma^2
    the largest eigenvalue of the weighted covariance of the residuals, both computed here independently (numpy's
    weighted polyfit and eigvalsh) on random uneven sample times."""
    rng = np.random.default_rng(3)
    tau = np.sort(rng.uniform(0.0, 1.0, size=(5, 7)), axis=1)
    points = rng.normal(size=(5, 7, 2)) + 4.0 * tau[..., None] * np.array([1.0, -2.0])
    slope, sigma = iq._linear_fit(tau, points)
    for k in range(5):
        seg = np.diff(tau[k])
        w = np.concatenate([seg, [0.0]]) / 2 + np.concatenate([[0.0], seg]) / 2
        fits = [np.polyfit(tau[k], points[k, :, i], 1, w=np.sqrt(w)) for i in range(2)]
        assert slope[k] == pytest.approx([fits[0][0], fits[1][0]], rel=1e-9)
        r = points[k] - np.stack([np.polyval(f, tau[k]) for f in fits], axis=1)
        cov = (w[:, None, None] * r[:, :, None] * r[:, None, :]).sum(axis=0) / w.sum()
        assert sigma[k] == pytest.approx(np.sqrt(np.linalg.eigvalsh(cov)[-1]), rel=1e-9)


def test_rolling_shutter_skew_of_an_accelerating_image_is_read_from_mid_exposure():
    """u = b t^2: the first and last rows at mid-exposure (t_k + T / 2 and L (H - 1) later) see the image
    b ((m + L (H-1))^2 - m^2) apart, m = t_k + T / 2: the skew depends on when it is read, unlike u = r t's."""
    line, rows, b = 20e-6, 1080, 5000.0
    cam = _camera(line_time_s=line)
    time = _time(4, 1e-5)
    frames = iq.frames_from_image_path(time, b * time**2, np.zeros_like(time), cam)
    mid = np.arange(3) / FPS + T / 2
    assert frames.skew_px == pytest.approx(b * ((mid + line * (rows - 1)) ** 2 - mid**2), rel=1e-6)


def test_a_frame_spans_the_rows_readout_and_the_exposure():
    """A window exactly L (H - 1) + T long holds one frame; L (H - 1) + T + 1 / fps - L / 2 still one, since the
    second frame's last row would end L / 2 after the window."""
    line = 20e-6
    cam = _camera(line_time_s=line)
    time = np.arange(20001) * 1e-5
    span = line * 1079 + T
    assert iq.frame_starts(time, cam, start_s=0.1, end_s=0.1 + span).size == 1
    assert iq.frame_starts(time, cam, start_s=0.1, end_s=0.1 + span + 1 / FPS - line / 2).size == 1
    assert iq.frame_starts(time, cam, start_s=0.1, end_s=0.1 + span + 1 / FPS).size == 2
    with pytest.raises(ValueError, match="shorter than one frame"):
        iq.frame_starts(time, cam, start_s=0.1, end_s=0.1 + span - line)


def test_the_record_and_window_checks_at_their_edges():
    """Two samples make a record; equal times, a step spread of 1e-5 of the step, an empty window or one starting
    more than 1e-9 of a step before the record are refused; the messages name the series and the record."""
    iq._check_time(np.array([0.0, 1e-3]))
    with pytest.raises(ValueError, match="strictly increasing"):
        iq._check_time(np.zeros(3))
    with pytest.raises(ValueError, match="strictly increasing"):
        iq._check_time(np.array([0.0, 1e-3, 2e-3 + 1e-8]))
    t = 5.0 + np.arange(11) * 1e-3
    assert iq._span(t, 5.0 - 0.5e-12, None) == (5.0 - 0.5e-12, float(t[-1]))
    with pytest.raises(ValueError, match=r"must lie within the record \[5.0, 5.01\] s"):
        iq._span(t, 5.0 - 1.5e-12, None)
    with pytest.raises(ValueError, match="must lie within the record"):
        iq._span(t, 5.004, 5.004)
    bad, good = np.array([0.0, np.nan, 0.0]), np.zeros(3)
    time = np.arange(3) * 1e-3
    for call, names in (
        (lambda y, p: iq.camera_criteria(["los_std"], time, np.zeros((2, 3)), y, p), ("camera_yaw", "camera_pitch")),
        (lambda y, p: iq.line_of_sight_stats(time, y, p), ("yaw", "pitch")),
        (lambda y, p: iq.frames_from_image_path(time, y, p, CAM), ("u_px", "v_px")),
    ):
        for args, name in (((bad, good), names[0]), ((good, bad), names[1])):
            with pytest.raises(ValueError, match=rf"^{name} holds non-finite values"):
                call(*args)


def test_camera_criteria_windows_need_two_samples_and_frames_a_camera():
    """A window of exactly two samples is scored; the frame criteria name themselves when no camera is given; the
    unsharp fraction reads the camera's sharp threshold."""
    time = _time(6, 1e-4)
    _, disp, yaw, pitch = _response(time, yaw=0.05 * time)
    two = iq.camera_criteria(["los_std"], time, disp, yaw, pitch, start_s=time[3], end_s=time[4])
    assert two["los_std"] == pytest.approx(0.05 * 1e-4 / 2, rel=1e-6)
    with pytest.raises(ValueError, match=r"fewer than 2 samples"):
        iq.camera_criteria(["los_std"], time, disp, yaw, pitch, start_s=time[3], end_s=time[3] + 0.5e-4)
    with pytest.raises(ValueError, match=r"criteria \['blur_p95'\] need a camera"):
        iq.camera_criteria(["los_std", "blur_p95"], time, disp, yaw, pitch)
    sharp = iq.camera_criteria(["unsharp_fraction"], time, disp, yaw, pitch, camera=_camera(sharp_threshold_px=0.3))
    assert sharp["unsharp_fraction"] == 1.0  # every frame smears F 0.05 T = 0.41 px
    assert iq.camera_criteria(["unsharp_fraction"], time, disp, yaw, pitch, camera=CAM)["unsharp_fraction"] == 0.0


def test_the_summary_percentiles_and_a_single_frames_jitter():
    """Path lengths and skews 0..99 px: their 95th percentiles are numpy's (94.05); one frame has no jitter."""
    n = 100
    frames = iq.Frames(
        start_s=np.arange(n) / FPS, blur_px=np.ones(n), path_px=np.arange(n, dtype=float),
        centroid_px=np.zeros((n, 2)), smear_px=np.ones(n), sigma_px=np.zeros(n), mtf_nyquist=np.ones(n),
        skew_px=np.arange(n, dtype=float)[::-1],
    )  # fmt: skip
    summary = iq.frame_summary(frames, 1.0)
    assert summary["blur_path_p95"][0] == summary["rolling_shutter_skew_p95"][0] == pytest.approx(94.05)
    one = iq.Frames(*(np.asarray(getattr(frames, f))[:1] for f in iq.Frames._fields))
    assert math.isnan(iq.frame_summary(one, 1.0)["frame_jitter_rms"][0])


def test_image_metrics_pass_the_window_to_both_halves():
    """image_metrics over [start, end] is line_of_sight_stats and frame_summary of frame_metrics over it."""
    time = _time(8, 1e-4)
    response = _response(time, yaw=2e-3 * np.sin(2 * np.pi * 3 * time), pitch=0.05 * time)
    out = iq.image_metrics(*response, CAM, start_s=0.05, end_s=0.2)
    los = iq.line_of_sight_stats(time, response[2], response[3], 0.05, 0.2)
    frames = iq.frame_metrics(*response, CAM, 0.05, 0.2)
    assert out == {**los, **iq.frame_summary(frames, CAM.sharp_threshold_px)}
    assert frames.start_s == pytest.approx(0.05 + np.arange(4) / FPS)
    assert los["los_yaw_std"][0] != iq.line_of_sight_stats(time, response[2], response[3], None, 0.2)["los_yaw_std"][0]


def test_the_batched_exposure_weights_are_the_frames_points_under_a_rolling_shutter():
    """`reference_table.sine_batch.exposure_weights` maps the image path to the exposure points of each frame:
    with a 20 us line time, their extent is `frames_from_image_path`'s blur frame by frame, on a random path."""
    from uavdamp.reference_table.sine_batch import exposure_weights

    cam = _camera(line_time_s=20e-6)
    time = np.arange(3001) * 1e-4
    path = np.cumsum(np.random.default_rng(4).normal(size=(time.size, 2)), axis=0)
    weights, samples, shape = exposure_weights(time, cam, (0.01, 0.29))
    points = (weights @ path[samples]).reshape(*shape, 2)
    frames = iq.frames_from_image_path(time, path[:, 0], path[:, 1], cam, 0.01, 0.29)
    assert shape[0] == frames.blur_px.size == 7  # 0.01 + 6 / 25 + 20 us x 1079 + 4 ms = 0.2756 s <= 0.29
    np.testing.assert_allclose(iq._extent(points), frames.blur_px, rtol=1e-12)
    np.testing.assert_allclose(points[:, 0], iq._interp(time, path, frames.start_s + 20e-6 * 1079 / 2), rtol=1e-12)


def test_the_frame_criteria_read_a_given_image_path_as_the_one_they_would_make():
    """camera_criteria's image_px (a caller's image path of the same arrays, reused over several frame clocks) gives
    the criteria bit for bit as without it; a different path gives different ones (it is read, not ignored). The
    angular rate makes a smear of F 0.05 T = 0.41 px a frame (`test_constant_angular_rate_gives_f_omega_t`)."""
    time = _time(6, 1e-4)
    _, disp, yaw, pitch = _response(time, yaw=0.05 * time, z=1e-4 * np.sin(300 * time))
    names, start = ["blur_p95", "unsharp_fraction"], time[0] + 0.3 / FPS
    camera = _camera(sharp_threshold_px=0.45)
    made = iq.camera_criteria(names, time, disp, yaw, pitch, camera, start)
    path = iq.image_displacement_px(camera, yaw, pitch, disp[0], disp[1])
    assert iq.camera_criteria(names, time, disp, yaw, pitch, camera, start, image_px=path) == made
    other = iq.camera_criteria(names, time, disp, yaw, pitch, camera, start, image_px=(2 * path[0], path[1]))
    assert other["blur_p95"] > made["blur_p95"]
