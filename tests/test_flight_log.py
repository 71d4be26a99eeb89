"""Flight logs -> mount motion (uavdamp.sources.flight_log, uavdamp.signals.inertial): integration of known sines,
rigid-body lever arm, FRD -> FLU signs, the two shipped PX4 logs (expected values read with pyulog here), synthetic
ArduPilot DataFlash files written with pymavlink's own format classes, and refusal of bad input."""

from __future__ import annotations

import hashlib
import shutil
import struct
import subprocess
import sys
import types

import numpy as np
import pytest
from conftest import ROOT
from pymavlink.DFReader import DFFormat, DFReader_binary
from pyulog import ULog

from uavdamp import io
from uavdamp.signals import inertial
from uavdamp.sources import flight_log
from uavdamp.sources.flight_log import FlightLogError, read_flight_log

LOGS = ROOT / "data" / "flight_logs"
QUAD = LOGS / "quadrotor_fmuv5_9s.ulg"
VTOL = LOGS / "vtol_cubeorange_hop.ulg"
BAND = (2.0, 40.0)
AS_IS = {"on_aliasing": "record", "on_ground": "record"}  # the shipped logs: aliased, mostly on the ground
FS = 200.0
G = 9.81


def sine_time(duration_s: float = 9.0, fs: float = FS) -> np.ndarray:
    return np.arange(int(round(duration_s * fs)) + 1) / fs


def interior(t: np.ndarray, band=BAND) -> np.ndarray:
    """Samples further than 3 / f_low from either end (the documented trusted part)."""
    edge = 3.0 / band[0]
    return (t >= t[0] + edge) & (t <= t[-1] - edge)


def write_csv(path, t, acc_frd, gyro_frd, header=flight_log.CSV_COLUMNS):
    rows = np.column_stack([t, *np.asarray(acc_frd), *np.asarray(gyro_frd)])
    np.savetxt(path, rows, delimiter=",", header=",".join(header), comments="", fmt="%.10g")
    return path


def still_frd(n: int) -> tuple[np.ndarray, np.ndarray]:
    """A level vehicle at rest, FRD: specific force -g along z (down), no rotation."""
    acc = np.zeros((3, n))
    acc[2] = -G
    return acc, np.zeros((3, n))


# --- band-pass integration against closed forms ---------------------------------------------------------


@pytest.mark.parametrize("freq_hz", [4.0, 6.1, 10.3, 20.7, 35.2, 38.0])
def test_acceleration_sines_integrate_to_their_displacement(freq_hz):
    t = sine_time()
    amplitude = 1e-3
    for phase in np.linspace(0.0, np.pi, 5):
        x = amplitude * np.sin(2 * np.pi * freq_hz * t + phase)
        acc = -((2 * np.pi * freq_hz) ** 2) * x + G  # gravity's constant specific force on top
        got = inertial.band_integrate(acc, 1 / FS, BAND, 2)
        k = interior(t)
        assert np.max(np.abs(got[k] - x[k])) < 0.005 * amplitude


@pytest.mark.parametrize("freq_hz", [4.0, 10.3, 20.7, 38.0])
def test_rates_integrate_to_their_rotation(freq_hz):
    t = sine_time()
    amplitude = 2e-3  # rad
    for phase in (0.0, 1.1):
        angle = amplitude * np.sin(2 * np.pi * freq_hz * t + phase)
        rate = amplitude * 2 * np.pi * freq_hz * np.cos(2 * np.pi * freq_hz * t + phase) + 0.05
        got = inertial.band_integrate(rate, 1 / FS, BAND, 1)
        k = interior(t)
        assert np.max(np.abs(got[k] - angle[k])) < 0.005 * amplitude


@pytest.mark.parametrize("freq_hz", [0.5, 1.0, 42.0, 60.0, 90.0])
def test_out_of_band_sines_are_removed(freq_hz):
    t = sine_time()
    amplitude = 1e-3
    acc = -((2 * np.pi * freq_hz) ** 2) * amplitude * np.sin(2 * np.pi * freq_hz * t + 0.3)
    got = inertial.band_integrate(acc, 1 / FS, BAND, 2)
    assert np.max(np.abs(got[interior(t)])) < 0.005 * amplitude


