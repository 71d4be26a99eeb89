"""ANFIS arithmetic shared by fit, predict and the gradient check (see ``uavdamp.anfis`` for the model).

Arrays are stored samples-last: X1T is (d + 1, n) with a last row of ones, Z (M, n) per MF, firing
strengths w and rule outputs f (R, n); reductions over rules are then fast.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.linalg

ILL_CONDITIONED = 1e-10  # switch to SVD when the Cholesky pivots suggest cond(A^T A) above 1e10
LSTSQ_RCOND = 1e-10  # singular values below this fraction of the largest are dropped


class Incidence:
    """Which membership function (MF) each rule uses for each input: sums over a rule's MFs and over an MF's rules.

    ``rule_mf`` (R, d): the MF index of rule r for input i. Both sums cost one pass per input over (R, n), not
    the R x M products of a dense 0/1 incidence matrix (65 times fewer for 65 clustered rules of 3 inputs): a
    rule's sum gathers its d MFs' rows; an MF's sum is a plain copy where every rule has its own MF for the input
    (clustering inits), else a small one-hot product (grid init: a few MFs per input shared by many rules).
    """

    def __init__(self, rule_mf: np.ndarray, n_mf_total: int):
        self.rule_mf = np.asarray(rule_mf, dtype=np.intp)
        self.n_mf = int(n_mf_total)
        self._shared = []  # per input: None (own MFs) or (its MF indices, one-hot (MFs, R))
        for column in self.rule_mf.T:
            mfs = np.unique(column)
            if mfs.size == column.size:
                self._shared.append(None)
            else:
                self._shared.append((mfs, (column[None, :] == mfs[:, None]).astype(float)))

    @property
    def n_rules(self) -> int:
        return self.rule_mf.shape[0]

    def rule_sum(self, V: np.ndarray) -> np.ndarray:
        """(R, n): for every rule, the sum over inputs of V at its MF (V is (M, n)), input by input."""
        out = V[self.rule_mf[:, 0]]
        for column in self.rule_mf.T[1:]:
            out += V[column]
        return out

    def mf_sum(self, U: np.ndarray) -> np.ndarray:
        """(M, n): for every MF, the sum of U (R, n) over the rules that use it."""
        out = np.zeros((self.n_mf, U.shape[1]))
        for column, shared in zip(self.rule_mf.T, self._shared, strict=True):
            if shared is None:
                out[column] = U
            else:
                out[shared[0]] = shared[1] @ U
        return out


def _incidence(rule_mf: np.ndarray, n_mf_total: int) -> Incidence:
    """The rules' MF incidence (see ``Incidence``)."""
    return Incidence(rule_mf, n_mf_total)


def _with_ones_row(X: np.ndarray) -> np.ndarray:
    """X (n, d) as a C-contiguous (d + 1, n) array with a last row of ones."""
    out = np.ones((X.shape[1] + 1, X.shape[0]))
    out[:-1] = X.T
    return out


def _firing(XT: np.ndarray, centres, sigmas, mf_input, incidence) -> tuple[np.ndarray, np.ndarray]:
    """Standardised distances Z = (x - c) / sigma (M, n) and normalised firing strengths (R, n).

    Arrays are stored samples-last (XT is (d, n)): reductions over rules are then fast.
    """
    Z = (XT[mf_input] - centres[:, None]) / sigmas[:, None]
    dist = incidence.rule_sum(Z * Z)  # -2 log w_r
    w = np.exp(-0.5 * (dist - dist.min(axis=0)))
    w /= w.sum(axis=0)
    return Z, w


def _predict(X: np.ndarray, input_range, centres, sigmas, mf_input, incidence, consequents) -> np.ndarray:
    """Output (n,) for X (n, d): each input clamped to its training range (input_range (d, 2)), then the rules'
    first-order outputs weighted by their normalised firing strengths. Shared by the estimator and the
    scikit-learn-free predictor (``uavdamp.anfis.predictor``), so that both give the same bits."""
    XcT = np.ascontiguousarray(np.clip(X, input_range[:, 0], input_range[:, 1]).T)
    w = _firing(XcT, centres, sigmas, mf_input, incidence)[1]
    f = consequents[:, :-1] @ XcT + consequents[:, -1:]
    return (w * f).sum(axis=0)


