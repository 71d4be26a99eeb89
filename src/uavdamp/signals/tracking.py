"""Causal dominant-frequency tracking with a choice of estimator: the FFT peak or ESPRIT.

One entry point, `frequency_causal(time, signal, t_now, options)`, estimates the dominant frequency
of the last `options.window` s of samples up to and including t_now (`spectrum.causal_segment`:
the same window, start-up and NaN rules for every method); `track` applies it at t_k = k P.

Methods (`study.tracking.method`):
- "fft": `spectrum.dominant_frequency_causal`, called unchanged (Hann peak, sine-fit refinement).
  A 1 s Hann window has a main lobe of +-2 Hz, so lines 1 Hz apart blend into one peak.
- "esprit": least-squares ESPRIT (Roy & Kailath 1989, IEEE Trans. ASSP 37(7) 984-995; the
  single-record Hankel form of Stoica & Moses, Spectral Analysis of Signals, 2005, sec. 4.7, with
  forward-backward averaging) fits `model_order` real sinusoids and a straight line to the window: a
  parametric model, so its resolution is not tied to 1 / window. The amplitude of each line comes
  from a least-squares fit of the model's exponentials (Hua & Sarkar 1990, IEEE Trans. ASSP 38(5),
  step 2); the result is the frequency of the largest-amplitude line in [min_freq_hz, max_freq_hz]. A window
  sampled finer than SAMPLES_PER_PERIOD samples per period of max_freq_hz is first low-passed and decimated
  (`decimation_factor`; scipy's polyphase FIR, within the window): the SVD's cost grows as the cube of the
  window's samples (a flight log's 0.5 ms grid: 2000 samples a 1 s window, against 200 on the helicopter's 5 ms).
"""

from __future__ import annotations

import functools
import hashlib
import threading
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np
import scipy.linalg
from threadpoolctl import ThreadpoolController

from uavdamp.settings import require, setting
from uavdamp.signals import spectrum

METHODS = ("fft", "esprit")
KEY = "study.tracking"
SAMPLES_PER_PERIOD = 40  # the finest ESPRIT sees a window, per period of max_freq_hz (choice; module docstring)


@dataclass(frozen=True)
class TrackerOptions:
    """The tracker's settings: the config's `study.tracking` section (a typed section, `uavdamp.config.load`).

    method: "fft" or "esprit"; window: s; min_freq_hz, max_freq_hz: search band, Hz; min_cycles:
    periods of min_freq_hz needed before a first estimate; zero_padding: FFT length as a multiple of
    the window ("fft"); model_order: real sinusoids in the ESPRIT model besides a straight line
    ("esprit"; lines outside the band count too); initial_freq_hz: the frequency the ANFIS law assumes
    before the first estimate, Hz (not used by the tracker itself).
    """

    method: str
    model_order: int
    window: float = setting("window_s")
    min_freq_hz: float = setting()
    max_freq_hz: float = setting()
    min_cycles: float = setting()
    zero_padding: int = setting()
    initial_freq_hz: float = setting()

    def validate(self) -> None:
        require(self.method in METHODS, f"{KEY}.method", f"must be one of {METHODS}, got {self.method!r}")
        require(self.model_order >= 1, f"{KEY}.model_order", f"must be an integer >= 1, got {self.model_order!r}")
        require(self.zero_padding >= 1, f"{KEY}.zero_padding", f"must be an integer >= 1, got {self.zero_padding!r}")
        require(self.window > 0, f"{KEY}.window_s", f"must be positive, got {self.window!r}")
        require(self.min_cycles > 0, f"{KEY}.min_cycles", f"must be positive, got {self.min_cycles!r}")
        require(
            0 <= self.min_freq_hz < self.max_freq_hz,
            f"{KEY}.max_freq_hz",
            f"the band [{self.min_freq_hz}, {self.max_freq_hz}] Hz is empty",
        )
        require(self.initial_freq_hz > 0, f"{KEY}.initial_freq_hz", f"must be positive, got {self.initial_freq_hz!r}")