def line_amplitudes(t, x, freqs_hz):
    """Least-squares amplitudes of sines at known frequencies (with an offset)."""
    basis = [np.ones_like(t)]
    for f in freqs_hz:
        basis += [np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t)]
    coef = np.linalg.lstsq(np.column_stack(basis), x, rcond=None)[0]
    return np.hypot(coef[1::2], coef[2::2])


def test_a_mixture_keeps_its_in_band_lines_and_loses_the_others():
    t = sine_time()
    lines = {5.0: 1e-3, 25.0: 2e-4, 0.3: 5e-2, 70.0: 5e-4}  # Hz: displacement amplitude, m
    acc = G + sum(-((2 * np.pi * f) ** 2) * a * np.sin(2 * np.pi * f * t + f) for f, a in lines.items())
    got = inertial.band_integrate(acc, 1 / FS, BAND, 2)
    k = interior(t)
    amp = dict(zip(lines, line_amplitudes(t[k], got[k], list(lines)), strict=True))
    assert amp[5.0] == pytest.approx(1e-3, rel=0.005)
    assert amp[25.0] == pytest.approx(2e-4, rel=0.005)
    assert amp[0.3] < 0.005 * 5e-2 and amp[70.0] < 0.005 * 5e-4


def test_other_band_and_rate_scale_alike():
    """Band (5, 80) Hz at 400 Hz on 5 s: the accuracy depends on f / f_low, as documented."""
    band, fs = (5.0, 80.0), 400.0
    t = sine_time(5.0, fs)
    for freq_hz in (10.0, 33.3, 70.0):
        x = 1e-4 * np.sin(2 * np.pi * freq_hz * t)
        got = inertial.band_integrate(-((2 * np.pi * freq_hz) ** 2) * x, 1 / fs, band, 2)
        k = interior(t, band)
        assert np.max(np.abs(got[k] - x[k])) < 0.005 * 1e-4


def test_edges_are_untrusted_and_the_interior_is_not():
    """The documented edge profile (10.3 Hz, band (2, 40) Hz): the taper's first 0.25 s is nearly zeroed;
    past the 1 s taper the error is below 0.5 %, and past edge_s = 1.5 s below 0.1 %."""
    t = sine_time()
    x = 1e-3 * np.sin(2 * np.pi * 10.3 * t + 0.4)
    err = np.abs(inertial.band_integrate(-((2 * np.pi * 10.3) ** 2) * x, 1 / FS, BAND, 2) - x) / 1e-3
    assert np.max(err[t < 0.25]) > 0.9 and np.max(err[t > t[-1] - 0.25]) > 0.9
    assert np.max(err[(t >= 1.0) & (t <= t[-1] - 1.0)]) < 0.005
    assert np.max(err[interior(t)]) < 0.001


def test_band_integrate_refuses_a_record_shorter_than_the_band_needs():
    t = sine_time(3.9)  # 8 / f_low = 4 s
    with pytest.raises(ValueError, match="shorter"):
        inertial.band_integrate(np.sin(t), 1 / FS, BAND, 2)


# --- rigid-body lever arm ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("omega", "r", "expected"),
    [
        ((0.0, 0.0, 3.0), (0.2, -0.1, 0.05), (-9.0 * 0.2, -9.0 * -0.1, 0.0)),  # about z: -w^2 r in the xy plane
        ((1.0, 0.0, 2.0), (0.0, 0.3, 0.0), (0.0, -5.0 * 0.3, 0.0)),  # r perpendicular to w: -|w|^2 r
        ((0.0, 0.0, 4.0), (0.0, 0.0, 0.5), (0.0, 0.0, 0.0)),  # on the axis: nothing
    ],
)
def test_constant_rate_gives_centripetal_acceleration(omega, r, expected):
    n = 10
    w = np.repeat(np.reshape(omega, (3, 1)), n, axis=1)
    got = inertial.lever_arm(np.zeros((3, n)), w, np.zeros((3, n)), r)
    np.testing.assert_allclose(got, np.repeat(np.reshape(expected, (3, 1)), n, axis=1), atol=1e-12)


def test_angular_acceleration_gives_tangential_acceleration():
    n = 10
    alpha = np.repeat([[0.0], [0.0], [7.0]], n, axis=1)
    got = inertial.lever_arm(np.zeros((3, n)), np.zeros((3, n)), alpha, (0.2, 0.0, 0.0))
    np.testing.assert_allclose(got[:, 0], [0.0, 7.0 * 0.2, 0.0], atol=1e-12)  # alpha x r = (0, a rx, 0)


