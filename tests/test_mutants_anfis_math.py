"""The ANFIS learning rule's linear algebra and step-size rule against independent computations (issue 17).

The consequents are a least-squares problem A p = y with A's columns w_r * [x, 1]: the ridge solution is
(A^T A + ridge * mean(diag(A^T A)) I)^-1 A^T y (scipy.linalg.solve), and where the problem is rank-deficient or
ill-conditioned the documented answer is the truncated-SVD one, pinv(A, rtol=1e-10) y.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

from uavdamp import anfis_math


def _problem(n: int, n_rules: int, seed: int = 4):
    rng = np.random.default_rng(seed)
    X = rng.uniform(-1, 1, (n, 2))
    w = rng.uniform(0.1, 1.0, (n_rules, n))
    w /= w.sum(axis=0)
    X1T = anfis_math._with_ones_row(X)
    A = (w[:, None, :] * X1T[None, :, :]).reshape(-1, n).T  # (n, rules * 3)
    y = rng.normal(size=n)
    return w, X1T, A, y


@pytest.mark.parametrize("n", [40, 6])  # more rows than unknowns, and exactly as many (2 rules x 3)
def test_ridge_consequents_are_the_regularised_normal_equations(n):
    w, X1T, A, y = _problem(n, 2)
    ridge = 0.3
    gram = A.T @ A
    expected = scipy.linalg.solve(gram + ridge * np.trace(gram) / gram.shape[0] * np.eye(gram.shape[0]), A.T @ y)
    got = anfis_math._solve_consequents(w, X1T, y, ridge)
    assert got.shape == (2, 3)
    np.testing.assert_allclose(got.ravel(), expected, rtol=1e-9, atol=1e-12)


def test_more_unknowns_than_rows_takes_the_minimum_norm_solution_ignoring_ridge():
    w, X1T, A, y = _problem(5, 3)  # 9 unknowns, 5 rows
    expected = scipy.linalg.pinv(A, rtol=1e-10) @ y
    got = anfis_math._solve_consequents(w, X1T, y, 0.5)
    np.testing.assert_allclose(got.ravel(), expected, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("gap", [1e-6, 1e-12])
def test_an_ill_conditioned_problem_takes_the_truncated_svd_solution(gap):
    """Two rules firing alike up to `gap`: cond(A) ~ 1 / gap. At 1e-6 the Cholesky of A^T A (cond 1e12) succeeds
    but loses 6 digits, so the SVD path is taken (its answer: QR least squares to cond eps = 1e-10 of the
    largest); at 1e-12 the singular values below 1e-10 of the largest are dropped (pinv(A, rtol=1e-10) y),
    not inverted."""
    w, X1T, A, y = _problem(40, 2)
    w[1] = w[0] + gap * np.random.default_rng(1).uniform(0, 1, 40)
    A = (w[:, None, :] * X1T[None, :, :]).reshape(-1, 40).T
    got = anfis_math._solve_consequents(w, X1T, y, 0.0).ravel()
    if gap > 1e-9:
        expected = scipy.linalg.lstsq(A, y, lapack_driver="gelsy")[0]
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-7 * np.abs(expected).max())
    else:
        expected = scipy.linalg.pinv(A, rtol=1e-10) @ y
        np.testing.assert_allclose(got, expected, rtol=1e-6, atol=1e-9)


@pytest.mark.parametrize(
    ("errors", "expected_step", "expected_change"),
    [
        ([1.0, 0.9, 0.8, 0.7, 0.6], 1.1, 4),  # four decreases: x 1.1
        ([1.0, 1.2, 1.1, 1.3, 1.2], 0.9, 4),  # up, down, up, down: x 0.9
        ([1.0, 1.0, 0.5, 0.8, 0.4], 1.0, 0),  # a tie is not an increase: no change
        ([1.0, 0.9, 0.8, 0.85, 0.7], 1.0, 0),  # only the second half alternates
        ([1.0, 1.1, 1.2, 1.3, 1.4], 1.0, 0),  # four increases
        ([1.0, 1.2, 1.1, 1.3], 1.0, 0),  # fewer than five errors since the last change
    ],
)
def test_step_size_rule_cases(errors, expected_step, expected_change):
    step, change = anfis_math.update_step_size(errors, 1.0, 0)
    assert step == pytest.approx(expected_step, rel=1e-15) and change == expected_change


def test_step_size_rule_counts_from_the_last_change():
    errors = [1.0, 0.9, 0.8, 0.7, 0.6, 0.5, 0.4]
    assert anfis_math.update_step_size(errors, 2.0, 4) == (2.0, 4)  # 2 errors since index 4
    step, change = anfis_math.update_step_size(errors, 2.0, 2)
    assert step == pytest.approx(2.2, rel=1e-15) and change == 6
