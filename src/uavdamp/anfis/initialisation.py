"""ANFIS rule initialisation: grid partition, fuzzy c-means and subtractive clustering.

Every function works on inputs scaled to [0, 1] by their training range (a constant input has span
0) and returns ``(centres, sigmas, mf_input, rule_mf)``: centres and sigmas (M,) of the Gaussian
MFs, mf_input (M,) the input index of each MF (grouped by input, ascending), rule_mf (R, d) the MF
index used by each rule for each input.

* grid: ``n_mfs[i]`` MFs evenly spaced over input i, neighbours crossing at 0.5, one rule per
  combination (MATLAB genfis1 / genfis "GridPartition"); the rule count is the product of n_mfs.
* fcm: fuzzy c-means (scikit-fuzzy) in the joint (input, output) space, one rule and one MF per
  input per cluster, sigma the fuzzy-weighted spread of the cluster (as MATLAB genfis3).
* subtractive: Chiu's subtractive clustering (Chiu 1994, "Fuzzy model identification based on
  cluster estimation"; the rule of MATLAB subclust / genfis2) in the joint space; the number of
  rules follows from the cluster ``radius``; sigma = radius * range / sqrt(8) per input (genfis2).
"""

from __future__ import annotations

import itertools

import numpy as np
from skfuzzy.cluster import cmeans

FCM_EXPONENT = 2.0  # fuzzifier m of fuzzy c-means (MATLAB genfis3 default)
FCM_TOLERANCE = 1e-5
FCM_MAX_ITER = 100
HALF_CROSSING = 2.0 * np.sqrt(2.0 * np.log(2.0))  # neighbours spaced by this many sigmas cross at 0.5
SQUASH = 1.25  # subtractive clustering: revision radius / cluster radius (Chiu; subclust default)
ACCEPT_RATIO = 0.5  # a potential above this fraction of the first centre's is always accepted
REJECT_RATIO = 0.15  # a potential below this fraction ends the search
_CHUNK = 2048  # rows per block of the pairwise potential (bounds memory at _CHUNK * n doubles)


def grid(span: np.ndarray, n_mfs: list[int]):
    """Grid partition: per input i, n_mfs[i] centres over [0, span[i]], one rule per MF combination."""
    centres, sigmas, mf_input = [], [], []
    for i, m in enumerate(n_mfs):
        spacing = span[i] / (m - 1) if m > 1 else span[i]
        centres.append(np.linspace(0.0, span[i], m) if m > 1 else np.array([span[i] / 2]))
        sigmas.append(np.full(m, spacing / HALF_CROSSING))
        mf_input.append(np.full(m, i))
    offsets = np.cumsum([0] + n_mfs[:-1])
    rule_mf = np.array(list(itertools.product(*[range(m) for m in n_mfs]))) + offsets
    return np.concatenate(centres), np.concatenate(sigmas), np.concatenate(mf_input), rule_mf


def _per_cluster(centres: np.ndarray, sigmas: np.ndarray):
    """Cluster centres and sigmas (R, d) as grouped MFs: input i owns MFs i*R .. i*R + R - 1."""
    n_rules, d = centres.shape
    mf_input = np.repeat(np.arange(d), n_rules)
    rule_mf = np.arange(n_rules)[:, None] + n_rules * np.arange(d)[None, :]
    return centres.T.ravel(), sigmas.T.ravel(), mf_input, rule_mf


def _scaled_output(y: np.ndarray) -> np.ndarray:
    span = np.ptp(y)
    return (y - y.min()) / (span if span > 0 else 1.0)


def fcm(Xs: np.ndarray, y: np.ndarray, n_rules: int, rng: np.random.Generator):
    """Fuzzy c-means with n_rules clusters on [Xs, y scaled to [0, 1]]; seeded initial partition."""
    n, d = Xs.shape
    u0 = rng.random((n_rules, n))
    u0 /= u0.sum(axis=0)
    # own seeded initial partition: cmeans' `seed` would reseed numpy's global generator
    data = np.column_stack([Xs, _scaled_output(y)]).T
    cntr, u = cmeans(data, n_rules, FCM_EXPONENT, FCM_TOLERANCE, FCM_MAX_ITER, init=u0)[:2]
    um = u**FCM_EXPONENT
    centres = cntr[:, :d]
    spread = np.einsum("rn,rni->ri", um, (Xs[None, :, :] - centres[:, None, :]) ** 2) / um.sum(axis=1)[:, None]
    return _per_cluster(centres, np.sqrt(spread))


def _potential(points: np.ndarray, alpha: float) -> np.ndarray:
    """P_i = sum_j exp(-alpha ||x_i - x_j||^2), computed in row blocks."""
    sq = (points**2).sum(axis=1)
    out = np.empty(len(points))
    for start in range(0, len(points), _CHUNK):
        block = points[start : start + _CHUNK]
        d2 = np.maximum(sq[start : start + _CHUNK, None] + sq[None, :] - 2.0 * block @ points.T, 0.0)
        out[start : start + _CHUNK] = np.exp(-alpha * d2).sum(axis=1)
    return out


def subtractive_centres(points: np.ndarray, radius: float) -> np.ndarray:
    """Chiu's subtractive clustering of points (n, k) already scaled to the unit box; centres (R, k).

    Every point's potential P_i = sum_j exp(-4 ||x_i - x_j||^2 / radius^2); the point of highest
    potential is the first centre (potential P_1). After each accepted centre x* of potential P*,
    every potential is reduced by P* exp(-4 ||x_i - x*||^2 / (SQUASH radius)^2). The next candidate
    (highest remaining potential P) is accepted if P > ACCEPT_RATIO P_1, ends the search if
    P < REJECT_RATIO P_1, and in between is accepted only if d_min / radius + P / P_1 >= 1 (d_min its
    distance to the nearest centre); a candidate so rejected gets potential 0 and the next is tried.
    """
    alpha, beta = 4.0 / radius**2, 4.0 / (SQUASH * radius) ** 2
    potential = _potential(points, alpha)
    first = potential.max()
    centres: list[np.ndarray] = []
    while True:
        k = int(np.argmax(potential))
        p = potential[k]
        if centres and p < REJECT_RATIO * first:
            break
        if centres and p <= ACCEPT_RATIO * first:
            d_min = np.sqrt(((np.asarray(centres) - points[k]) ** 2).sum(axis=1).min())
            if d_min / radius + p / first < 1.0:
                potential[k] = 0.0
                if potential.max() <= 0.0:
                    break
                continue
        centres.append(points[k].copy())
        potential = potential - p * np.exp(-beta * ((points - points[k]) ** 2).sum(axis=1))
        if len(centres) == len(points):
            break
    return np.asarray(centres)


def subtractive(Xs: np.ndarray, y: np.ndarray, span: np.ndarray, radius: float):
    """Subtractive clustering on [Xs, y scaled to [0, 1]]; sigma = radius * span / sqrt(8) per input."""
    centres = subtractive_centres(np.column_stack([Xs, _scaled_output(y)]), radius)[:, : Xs.shape[1]]
    sigmas = np.broadcast_to(radius * span / np.sqrt(8.0), centres.shape)
    return _per_cluster(centres, np.array(sigmas))