def test_sinusoidal_rate_about_z_moves_the_mount_as_the_closed_form(tmp_path):
    """End to end through a CSV (FRD): w_z = W sin(2 pi f t) in FLU, r = (rx, 0, 0) gives a_x = -w_z^2 rx
    (centripetal), a_y = dw_z/dt rx = W 2 pi f cos(2 pi f t) rx (tangential); a_z is the specific force g."""
    t = sine_time()
    big_w, f, rx = 2.0, 5.0, 0.25
    acc, gyro = still_frd(t.size)
    gyro[2] = -big_w * np.sin(2 * np.pi * f * t)  # FRD z is down
    ds = read_flight_log(write_csv(tmp_path / "spin.csv", t, acc, gyro), band_hz=BAND, imu_to_mount_m=(rx, 0, 0))
    k = interior(t)
    wz = big_w * np.sin(2 * np.pi * f * t)
    a = ds.acceleration.values
    np.testing.assert_allclose(a[0, k], -(wz[k] ** 2) * rx, atol=1e-4 * big_w**2 * rx)
    np.testing.assert_allclose(a[1, k], big_w * 2 * np.pi * f * np.cos(2 * np.pi * f * t[k]) * rx, atol=1e-4 * 2.5)
    np.testing.assert_allclose(a[2], G, atol=1e-9)
    np.testing.assert_allclose(ds.angular_rate.values[2], wz, atol=1e-9)  # CSV: 10 digits


def test_rotation_about_z_moves_an_offset_mount_tangentially(tmp_path):
    """theta_z = T sin(2 pi f t) about z (FLU) with the mount at r = (rx, 0, 0): a_y = dw_z/dt rx integrates to
    y = rx theta_z, and theta_z comes back from the rates; the centripetal a_x = -w_z^2 rx has a 2f line whose
    displacement amplitude is rx T^2 / 8."""
    t = sine_time()
    big_t, f, rx = 0.02, 5.0, 0.2
    acc, gyro = still_frd(t.size)
    gyro[2] = -big_t * 2 * np.pi * f * np.cos(2 * np.pi * f * t)
    ds = read_flight_log(write_csv(tmp_path / "yaw.csv", t, acc, gyro), band_hz=BAND, imu_to_mount_m=(rx, 0, 0))
    k = interior(t)
    theta = big_t * np.sin(2 * np.pi * f * t)
    assert np.max(np.abs(ds.mount_rotation.values[2, k] - theta[k])) < 0.005 * big_t
    assert np.max(np.abs(ds.mount_displacement.values[1, k] - rx * theta[k])) < 0.005 * rx * big_t
    amp_2f = line_amplitudes(t[k], ds.mount_displacement.values[0, k], [2 * f])[0]
    assert amp_2f == pytest.approx(rx * big_t**2 / 8, rel=0.01)


def test_spline_reproduces_cubics_on_jittered_times():
    """A not-a-knot cubic spline is exact for a cubic polynomial, ends included."""
    rng = np.random.default_rng(3)
    t = np.sort(rng.uniform(0.0, 2.0, 50))
    cubic = np.array([1.0 + t - 2 * t**2 + 0.5 * t**3, -(t**3), 3 + 0 * t])
    grid = inertial.uniform_grid(t[0], t[-1], 0.01)
    values, slope = inertial.resample(t, cubic, grid, derivative=True)
    g = grid
    np.testing.assert_allclose(values[:2], [1.0 + g - 2 * g**2 + 0.5 * g**3, -(g**3)], atol=1e-9)
    np.testing.assert_allclose(slope[:2], [1.0 - 4 * g + 1.5 * g**2, -3 * g**2], atol=1e-9)