def _premise_gradient(Z, w, f, y_hat, err, sigmas, incidence) -> tuple[np.ndarray, np.ndarray]:
    """dE/dc and dE/dsigma per MF for E = sum(err^2), err = y - y_hat, consequents fixed.

    d y_hat / d log w_r = w_r (f_r - y_hat); d log mu / dc = Z / sigma; d log mu / dsigma = Z^2 / sigma.
    Shapes: Z (M, n), w and f (R, n), y_hat and err (n,).
    """
    dE_dlogw = (-2.0 * err) * w * (f - y_hat)
    HZ = incidence.mf_sum(dE_dlogw) * Z
    return HZ.sum(axis=1) / sigmas, (HZ * Z).sum(axis=1) / sigmas


def loss_and_gradient(X, y, centres, sigmas, mf_input, rule_mf, consequents) -> tuple[float, np.ndarray, np.ndarray]:
    """Training loss and its analytic gradient with respect to the premise parameters.

    X (n, d) and y (n,) in any consistent units; centres, sigmas (M,) with mf_input (M,) the input
    index of each MF; rule_mf (R, d) the MF index used by each rule for each input; consequents
    (R, d + 1), constant last (held fixed). Returns E = sum((y - y_hat)^2) and dE/dcentres,
    dE/dsigmas, each (M,). No clamping or scaling: this is the raw model ``fit`` differentiates.
    """
    X1T = _with_ones_row(np.asarray(X, float))
    y = np.asarray(y, float)
    centres, sigmas = np.asarray(centres, float), np.asarray(sigmas, float)
    inc = _incidence(np.asarray(rule_mf, int), centres.size)
    Z, w = _firing(X1T[:-1], centres, sigmas, np.asarray(mf_input, int), inc)
    f = np.asarray(consequents, float) @ X1T
    y_hat = (w * f).sum(axis=0)
    err = y - y_hat
    g_c, g_s = _premise_gradient(Z, w, f, y_hat, err, sigmas, inc)
    return float(err @ err), g_c, g_s


def _solve_consequents(w: np.ndarray, X1T: np.ndarray, y: np.ndarray, ridge: float) -> np.ndarray:
    """Least-squares consequents (R, d + 1) for normalised firing strengths w (R, n), X1T (d + 1, n).

    Cholesky on the normal equations (plus ``ridge`` * mean(diag)); when that fails, its pivots
    show a condition number above 1 / ILL_CONDITIONED, or there are more unknowns than rows, the
    truncated-SVD solution instead.
    """
    n_rules, n = w.shape
    AT = (w[:, None, :] * X1T[None, :, :]).reshape(-1, n)
    if AT.shape[0] > n:  # more unknowns than rows: A^T A is singular (and needlessly large)
        return np.linalg.lstsq(AT.T, y, rcond=LSTSQ_RCOND)[0].reshape(n_rules, X1T.shape[0])
    gram = scipy.linalg.blas.dsyrk(1.0, AT.T, trans=1)  # AT AT^T, upper triangle only (half the work of AT @ AT.T)
    gram.flat[:: gram.shape[0] + 1] += ridge * np.trace(gram) / gram.shape[0]
    factor, p, info = scipy.linalg.lapack.dposv(gram, AT @ y)  # reads the upper triangle
    pivots = np.abs(np.diag(factor))
    if info != 0 or pivots.min() ** 2 < ILL_CONDITIONED * pivots.max() ** 2:
        p = np.linalg.lstsq(AT.T, y, rcond=LSTSQ_RCOND)[0]
    return p.reshape(n_rules, X1T.shape[0])


def update_step_size(
    errors: Sequence[float], step: float, last_change: int, increase: float = 1.1, decrease: float = 0.9
) -> tuple[float, int]:
    """MATLAB anfis step-size rule, applied after each epoch.

    ``errors`` are the training errors so far (one per epoch, index k = len - 1 is the newest);
    ``last_change`` is the index at which the step last changed (0 at the start). Looking at the
    last five errors, all at or after ``last_change``: four consecutive decreases multiply the step
    by ``increase``; two consecutive alternations (up, down, up, down) multiply it by ``decrease``.
    Returns the new step and the new ``last_change``.
    """
    k = len(errors) - 1
    if k - last_change < 4:
        return step, last_change
    e = [float(v) for v in errors[k - 4 :]]
    up = [b > a for a, b in zip(e[:-1], e[1:], strict=True)]
    down = [b < a for a, b in zip(e[:-1], e[1:], strict=True)]
    if all(down):
        return step * increase, k
    if up[0] and down[1] and up[2] and down[3]:
        return step * decrease, k
    return step, last_change