def trend_cutoff_hz(n: int, dt: float) -> float:
    """The frequency resolution 1 / (n dt), Hz, of n samples every dt s: ESPRIT poles below it are the trend."""
    return 1.0 / (n * dt)


def decimation_factor(dt: float, max_freq_hz: float) -> int:
    """The largest integer q (1: none) by which a window sampled every dt s is decimated before ESPRIT that keeps at
    least SAMPLES_PER_PERIOD samples per period of max_freq_hz."""
    return max(1, int(1.0 / (dt * SAMPLES_PER_PERIOD * max_freq_hz)))


@functools.cache
def _thread_pools() -> ThreadpoolController:
    """The process's thread pools, numpy's and scipy.linalg's OpenBLAS among them (both loaded by this module's
    imports), found once: `threadpool_limits` looks for them on every entry (0.7 ms, against 12 us for the
    controller's `limit`), twice per ESPRIT call before (4.3 s of the default benchmark's 558 s of samples)."""
    return ThreadpoolController()


def esprit_lines(segment: np.ndarray, dt: float, model_order: int) -> tuple[np.ndarray, np.ndarray]:
    """(freq_hz, amplitude) of the lines LS-ESPRIT finds in `segment` (sampled every dt s), ascending frequency.

    The model: model_order real sinusoids plus a straight line (a double pole at z = 1), i.e.
    2 model_order + 2 exponentials. The segment forms a Hankel matrix of N // 2 rows, extended by its
    forward-backward copy (rows and columns reversed: real data, conjugate-symmetric model); its
    2 model_order + 2 leading left singular vectors span the signal subspace, and the
    eigenvalues z of the least-squares rotation between the subspace's first and last N // 2 - 1 rows
    are the model's poles, f = arg(z) / (2 pi dt). The amplitudes come from a least-squares fit of
    all the (possibly damped) exponentials z^n to the segment: amplitude = 2 |c| times the
    RMS of the envelope |z|^n over the window (the signal's unit). Poles with arg 0 or pi (real z) are
    left out of the result, and so are the straight line's: its double pole at z = 1 splits into a pair near
    z = 1 (by round-off, |arg z| ~ sqrt(eps), a double eigenvalue moving by the square root of a perturbation;
    by noise, far more: 0.02-0.03 Hz in a 1 s window at 1 % noise). The cut is the frequency resolution
    1 / (N dt) (`trend_cutoff_hz`): a pole of less than one cycle in the window cannot be told from the trend
    (over less than a period a sinusoid and a straight line are nearly collinear), and no line of the
    tracker's band is below it once min_cycles >= 1 periods of min_freq_hz are in the window.
    """
    x = np.asarray(segment, dtype=float)
    n = x.size
    rows = n // 2
    n_exp = 2 * int(model_order) + 2
    if rows < n_exp + 2:
        raise ValueError(f"{KEY}.model_order: {model_order} sinusoids need more than {n} samples in the window")
    hankel = scipy.linalg.hankel(x[:rows], x[rows - 1 :])
    stacked = np.hstack([hankel, hankel[::-1, ::-1]])
    with _thread_pools().limit(limits=1):  # small dense problems: BLAS threads only contend (2.4 s against 0.06 s)
        u = scipy.linalg.svd(stacked, full_matrices=False)[0][:, :n_exp]
        z = scipy.linalg.eigvals(scipy.linalg.lstsq(u[:-1], u[1:])[0])
        m = np.arange(n) - 0.5 * (n - 1)
        log_envelope = np.clip(np.outer(m, np.log(np.abs(z) + 1e-300)), -50.0, 50.0)
        basis = np.exp(log_envelope + 1j * np.outer(m, np.angle(z)))
        basis /= np.sqrt(np.mean(np.abs(basis) ** 2, axis=0))
        coef = scipy.linalg.lstsq(basis, x.astype(complex))[0]
    angle = np.angle(z)
    trend = 2 * np.pi * dt * trend_cutoff_hz(n, dt)  # rad per sample: the trend's split pole pair is below it
    line = (angle >= trend) & (angle < np.pi - 1e-9)
    order = np.argsort(angle[line])
    return angle[line][order] / (2 * np.pi * dt), 2 * np.abs(coef[line][order])