def test_spline_derivative_has_the_compact_difference_gain():
    """At the knots of uniform samples, the cubic spline's derivative of sin(w t) is G w cos(w t) with
    G = 3 sin(x) / (x (2 + cos x)), x = w dt (the tridiagonal spline relation s'_{i-1} + 4 s'_i + s'_{i+1}
    = 3 (y_{i+1} - y_{i-1}) / dt applied to a sinusoid)."""
    dt = 1 / FS
    t = sine_time()
    for f in (20.0, 40.0):
        x = 2 * np.pi * f * dt
        gain = 3 * np.sin(x) / (x * (2 + np.cos(x)))
        _, deriv = inertial.resample(t, np.tile(np.sin(2 * np.pi * f * t), (3, 1)), t, derivative=True)
        k = interior(t)
        expected = gain * 2 * np.pi * f * np.cos(2 * np.pi * f * t[k])
        np.testing.assert_allclose(deriv[0, k], expected, atol=1e-6 * 2 * np.pi * f)


# --- axes and signs -------------------------------------------------------------------------------------------


def test_frd_to_flu_negates_y_and_z_and_keeps_handedness():
    np.testing.assert_array_equal(inertial.frd_to_flu(np.array([[1.0], [2.0], [3.0]]))[:, 0], [1.0, -2.0, -3.0])
    a, b = np.array([[1.0], [2.0], [0.5]]), np.array([[-0.3], [0.7], [2.0]])
    flu_of_cross = inertial.frd_to_flu(np.cross(a, b, axis=0))
    np.testing.assert_allclose(flu_of_cross, np.cross(inertial.frd_to_flu(a), inertial.frd_to_flu(b), axis=0))


def test_csv_signs_arrive_in_uavdamp_axes(tmp_path):
    t = sine_time(5.0)
    acc, gyro = still_frd(t.size)
    acc[0], acc[1] = 0.4, 0.7
    gyro[:] = np.reshape([0.1, 0.2, 0.3], (3, 1))
    ds = read_flight_log(write_csv(tmp_path / "signs.csv", t, acc, gyro), band_hz=BAND)
    np.testing.assert_allclose(ds.acceleration.values[:, 0], [0.4, -0.7, G])  # at rest, +g points up
    np.testing.assert_allclose(ds.angular_rate.values[:, 0], [0.1, -0.2, -0.3])
    assert "y left, z up" in ds.attrs["frame"] and "y -> -y, z -> -z" in ds.attrs["sign"]


def test_csv_columns_in_any_order_with_extra_ones(tmp_path):
    t = sine_time(5.0)
    acc, gyro = still_frd(t.size)
    gyro[1] = 0.3
    ds = read_flight_log(write_csv(tmp_path / "a.csv", t, acc, gyro), band_hz=BAND)
    order = [3, 0, 6, 1, 5, 2, 4]
    table = np.column_stack([t, *acc, *gyro, np.ones_like(t)])[:, order + [7]]
    header = ",".join([flight_log.CSV_COLUMNS[i] for i in order] + ["battery_v"])
    path = tmp_path / "b.csv"
    np.savetxt(path, table, delimiter=",", header="# exported by hand\n" + header, comments="", fmt="%.10g")
    other = read_flight_log(path, band_hz=BAND)
    np.testing.assert_array_equal(other.acceleration, ds.acceleration)
    np.testing.assert_array_equal(other.angular_rate, ds.angular_rate)
    np.testing.assert_allclose(other.angular_rate.values[1], -0.3)


def test_jittered_csv_sine_integrates_to_its_displacement(tmp_path):
    """200 Hz with +-10 % timestamp jitter; 6 Hz and 15 Hz lines on FRD y (uavdamp y = -FRD y)."""
    rng = np.random.default_rng(7)
    t = 100.0 + np.arange(1801) / FS + rng.uniform(-0.1, 0.1, 1801) / FS
    lines = {6.0: 1e-3, 15.0: 3e-4}
    acc, gyro = still_frd(t.size)
    acc[1] = sum(-((2 * np.pi * f) ** 2) * a * np.sin(2 * np.pi * f * t) for f, a in lines.items())
    ds = read_flight_log(write_csv(tmp_path / "jitter.csv", t, acc, gyro), band_hz=BAND)
    assert ds.attrs["interval_jitter_max"] == pytest.approx(0.2, abs=0.02)
    log_time = ds.time.values + t[0]
    expected = -sum(a * np.sin(2 * np.pi * f * log_time) for f, a in lines.items())
    k = interior(ds.time.values)
    assert np.max(np.abs(ds.mount_displacement.values[1, k] - expected[k])) < 0.005 * 1e-3


