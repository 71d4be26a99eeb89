"""`uavdamp.platform.wire_rope`'s steps, compiled (`uavdamp.platform.wire_rope_kernel`), against the same scheme
written here with numpy arrays (the loop the kernel replaced): the whole held run in one call, a schedule stepped
one sample at a time, more than one fixed-point pass, and a Bouc-Wen exponent other than 1. The scheme itself is
checked against independent integrations in tests/test_wire_rope.py."""

from __future__ import annotations

import numpy as np
import pytest
from test_wire_rope import C, H, isolator, mount

from uavdamp.platform import wire_rope
from uavdamp.platform.wire_rope import WireRope

YIELDING = {"alpha": 0.3, "yield_stroke": 5e-4, "beta_share": 0.75}  # 2 mm strokes: four times the yield stroke


def numpy_steps(wire, bank, u, n_c, choose, iterations):
    """The scheme with numpy arrays, every run of the batch at once, one step after another."""
    h_rows, h = bank.h_rows, bank.h
    n_h, u = h_rows.shape[0], np.broadcast_to(u, (n_c, *u.shape[-2:]))
    n = u.shape[1]
    slopes = np.diff(u, axis=1) / h
    mount_strokes = u @ h_rows.T
    w, z = np.zeros((n_c, n, 12)), np.zeros((n_c, n, n_h))
    w[:, 0, :6], w[:, 0, 6:] = u[:, 0], slopes[:, 0]
    s_k, de = np.zeros((n_c, n_h)), np.zeros((n_c, n_h))
    for k in range(n - 1):
        maps, ge1, p = bank.take(choose(k, w[:, k]))
        inputs = np.concatenate([w[:, k], s_k - z[:, k], u[:, k], slopes[:, k]], axis=1)
        base = np.einsum("cij,cj->ci", maps, inputs)
        d0 = base[:, :6] @ h_rows.T - mount_strokes[:, k + 1] - s_k
        for _ in range(iterations):
            ds = d0 + np.einsum("cij,cj->ci", p, de)
            direction = np.sign(ds)
            slope0 = wire.phi(z[:, k], direction)
            dz = 0.5 * ds * (slope0 + wire.phi(z[:, k] + ds * slope0, direction))
            de = ds - dz
        w[:, k + 1] = base + np.einsum("cij,cj->ci", ge1, de)
        z[:, k + 1] = z[:, k] + dz
        s_k = s_k + ds
    return w, z


def _batch(duration: float = 0.25):
    """The mount's coordinates (n, 6) at 2 mm and 2 mrad, a bank of step maps, and three dampings (N s m-1)."""
    t, tr, rot = mount(duration, 2e-3)
    return np.vstack([tr, rot]).T, [[1.0] * 4, C, [30.0, 3.0, 100.0, 10.0]]


def _compare(got, ref):
    """Equal to rounding: the kernel sums the same products in another order (about 1e-16 relative a step, grown
    by the run's 500 steps, whose exact step maps neither amplify nor damp it much)."""
    for a, b in zip(got, ref, strict=True):
        scale = np.abs(b).max()
        assert scale > 0
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * scale)


@pytest.mark.parametrize(("exponent", "iterations"), [(1.0, 1), (2.0, 1), (1.0, 3)])
def test_a_held_run_is_the_numpy_schemes(monkeypatch, exponent, iterations):
    """`integrate`'s path (held maps, the whole run in one compiled call) on a yielding batch of three dampings."""
    monkeypatch.setattr(wire_rope, "ITERATIONS", iterations)
    wire = WireRope(exponent=exponent, **YIELDING)
    u, dampings = _batch()
    bank = wire_rope._Bank(isolator(), wire, H)
    keys = [bank.find(c) for c in dampings]
    got = wire_rope._steps(wire, bank, u, len(keys), lambda k, w_k: keys, held=True)
    ref = numpy_steps(wire, bank, u, len(keys), lambda k, w_k: keys, iterations)
    assert np.abs(ref[1]).max() > 0.99 * wire.yield_stroke  # the elements yield
    _compare(got, ref)


def test_a_schedule_decided_at_every_sample_is_the_numpy_schemes():
    """`integrate_scheduled`'s path (one compiled step a sample): a rule switching each run between two dampings on
    its own states, so that the maps change within the run and the decisions read the states the kernel wrote."""
    wire = WireRope(**YIELDING)
    u, dampings = _batch()
    bank = wire_rope._Bank(isolator(), wire, H)
    low, high = bank.find(dampings[0]), bank.find(dampings[2])

    def choose(k, w_k):  # the payload's x rate against its x displacement: on where they agree
        return [high if w_k[b, 6] * w_k[b, 0] > 0 else low for b in range(len(w_k))]

    calls = []
    got = wire_rope._steps(wire, bank, u, 2, lambda k, w_k: calls.append(k) or choose(k, w_k))
    ref = numpy_steps(wire, bank, u, 2, choose, wire_rope.ITERATIONS)
    assert calls == list(range(len(u)))  # every sample asked, the last one included
    _compare(got, ref)


def test_a_held_run_in_one_call_is_the_same_run_stepped_sample_by_sample():
    """The two paths through the kernel agree exactly: the same products in the same order."""
    wire = WireRope(**YIELDING)
    u, dampings = _batch(0.05)
    bank = wire_rope._Bank(isolator(), wire, H)
    keys = [bank.find(c) for c in dampings]
    held = wire_rope._steps(wire, bank, u, len(keys), lambda k, w_k: keys, held=True)
    stepped = wire_rope._steps(wire, bank, u, len(keys), lambda k, w_k: keys)
    for a, b in zip(held, stepped, strict=True):
        np.testing.assert_array_equal(a, b)


def test_every_path_calls_the_kernel_with_one_signature(monkeypatch):
    """A second signature is a second compilation (seconds in a fresh clone): a held run of one mount motion (its
    broadcast to the batch a copy), a held batch already as wide as its runs (the broadcast a read-only view of it,
    as `sine_transmissibility`'s) and a schedule stepped sample by sample give the kernel the same argument types."""
    from numba import typeof

    from uavdamp.platform import wire_rope_kernel as kernel

    kernel.compile_now()
    real, seen = kernel.advance, set()

    def spy(*args):
        seen.add(tuple(typeof(a) for a in args))
        return real(*args)

    monkeypatch.setattr(kernel, "advance", spy)
    wire = WireRope(**YIELDING)
    u, dampings = _batch(0.02)
    bank = wire_rope._Bank(isolator(), wire, H)
    keys = [bank.find(c) for c in dampings]
    wide = np.ascontiguousarray(np.broadcast_to(u, (len(keys), *u.shape)))
    for mount_input, held in ((u, True), (wide, True), (u, False)):
        wire_rope._steps(wire, bank, mount_input, len(keys), lambda k, w_k: keys, held=held)
    assert len(seen) == 1, seen