_SEEN: OrderedDict = OrderedDict()  # (segment digest, dt, model_order) -> esprit_lines' result, the last _SEEN_SIZE
_SEEN_SIZE = 4096
_SEEN_LOCK = threading.Lock()  # joblib's threads may share the memory


def _esprit_lines_seen(segment: np.ndarray, dt: float, model_order: int) -> tuple[np.ndarray, np.ndarray]:
    """`esprit_lines`, remembered by the segment's bytes: every law of a run, and every damper and stiffness of a
    scenario, tracks the same mount signal at the same update times (a pure function: the same numbers)."""
    key = (hashlib.blake2b(segment.tobytes(), digest_size=16).digest(), segment.size, float(dt), int(model_order))
    with _SEEN_LOCK:
        if key in _SEEN:
            _SEEN.move_to_end(key)
            return _SEEN[key]
    found = esprit_lines(segment, dt, model_order)
    for array in found:
        array.flags.writeable = False
    with _SEEN_LOCK:
        _SEEN[key] = found
        while len(_SEEN) > _SEEN_SIZE:
            _SEEN.popitem(last=False)
    return found


def esprit_dominant(
    segment: np.ndarray, dt: float, *, model_order: int, min_freq_hz: float, max_freq_hz: float
) -> float:
    """Frequency, Hz, of the largest-amplitude ESPRIT line in [min_freq_hz, max_freq_hz]; NaN if none."""
    segment = np.ascontiguousarray(segment, dtype=float)
    if not np.any(segment != segment[0]):
        return float("nan")
    freq, amp = _esprit_lines_seen(segment, dt, model_order)
    band = (freq >= min_freq_hz) & (freq <= max_freq_hz)
    if not np.any(band):
        return float("nan")
    return float(freq[band][np.argmax(amp[band])])


def frequency_causal(time: np.ndarray, signal: np.ndarray, t_now: float, options: TrackerOptions) -> float:
    """Dominant frequency, Hz, of the last options.window s of `signal` up to and including t_now.

    Only samples with time <= t_now are used; NaN until `spectrum.required_span` s have been seen
    (window semantics: `spectrum.causal_segment`). method "fft" returns exactly
    `spectrum.dominant_frequency_causal` with these options.
    """
    if options.method == "fft":
        return spectrum.dominant_frequency_causal(
            time,
            signal,
            t_now,
            options.window,
            min_freq_hz=options.min_freq_hz,
            max_freq_hz=options.max_freq_hz,
            zero_padding=options.zero_padding,
            min_cycles=options.min_cycles,
        )
    found = spectrum.causal_segment(
        time, signal, t_now, options.window, min_freq_hz=options.min_freq_hz, min_cycles=options.min_cycles
    )
    if found is None:
        return float("nan")
    segment, dt = found
    q = decimation_factor(dt, options.max_freq_hz)
    if q > 1:  # low-passed below the new Nyquist (Kaiser window), the window's ends extended along a line
        import scipy.signal  # here: a window that needs no decimation (the 2 ms grids) spares a job its 0.65 s import

        segment, dt = scipy.signal.resample_poly(segment, 1, q, padtype="line"), dt * q
    return esprit_dominant(
        segment, dt, model_order=options.model_order, min_freq_hz=options.min_freq_hz, max_freq_hz=options.max_freq_hz
    )


def track(
    time: np.ndarray, signal: np.ndarray, *, update_period: float, options: TrackerOptions
) -> tuple[np.ndarray, np.ndarray]:
    """Causal track: (update times k update_period s, k = 1, 2, ... up to time[-1]; freq_hz), as
    `spectrum.track_dominant` but with any method."""
    time = np.asarray(time, dtype=float)
    times = spectrum.update_times(time[-1], update_period)
    return times, np.array([frequency_causal(time, signal, t, options) for t in times])