# --- the shipped PX4 logs ---------------------------------------------------------------------------------------


def sensor_combined(path):
    return ULog(str(path), ["sensor_combined"]).get_dataset("sensor_combined").data


def test_quadrotor_log_rate_duration_and_topic():
    raw = sensor_combined(QUAD)
    t = raw["timestamp"] * 1e-6
    ds = read_flight_log(QUAD, band_hz=BAND, **AS_IS)
    steps = np.diff(t)
    assert ds.attrs["sample_rate_hz"] == pytest.approx(1 / np.median(steps), rel=1e-12)
    assert ds.attrs["sample_rate_hz"] == pytest.approx(200.0, rel=0.01)  # FMU-V5 sensor_combined: 200 Hz
    assert float(ds.time[-1]) == pytest.approx(t[-1] - t[0], abs=np.median(steps))
    assert float(ds.time[-1]) == pytest.approx(8.94, abs=0.02)  # about 9 s
    jitter = np.abs(steps - np.median(steps)) / np.median(steps)
    assert ds.attrs["interval_jitter_max"] == pytest.approx(jitter.max(), rel=1e-9)  # a dropped sample: ~1.1
    assert ds.attrs["interval_jitter_std"] == pytest.approx(np.std(steps / np.median(steps)), rel=1e-9)
    assert ds.attrs["log_format"] == "PX4 ULog" and ds.attrs["log_messages"].startswith("sensor_combined")
    assert ds.attrs["log_sha256"] == hashlib.sha256(QUAD.read_bytes()).hexdigest()
    assert ds.attrs["accelerometer_clipped_samples"] == np.count_nonzero(raw["accelerometer_clipping"])
    on_ground = t < t[0] + 1.0  # the first second: standing still, z down in FRD
    assert np.mean(raw["accelerometer_m_s2[2]"][on_ground]) == pytest.approx(-G, abs=0.2)
    assert float(ds.acceleration.sel(axis="z", time=slice(0, 1)).mean()) == pytest.approx(
        -np.mean(raw["accelerometer_m_s2[2]"][on_ground]), abs=0.01
    )
    io.check_metadata(ds)


def test_accelerometer_relative_timestamps_are_used(tmp_path):
    """The quadrotor log rewritten by pyulog with the accelerometer 2.5 ms after the gyro and a 3 Hz line of
    the accelerometer's own time on FRD x: the resampled line has no phase lag (2.5 ms would be 4.7 %)."""
    ulog = ULog(str(QUAD), ["sensor_combined"])
    data = ulog.get_dataset("sensor_combined").data
    data["accelerometer_timestamp_relative"][:] = 2500
    acc_time = 1e-6 * (data["timestamp"] + 2500)
    data["accelerometer_m_s2[0]"][:] = np.sin(2 * np.pi * 3.0 * acc_time)
    ulog.write_ulog(str(tmp_path / "shifted.ulg"))
    ds = read_flight_log(tmp_path / "shifted.ulg", band_hz=BAND, **AS_IS)
    log_time = ds.time.values + ds.attrs["log_window_s"][0]
    np.testing.assert_allclose(ds.acceleration.values[0], np.sin(2 * np.pi * 3.0 * log_time), atol=2e-3)


def test_vtol_log_is_refused_whole_for_its_start_gap_and_read_after_it():
    raw = sensor_combined(VTOL)
    t = raw["timestamp"] * 1e-6
    assert t[1] - t[0] > 0.15  # 161 ms between the first two samples
    with pytest.raises(FlightLogError, match=f"{VTOL.name}.*gap of 161.3 ms"):
        read_flight_log(VTOL, band_hz=BAND, **AS_IS)
    ds = read_flight_log(VTOL, band_hz=BAND, window_s=(t[1], t[-1]), **AS_IS)
    assert ds.attrs["sample_rate_hz"] == pytest.approx(1 / np.median(np.diff(t[1:])), rel=1e-12)
    assert ds.attrs["sample_rate_hz"] == pytest.approx(204.6, abs=0.1)
    assert float(ds.time[-1]) == pytest.approx(t[-1] - t[1], abs=0.005)
    assert float(ds.time[-1]) == pytest.approx(6.33, abs=0.01)
    np.testing.assert_allclose(ds.attrs["log_window_s"], [t[1], t[-1]], atol=0.005)


def test_dataset_metadata_and_attributes_survive_netcdf(tmp_path):
    ds = read_flight_log(QUAD, band_hz=BAND, window_s=(4.0, 12.0), imu_to_mount_m=(0.05, 0.0, -0.08), **AS_IS)
    io.check_metadata(ds)
    assert set(ds.data_vars) == {"mount_displacement", "mount_rotation", "acceleration", "angular_rate"}
    assert ds.mount_displacement.dims == ("axis", "time") and list(ds.axis.values) == ["x", "y", "z"]
    assert float(ds.time[0]) == 0.0
    for key in (
        "log_file",
        "log_sha256",
        "log_format",
        "log_messages",
        "sample_rate_hz",
        "log_window_s",
        "band_hz",
        "imu_to_mount_m",
        "interval_jitter_std",
        "interval_jitter_max",
        "frame",
        "sign",
        "edge_s",
    ):
        assert key in ds.attrs, key
    np.testing.assert_allclose(ds.attrs["imu_to_mount_m"], [0.05, 0.0, -0.08])
    back = io.open_dataset(io.write_netcdf(ds, tmp_path / "log.nc", {}, section="flight_log"))
    np.testing.assert_allclose(back.mount_rotation, ds.mount_rotation)


def test_read_flight_log_is_importable_lazily_from_the_package():
    import uavdamp

    assert uavdamp.read_flight_log is read_flight_log
    code = "import sys, uavdamp; print(sorted({'pyulog', 'pymavlink', 'xarray', 'scipy'} & set(sys.modules)))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


# --- ArduPilot DataFlash, written with pymavlink's format classes --------------------------------------------

FMT = DFFormat(0x80, "FMT", 89, "BBnNZ", "Type,Length,Name,Format,Columns")
IMU = DFFormat(0x81, "IMU", 0, "QBffffff", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ")


def write_dataflash(path, t, acc_frd, gyro_frd, *, instances=(0, 1), message=IMU):
    """FMT records, then one IMU message per sample and instance (instance i adds i to every value)."""
    holder = types.SimpleNamespace(formats={0x80: FMT})
    buf = DFReader_binary.make_format_msgbuf(holder, FMT) + DFReader_binary.make_format_msgbuf(holder, message)
    for k in range(t.size):
        for i in instances:
            values = [int(round(1e6 * t[k])), i, *(gyro_frd[:, k] + i), *(acc_frd[:, k] + i)]
            buf += DFReader_binary.make_msgbuf(None, message, values)
    path.write_bytes(buf)
    return path


def test_dataflash_first_imu_instance_in_uavdamp_axes(tmp_path):
    t = 30.0 + sine_time(5.0)
    acc, gyro = still_frd(t.size)
    acc[1] = -((2 * np.pi * 10.0) ** 2) * 1e-3 * np.sin(2 * np.pi * 10.0 * t)
    gyro[0] = 0.2
    ds = read_flight_log(write_dataflash(tmp_path / "log.bin", t, acc, gyro), band_hz=BAND)
    assert ds.attrs["log_format"] == "ArduPilot DataFlash" and ds.attrs["log_messages"].startswith("IMU")
    assert ds.attrs["sample_rate_hz"] == pytest.approx(FS, rel=1e-6)
    np.testing.assert_allclose(ds.acceleration.values[2], G, atol=1e-5)  # instance 1 would read G - 1
    np.testing.assert_allclose(ds.angular_rate.values[0], 0.2, atol=1e-7)
    k = interior(ds.time.values)
    expected = -1e-3 * np.sin(2 * np.pi * 10.0 * t)  # y left = -FRD y
    assert np.max(np.abs(ds.mount_displacement.values[1, k] - expected[k])) < 0.005 * 1e-3


def test_imu_messages_without_instance_field_are_instance_zero():
    msgs = [types.SimpleNamespace(TimeUS=1000 * k, GyrX=1, GyrY=2, GyrZ=3, AccX=4, AccY=5, AccZ=6) for k in range(5)]
    msgs.append(types.SimpleNamespace(TimeUS=9, I=1, GyrX=0, GyrY=0, GyrZ=0, AccX=0, AccY=0, AccZ=0))
    record = flight_log.imu_from_messages(msgs, "x.bin")
    np.testing.assert_allclose(record.time_s, 1e-3 * np.arange(5))
    np.testing.assert_array_equal(record.angular_rate[:, 0], [1, 2, 3])
    np.testing.assert_array_equal(record.acceleration[:, 0], [4, 5, 6])


# --- refusals: every one names the file and writes nothing -------------------------------------------------------


def refused(path, match, **kwargs):
    before = sorted(p.name for p in path.parent.iterdir())
    with pytest.raises(ValueError, match=match) as info:
        read_flight_log(path, **{"band_hz": BAND, **kwargs})
    assert str(path) in str(info.value)
    assert sorted(p.name for p in path.parent.iterdir()) == before
    return info.value


def first_subscription_offset(data: bytes, topic: bytes) -> int:
    """Byte offset of the ULog 'A' (add logged message) record of `topic`: uint16 size, 'A', uint8 multi_id,
    uint16 msg_id, name."""
    offset = 16
    while offset + 3 <= len(data):
        size, kind = struct.unpack_from("<HB", data, offset)
        if kind == ord("A") and data[offset + 6 : offset + 3 + size] == topic:
            return offset
        offset += 3 + size
    raise AssertionError(f"no subscription of {topic!r}")


def test_truncated_ulog_is_refused(tmp_path):
    path = tmp_path / "cut.ulg"
    path.write_bytes(QUAD.read_bytes()[:300001])
    assert isinstance(refused(path, "truncated"), FlightLogError)


def test_ulog_cut_inside_its_header_is_refused(tmp_path):
    path = tmp_path / "head.ulg"
    path.write_bytes(QUAD.read_bytes()[:10])
    refused(path, "truncated: 10 bytes")


def test_ulog_with_invalid_accelerometer_samples_is_refused(tmp_path):
    ulog = ULog(str(QUAD), ["sensor_combined"])
    ulog.get_dataset("sensor_combined").data["accelerometer_timestamp_relative"][100] = 2**31 - 1
    ulog.write_ulog(str(tmp_path / "invalid.ulg"))
    refused(tmp_path / "invalid.ulg", "accelerometer samples invalid")


def test_ulog_without_sensor_combined_is_refused(tmp_path):
    data = QUAD.read_bytes()
    path = tmp_path / "no_imu.ulg"
    path.write_bytes(data[: first_subscription_offset(data, b"sensor_combined")])  # cut on a message boundary
    refused(path, "no sensor_combined")


def test_text_named_ulg_is_refused(tmp_path):
    path = tmp_path / "notes.ulg"
    path.write_text("this is not a flight log\n")
    refused(path, "not a PX4 ULog")


def test_csv_content_named_ulg_and_ulog_named_csv_are_refused(tmp_path):
    t = sine_time(5.0)
    csv = write_csv(tmp_path / "ok.csv", t, *still_frd(t.size))
    shutil.copy(csv, tmp_path / "fake.ulg")
    refused(tmp_path / "fake.ulg", "named .ulg")
    shutil.copy(QUAD, tmp_path / "fake.csv")
    refused(tmp_path / "fake.csv", "named .csv")


def test_another_binary_format_is_refused(tmp_path):
    path = tmp_path / "picture.dat"
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(200))
    refused(path, "not a PX4 ULog")


def test_truncated_dataflash_is_refused(tmp_path):
    t = sine_time(5.0)
    path = write_dataflash(tmp_path / "log.bin", t, *still_frd(t.size))
    path.write_bytes(path.read_bytes()[:-7])
    refused(path, "truncated")


def test_dataflash_without_imu_is_refused(tmp_path):
    other = DFFormat(0x82, "BARO", 0, "QBffffff", "TimeUS,I,Alt,Press,Temp,CRt,SMS,Offset")
    t = sine_time(5.0)
    refused(write_dataflash(tmp_path / "baro.bin", t, *still_frd(t.size), message=other), "no IMU messages")


def test_csv_missing_a_column_is_refused(tmp_path):
    t = sine_time(5.0)
    acc, gyro = still_frd(t.size)
    header = list(flight_log.CSV_COLUMNS)
    header[5] = "gyro_y_deg_s"
    refused(write_csv(tmp_path / "cols.csv", t, acc, gyro, header=header), "lacks the columns.*gyro_y_rad_s")


def test_csv_with_backwards_time_is_refused(tmp_path):
    t = sine_time(5.0)
    t[500] = t[498]
    refused(write_csv(tmp_path / "back.csv", t, *still_frd(t.size)), "do not increase")


def test_csv_with_non_numbers_or_nan_is_refused(tmp_path):
    t = sine_time(5.0)
    acc, gyro = still_frd(t.size)
    acc[0, 10] = np.nan
    refused(write_csv(tmp_path / "nan.csv", t, acc, gyro), "non-finite")
    path = tmp_path / "text.csv"
    path.write_text(",".join(flight_log.CSV_COLUMNS) + "\n0,1,2,3,4,5,six\n")
    refused(path, "not all numbers")


@pytest.mark.parametrize(("gap_ms", "accepted"), [(12.0, True), (13.0, False)])
def test_csv_gap_longer_than_half_the_top_period_is_refused(tmp_path, gap_ms, accepted):
    """Band top 40 Hz: half its period is 12.5 ms; one interval of the 200 Hz record is stretched."""
    t = sine_time(6.0)
    t[600:] += gap_ms * 1e-3 - 1 / FS
    path = write_csv(tmp_path / "gap.csv", t, *still_frd(t.size))
    if accepted:
        read_flight_log(path, band_hz=BAND)
    else:
        refused(path, "gap of 13 ms.*12.5 ms")


def test_csv_sampled_too_slowly_for_the_band_is_refused(tmp_path):
    t = sine_time(6.0, fs=75.0)  # below 2 x 40 Hz
    refused(write_csv(tmp_path / "slow.csv", t, *still_frd(t.size)), "median sample rate 75 Hz is below twice")


def test_too_few_samples_are_refused(tmp_path):
    t = sine_time(3.9)  # the band's 2 Hz low edge needs 8 / 2 = 4 s
    refused(write_csv(tmp_path / "short.csv", t, *still_frd(t.size)), "too few samples.*needs at least 4 s")
    refused(write_csv(tmp_path / "three.csv", t[:3], *still_frd(3)), "too few samples: 3")


@pytest.mark.parametrize("window_s", [(0.0, 8.0), (5.0, 13.0), (9.0, 6.0)])
def test_window_outside_the_log_is_refused(tmp_path, window_s):
    path = tmp_path / QUAD.name
    shutil.copy(QUAD, path)
    refused(path, "outside the log", window_s=window_s, **AS_IS)


# --- figure ---------------------------------------------------------------------------------------------------------


def test_psd_figure_shows_both_spectra_with_units_band_and_the_line(tmp_path):
    from matplotlib.patches import Rectangle

    from uavdamp.plots.flight_log import psd_figure

    t = sine_time(8.0)
    acc, gyro = still_frd(t.size)
    acc[0] += 0.5 * np.sin(2 * np.pi * 20.0 * t) + 2.0 * np.sin(2 * np.pi * 60.0 * t)  # the larger line out of band
    gyro[2] = 0.01 * np.sin(2 * np.pi * 12.0 * t) + 1e-4 * np.random.default_rng(1).standard_normal(t.size)
    fig = psd_figure(read_flight_log(write_csv(tmp_path / "line.csv", t, acc, gyro), band_hz=BAND))
    acc_ax, rate_ax = fig.axes
    assert acc_ax.get_yscale() == rate_ax.get_yscale() == "log"
    assert "(m/s²)²/Hz" in acc_ax.get_ylabel() and "(rad/s)²/Hz" in rate_ax.get_ylabel()
    assert "Hz" in rate_ax.get_xlabel()
    labels = [text.get_text() for text in acc_ax.get_legend().get_texts()]
    assert "x: in-band peak 20.0 Hz" in labels and "band 2-40 Hz" in labels
    assert "z: in-band peak 12.0 Hz" in [text.get_text() for text in rate_ax.get_legend().get_texts()]
    bottom, top = acc_ax.get_ylim()
    assert 0 < bottom < top < np.inf and top / bottom <= 10.0**7 * 1.0001
    spans = [p for p in acc_ax.patches if isinstance(p, Rectangle)]
    assert any(abs(p.get_x() - 2.0) < 1e-9 and abs(p.get_width() - 38.0) < 1e-9 for p in spans)
