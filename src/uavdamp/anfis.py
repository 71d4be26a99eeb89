"""ANFIS: a first-order Takagi-Sugeno neuro-fuzzy regressor trained with Jang's hybrid rule.

The model (Jang 1993, as in MATLAB's ``anfis``), for inputs x = (x_1 .. x_d):

    mu_m(x_i) = exp(-(x_i - c_m)^2 / (2 sigma_m^2))          Gaussian membership functions (MFs)
    w_r       = prod_i mu_{m(r, i)}(x_i)                       product AND, one MF per input per rule
    f_r       = p_r1 x_1 + ... + p_rd x_d + p_r0               first-order consequents
    y         = sum_r w_r f_r / sum_r w_r                      normalised weighted average

Training (``fit``), once per epoch: the consequents by least squares on the whole batch, then the
premise parameters (every c and sigma) one step along the normalised gradient of the squared error,
step = step_size * g / ||g||, with the step size adapted as in MATLAB's ``anfis``
(see ``update_step_size``).

Choices worth knowing (each is a guard the issue asks for):

* Units. Everything stored or printed (centres, sigmas, consequents, ranges) is in the original
  input and output units. Internally ``fit`` works on inputs scaled to [0, 1] by their training
  range, so that ``step_size`` and ``min_sigma_frac`` are fractions of each input's range whatever
  its unit (a step of 0.01 Hz and 0.01 N/m would otherwise mean very different things). The
  parameters are mapped back to original units when a snapshot is kept; ``predict`` computes in
  original units from exactly the stored numbers, so a save/load round trip is bit-identical.
* Zero firing strength. Firing strengths are normalised in log space (a softmax of
  sum_i log mu), which equals w_r / sum w_r but never divides 0 by 0.
* Inputs outside the training range are clamped to it, per input, before evaluation: the model
  does not extrapolate, and far-away inputs give the prediction at the nearest edge of the
  training box (finite and bounded).
* A constant input (zero range) warns; it gets a nominal scale max(|value|, 1) for the internal
  scaling and is clamped to its single value in ``predict``, so the model ignores it.
* Widths: after each step every sigma is floored at ``min_sigma_frac`` times its input's range.
* Least squares: the normal equations A^T A p = A^T y, solved by Cholesky, which was ten times
  faster here than an SVD ``lstsq`` on A and agrees with it to ~1e-12 when A is well conditioned.
  When Cholesky fails or its pivots show cond(A^T A) > 1e10 (collinear columns: duplicate rows,
  a constant input, rules that never fire), the minimum-norm truncated-SVD solution is used
  instead (numpy ``lstsq``, singular values below 1e-10 of the largest dropped). An optional
  Tikhonov term ``ridge`` * mean(diag(A^T A)) (default 0) regularises the normal equations, as
  the start S_0 = gamma I of Jang's sequential least squares does with an absolute 1 / gamma.

No file I/O here: ``to_dataset`` / ``from_dataset`` convert to and from an ``xarray.Dataset``.
"""

from __future__ import annotations

import inspect
import itertools
import json
import numbers
import warnings
from collections.abc import Sequence

import numpy as np
import scipy.linalg
import xarray as xr
from skfuzzy.cluster import cmeans

from uavdamp.io import json_default

MAX_RULES = 4096
FCM_EXPONENT = 2.0  # fuzzifier m of fuzzy c-means (MATLAB genfis3 default)
FCM_TOLERANCE = 1e-5
FCM_MAX_ITER = 100
ILL_CONDITIONED = 1e-10  # switch to SVD when the Cholesky pivots suggest cond(A^T A) above 1e10
LSTSQ_RCOND = 1e-10  # singular values below this fraction of the largest are dropped
_HALF_CROSSING = 2.0 * np.sqrt(2.0 * np.log(2.0))  # neighbours spaced by this many sigmas cross at 0.5


# ---------------------------------------------------------------------------------------------
# Model arithmetic, shared by fit, predict and the gradient check


def _incidence(rule_mf: np.ndarray, n_mf_total: int) -> np.ndarray:
    """(rules, MFs) 0/1 matrix: entry (r, m) is 1 when rule r uses membership function m."""
    inc = np.zeros((rule_mf.shape[0], n_mf_total))
    np.put_along_axis(inc, rule_mf, 1.0, axis=1)
    return inc


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
    dist = incidence @ (Z * Z)  # -2 log w_r
    w = np.exp(-0.5 * (dist - dist.min(axis=0)))
    w /= w.sum(axis=0)
    return Z, w


def _premise_gradient(Z, w, f, y_hat, err, sigmas, incidence) -> tuple[np.ndarray, np.ndarray]:
    """dE/dc and dE/dsigma per MF for E = sum(err^2), err = y - y_hat, consequents fixed.

    d y_hat / d log w_r = w_r (f_r - y_hat); d log mu / dc = Z / sigma; d log mu / dsigma = Z^2 / sigma.
    Shapes: Z (M, n), w and f (R, n), y_hat and err (n,).
    """
    dE_dlogw = (-2.0 * err) * w * (f - y_hat)
    HZ = (incidence.T @ dE_dlogw) * Z
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

    Cholesky on the normal equations (plus ``ridge`` * mean(diag)); when that fails or its pivots
    show a condition number above 1 / ILL_CONDITIONED, the truncated-SVD solution instead.
    """
    n_rules, n = w.shape
    AT = (w[:, None, :] * X1T[None, :, :]).reshape(-1, n)
    gram = AT @ AT.T
    gram.flat[:: gram.shape[0] + 1] += ridge * np.trace(gram) / gram.shape[0]
    factor, p, info = scipy.linalg.lapack.dposv(gram, AT @ y)
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
    up = [b > a for a, b in zip(e, e[1:])]
    down = [b < a for a, b in zip(e, e[1:])]
    if all(down):
        return step * increase, k
    if up[0] and down[1] and up[2] and down[3]:
        return step * decrease, k
    return step, last_change


class NotFittedError(RuntimeError, AttributeError):
    """The model is used before ``fit`` or ``from_dataset``."""


# ---------------------------------------------------------------------------------------------
# Argument checks


def _is_int(value) -> bool:
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def _is_real(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool) and np.isfinite(value)


def _check_array(name: str, value, ndim: int, n_cols: int | None = None) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be numeric: {exc}") from None
    if arr.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-D, got shape {arr.shape}")
    if arr.shape[0] == 0:
        raise ValueError(f"{name} has no rows")
    if n_cols is not None and arr.shape[1] != n_cols:
        raise ValueError(f"{name} has {arr.shape[1]} columns, the model has {n_cols} inputs")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains non-finite values (NaN or inf)")
    return arr


def _unit_suffix(unit: str) -> str:
    return "" if unit in ("", "1") else " " + unit


def _ratio_units(out: str, inp: str) -> str:
    if inp in ("", "1"):
        return out
    return f"1/({inp})" if out in ("", "1") else f"({out})/({inp})"


# ---------------------------------------------------------------------------------------------


class ANFIS:
    """First-order Takagi-Sugeno ANFIS regressor with Gaussian MFs and hybrid learning.

    Parameters (stored as given, checked in ``fit``):
        n_mfs: MFs per input for ``init="grid"`` (int, or one int per input); ignored by "fcm".
        init: "grid" (centres evenly spaced over each input's range, neighbours crossing at 0.5,
            one rule per combination of MFs) or "fcm" (fuzzy c-means on the scaled inputs and
            output, one rule and one MF per input per cluster; sigma = fuzzy-weighted spread).
        n_rules: number of clusters/rules for "fcm" (required there); ignored by "grid".
        epochs: maximum number of training epochs (>= 1).
        error_goal: stop when the training RMSE (output units) falls to or below this.
        step_size: initial premise step, as a fraction of the inputs' ranges (default 0.01).
        step_increase, step_decrease: step-size factors (> 1 and in (0, 1)), see update_step_size.
        min_sigma_frac: floor of every sigma as a fraction of its input's range.
        ridge: relative Tikhonov term of the consequent least squares (>= 0, default 0).
        random_state: int seed (or None) of numpy.random.default_rng; used by "fcm" only.
        input_names, input_units: one string per input (default x1.., "1").
        output_name, output_units: name and unit of the output.

    Fitted attributes (original units): ``centres_``, ``sigmas_`` and ``initial_centres_``,
    ``initial_sigmas_`` (M,), ``mf_input_`` (M,) input index of each MF, ``rule_mf_`` (R, d) MF
    index of each rule and input, ``consequents_`` (R, d + 1) with the constant last,
    ``input_range_`` (d, 2), ``train_rmse_``, ``val_rmse_`` (empty without validation data) and
    ``step_sizes_`` per epoch, ``best_epoch_`` (1-based: the kept snapshot is epoch
    ``best_epoch_``, i.e. ``train_rmse_[best_epoch_ - 1]``).
    """

    def __init__(
        self,
        n_mfs: int | Sequence[int] = 2,
        init: str = "grid",
        n_rules: int | None = None,
        epochs: int = 100,
        error_goal: float = 0.0,
        step_size: float = 0.01,
        step_increase: float = 1.1,
        step_decrease: float = 0.9,
        min_sigma_frac: float = 0.01,
        ridge: float = 0.0,
        random_state: int | None = 0,
        input_names: Sequence[str] | None = None,
        input_units: Sequence[str] | None = None,
        output_name: str = "y",
        output_units: str = "1",
    ):
        self.n_mfs = n_mfs
        self.init = init
        self.n_rules = n_rules
        self.epochs = epochs
        self.error_goal = error_goal
        self.step_size = step_size
        self.step_increase = step_increase
        self.step_decrease = step_decrease
        self.min_sigma_frac = min_sigma_frac
        self.ridge = ridge
        self.random_state = random_state
        self.input_names = input_names
        self.input_units = input_units
        self.output_name = output_name
        self.output_units = output_units

    # -- scikit-learn style parameter handling -------------------------------------------------

    @classmethod
    def _param_names(cls) -> list[str]:
        return [name for name in inspect.signature(cls.__init__).parameters if name != "self"]

    def get_params(self, deep: bool = True) -> dict:
        """Constructor arguments as a dict (``deep`` is accepted for scikit-learn compatibility)."""
        return {name: getattr(self, name) for name in self._param_names()}

    def set_params(self, **params) -> ANFIS:
        """Set constructor arguments; unknown names raise ValueError. Returns self."""
        valid = self._param_names()
        for name, value in params.items():
            if name not in valid:
                raise ValueError(f"invalid parameter {name!r} for ANFIS; valid parameters: {', '.join(valid)}")
            setattr(self, name, value)
        return self

    def __repr__(self) -> str:
        defaults = inspect.signature(type(self).__init__).parameters
        changed = [f"{k}={v!r}" for k, v in self.get_params().items() if not _same(v, defaults[k].default)]
        return f"ANFIS({', '.join(changed)})"

    def _check_params(self, n_inputs: int, n_samples: int) -> list[int]:
        """Validate the constructor arguments for data with n_inputs columns; return MFs per input."""
        if self.init not in ("grid", "fcm"):
            raise ValueError(f"init must be 'grid' or 'fcm', got {self.init!r}")
        if self.init == "grid":
            n_mfs = [self.n_mfs] * n_inputs if _is_int(self.n_mfs) else self.n_mfs
            if (
                isinstance(n_mfs, (str, bytes))
                or not isinstance(n_mfs, (Sequence, np.ndarray))
                or len(n_mfs) != n_inputs
                or not all(_is_int(m) and m >= 1 for m in n_mfs)
            ):
                raise ValueError(f"n_mfs must be a positive int or {n_inputs} positive ints, got {self.n_mfs!r}")
            n_mfs = [int(m) for m in n_mfs]
            if np.prod(n_mfs, dtype=float) > MAX_RULES:
                raise ValueError(f"n_mfs={self.n_mfs!r} gives more than {MAX_RULES} grid rules; use init='fcm'")
        else:
            if not (_is_int(self.n_rules) and 1 <= self.n_rules <= n_samples):
                raise ValueError(
                    f"n_rules must be an int between 1 and the number of samples ({n_samples}) "
                    f"for init='fcm', got {self.n_rules!r}"
                )
            n_mfs = [int(self.n_rules)] * n_inputs
        if not (_is_int(self.epochs) and self.epochs >= 1):
            raise ValueError(f"epochs must be an int >= 1, got {self.epochs!r}")
        checks = [
            ("error_goal", lambda v: v >= 0, ">= 0"),
            ("step_size", lambda v: v > 0, "> 0"),
            ("step_increase", lambda v: v > 1, "> 1"),
            ("step_decrease", lambda v: 0 < v < 1, "in (0, 1)"),
            ("min_sigma_frac", lambda v: 0 < v <= 1, "in (0, 1]"),
            ("ridge", lambda v: v >= 0, ">= 0"),
        ]
        for name, ok, text in checks:
            value = getattr(self, name)
            if not (_is_real(value) and ok(value)):
                raise ValueError(f"{name} must be a finite number {text}, got {value!r}")
        if self.random_state is not None and not (_is_int(self.random_state) and self.random_state >= 0):
            raise ValueError(f"random_state must be None or an int >= 0, got {self.random_state!r}")
        for name in ("input_names", "input_units"):
            value = getattr(self, name)
            if value is not None and (
                isinstance(value, str)
                or not isinstance(value, Sequence)
                or len(value) != n_inputs
                or not all(isinstance(v, str) for v in value)
            ):
                raise ValueError(f"{name} must be None or {n_inputs} strings (one per input), got {value!r}")
        if self.input_names is not None and (len(set(self.input_names)) != n_inputs or "" in self.input_names):
            raise ValueError(f"input_names must be distinct non-empty strings, got {self.input_names!r}")
        if not (isinstance(self.output_name, str) and self.output_name):
            raise ValueError(f"output_name must be a non-empty string, got {self.output_name!r}")
        if not isinstance(self.output_units, str):
            raise ValueError(f"output_units must be a string, got {self.output_units!r}")
        return n_mfs

    # -- initialisation (in scaled inputs) -----------------------------------------------------

    def _init_grid(self, span: np.ndarray, n_mfs: list[int]):
        centres, sigmas, mf_input = [], [], []
        for i, m in enumerate(n_mfs):
            spacing = span[i] / (m - 1) if m > 1 else span[i]
            centres.append(np.linspace(0.0, span[i], m) if m > 1 else np.array([span[i] / 2]))
            sigmas.append(np.full(m, spacing / _HALF_CROSSING))
            mf_input.append(np.full(m, i))
        offsets = np.cumsum([0] + n_mfs[:-1])
        rule_mf = np.array(list(itertools.product(*[range(m) for m in n_mfs]))) + offsets
        return np.concatenate(centres), np.concatenate(sigmas), np.concatenate(mf_input), rule_mf

    def _init_fcm(self, Xs: np.ndarray, y: np.ndarray, rng: np.random.Generator):
        n, d = Xs.shape
        n_rules = int(self.n_rules)
        y_span = np.ptp(y)
        ys = (y - y.min()) / (y_span if y_span > 0 else 1.0)
        u0 = rng.random((n_rules, n))
        u0 /= u0.sum(axis=0)
        # own seeded initial partition: cmeans' `seed` would reseed numpy's global generator
        cntr, u = cmeans(np.column_stack([Xs, ys]).T, n_rules, FCM_EXPONENT, FCM_TOLERANCE, FCM_MAX_ITER, init=u0)[:2]
        um = u**FCM_EXPONENT
        centres = cntr[:, :d]  # (R, d)
        spread = np.einsum("rn,rni->ri", um, (Xs[None, :, :] - centres[:, None, :]) ** 2) / um.sum(axis=1)[:, None]
        sigmas = np.sqrt(spread)
        # MFs grouped by input: input i owns MFs i*R .. i*R + R - 1, rule r uses MF r of each input
        mf_input = np.repeat(np.arange(d), n_rules)
        rule_mf = np.arange(n_rules)[:, None] + n_rules * np.arange(d)[None, :]
        return centres.T.ravel(), sigmas.T.ravel(), mf_input, rule_mf

    # -- training ------------------------------------------------------------------------------

    def fit(self, X, y, X_val=None, y_val=None) -> ANFIS:
        """Train on X (n, d) and y (n,); with X_val, y_val keep the epoch of lowest validation RMSE.

        Without validation data the kept snapshot is the epoch of lowest training RMSE (as MATLAB's
        anfis). Each epoch's RMSE is that of the premise at the start of the epoch with its
        least-squares consequents, i.e. exactly the model kept if that epoch is best.
        """
        X = _check_array("X", X, 2)
        y = _check_array("y", y, 1)
        n, d = X.shape
        if y.shape[0] != n:
            raise ValueError(f"y has {y.shape[0]} values, X has {n} rows")
        if (X_val is None) != (y_val is None):
            raise ValueError("X_val and y_val must be given together")
        n_mfs = self._check_params(d, n)
        names = list(self.input_names) if self.input_names is not None else [f"x{i + 1}" for i in range(d)]
        units = list(self.input_units) if self.input_units is not None else ["1"] * d
        validate = X_val is not None
        if validate:
            X_val = _check_array("X_val", X_val, 2, d)
            y_val = _check_array("y_val", y_val, 1)
            if y_val.shape[0] != X_val.shape[0]:
                raise ValueError(f"y_val has {y_val.shape[0]} values, X_val has {X_val.shape[0]} rows")

        lo, hi = X.min(axis=0), X.max(axis=0)
        span = hi - lo
        for i in np.flatnonzero(span == 0):
            warnings.warn(
                f"ANFIS input {names[i]!r} is constant ({lo[i]:g}{_unit_suffix(units[i])}) in the training "
                "data: its membership functions cannot be fitted and predict clamps it to that value, "
                "so the model ignores it",
                UserWarning,
                stacklevel=2,
            )
        scale = np.where(span > 0, span, np.maximum(np.abs(lo), 1.0))
        Xs = (X - lo) / scale
        span_s = span / scale  # 1, or 0 for a constant input

        rng = np.random.default_rng(self.random_state)
        if self.init == "grid":
            c, s, mf_input, rule_mf = self._init_grid(span_s, n_mfs)
        else:
            c, s, mf_input, rule_mf = self._init_fcm(Xs, y, rng)
        s = np.maximum(s, self.min_sigma_frac)
        c0, s0 = c.copy(), s.copy()
        inc = _incidence(rule_mf, c.size)
        X1T = _with_ones_row(Xs)  # samples last, constant row for the consequents
        if validate:
            Xv1T = _with_ones_row(np.clip((X_val - lo) / scale, 0.0, span_s))

        step, last_change = float(self.step_size), 0
        train_rmse, val_rmse, steps = [], [], []
        best = (np.inf, 0, c, s, None)
        for epoch in range(1, self.epochs + 1):
            Z, w = _firing(X1T[:-1], c, s, mf_input, inc)
            P = _solve_consequents(w, X1T, y, self.ridge)
            f = P @ X1T
            y_hat = (w * f).sum(axis=0)
            err = y - y_hat
            train_rmse.append(np.sqrt(err @ err / n))
            steps.append(step)
            if validate:
                ev = y_val - (_firing(Xv1T[:-1], c, s, mf_input, inc)[1] * (P @ Xv1T)).sum(axis=0)
                val_rmse.append(np.sqrt(ev @ ev / ev.size))
            criterion = val_rmse[-1] if validate else train_rmse[-1]
            if criterion < best[0]:
                best = (criterion, epoch, c, s, P)  # c, s are rebound below, never modified in place
            if train_rmse[-1] <= self.error_goal:
                break
            g_c, g_s = _premise_gradient(Z, w, f, y_hat, err, s, inc)
            norm = np.sqrt(g_c @ g_c + g_s @ g_s)
            if norm > 0 and np.isfinite(norm):
                c = c - step * g_c / norm
                s = np.maximum(s - step * g_s / norm, self.min_sigma_frac)
            step, last_change = update_step_size(train_rmse, step, last_change, self.step_increase, self.step_decrease)

        if best[4] is None:  # only if every error was NaN, which the guards rule out
            raise FloatingPointError("ANFIS training produced no finite error")
        _, self.best_epoch_, c, s, P = best
        # back to original units: x = lo + scale * xs
        self.n_features_in_ = d
        self.input_names_, self.input_units_ = names, units
        self.input_range_ = np.column_stack([lo, hi])
        self.mf_input_ = mf_input
        self.rule_mf_ = rule_mf
        self.centres_ = lo[mf_input] + scale[mf_input] * c
        self.sigmas_ = scale[mf_input] * s
        self.initial_centres_ = lo[mf_input] + scale[mf_input] * c0
        self.initial_sigmas_ = scale[mf_input] * s0
        coef = P[:, :-1] / scale
        self.consequents_ = np.column_stack([coef, P[:, -1] - coef @ lo])
        self.train_rmse_ = np.array(train_rmse)
        self.val_rmse_ = np.array(val_rmse)
        self.step_sizes_ = np.array(steps)
        self._incidence_ = inc
        return self

    # -- prediction ----------------------------------------------------------------------------

    def _check_fitted(self) -> None:
        if not hasattr(self, "consequents_"):
            raise NotFittedError("this ANFIS is not fitted yet: call fit (or from_dataset) first")

    def predict(self, X) -> np.ndarray:
        """Output for X (n, d) in original units; inputs are clamped to the training range first."""
        self._check_fitted()
        X = _check_array("X", X, 2, self.n_features_in_)
        XcT = np.ascontiguousarray(np.clip(X, self.input_range_[:, 0], self.input_range_[:, 1]).T)
        w = _firing(XcT, self.centres_, self.sigmas_, self.mf_input_, self._incidence_)[1]
        f = self.consequents_[:, :-1] @ XcT + self.consequents_[:, -1:]
        return (w * f).sum(axis=0)

    def score(self, X, y) -> float:
        """Coefficient of determination R^2 of predict(X) against y (1 for a perfect fit)."""
        y = _check_array("y", y, 1)
        y_hat = self.predict(X)
        if y_hat.shape != y.shape:
            raise ValueError(f"y has {y.size} values, X has {y_hat.size} rows")
        ss_res = float(((y - y_hat) ** 2).sum())
        ss_tot = float(((y - y.mean()) ** 2).sum())
        if ss_tot == 0:
            return 1.0 if ss_res == 0 else 0.0
        return 1.0 - ss_res / ss_tot

    # -- reading the rules ---------------------------------------------------------------------

    @property
    def n_rules_(self) -> int:
        self._check_fitted()
        return self.rule_mf_.shape[0]

    def membership_functions(self, initial: bool = False) -> list[tuple[np.ndarray, np.ndarray]]:
        """Per input, (centres, sigmas) of its MFs in input units (before training if ``initial``)."""
        self._check_fitted()
        c, s = (self.initial_centres_, self.initial_sigmas_) if initial else (self.centres_, self.sigmas_)
        return [(c[self.mf_input_ == i], s[self.mf_input_ == i]) for i in range(self.n_features_in_)]

    def rules_text(self, precision: int = 4) -> str:
        """The rules in words, one per line, numbers with ``precision`` significant digits."""
        self._check_fitted()
        offsets = np.searchsorted(self.mf_input_, np.arange(self.n_features_in_))
        out = self.output_name
        lines = [
            f"{self.n_rules_} first-order Takagi-Sugeno rules, membership mu(x) = exp(-(x - c)^2 / (2 sigma^2)); "
            f"{out} in {self.output_units}; inputs: "
            + ", ".join(f"{n} in {u}" for n, u in zip(self.input_names_, self.input_units_))
        ]

        def num(v: float) -> str:
            return f"{v:.{precision}g}"

        for r, mfs in enumerate(self.rule_mf_):
            conds = []
            for i, m in enumerate(mfs):
                u = _unit_suffix(self.input_units_[i])
                conds.append(
                    f"{self.input_names_[i]} is MF{m - offsets[i] + 1} "
                    f"(c = {num(self.centres_[m])}{u}, sigma = {num(self.sigmas_[m])}{u})"
                )
            coef = self.consequents_[r]
            expr = f"{num(coef[0])}*{self.input_names_[0]}"
            for i in range(1, self.n_features_in_):
                expr += f" {'-' if coef[i] < 0 else '+'} {num(abs(coef[i]))}*{self.input_names_[i]}"
            expr += f" {'-' if coef[-1] < 0 else '+'} {num(abs(coef[-1]))}"
            lines.append(f"Rule {r + 1}: IF " + " AND ".join(conds) + f" THEN {out} = {expr}")
        return "\n".join(lines)

    # -- persistence ---------------------------------------------------------------------------

    def to_dataset(self) -> xr.Dataset:
        """The fitted model as an xarray.Dataset (original units; one set of MF variables per input).

        Per input i: ``mf_centre_i``, ``mf_sigma_i`` (and ``*_initial_i``) along ``mf_i``,
        ``input_range_i`` (min, max) and the consequent coefficient ``consequent_i`` along ``rule``,
        each in its own units; ``consequent_constant``, ``rule_mf`` (1-based MF numbers), per-epoch
        ``train_rmse``, ``val_rmse`` (if validated) and ``step_size``. Hyper-parameters are the
        JSON text attribute ``hyperparameters``.
        """
        self._check_fitted()
        d, out_u = self.n_features_in_, self.output_units
        offsets = np.searchsorted(self.mf_input_, np.arange(d))
        epochs = np.arange(1, self.train_rmse_.size + 1)
        ds = xr.Dataset(
            coords={
                "input": ("input", np.arange(1, d + 1), {"long_name": "input number", "units": "1"}),
                "input_name": (
                    "input",
                    np.array(self.input_names_, dtype=object),
                    {"long_name": "input variable name", "units": "1"},
                ),
                "input_units": (
                    "input",
                    np.array(self.input_units_, dtype=object),
                    {"long_name": "units of each input", "units": "1"},
                ),
                "rule": ("rule", np.arange(1, self.n_rules_ + 1), {"long_name": "rule number", "units": "1"}),
                "epoch": ("epoch", epochs, {"long_name": "training epoch number", "units": "1"}),
            }
        )
        ds["rule_mf"] = (
            ("rule", "input"),
            (self.rule_mf_ - offsets + 1).astype(np.int32),
            {"long_name": "membership function number (1-based, per input) used by each rule", "units": "1"},
        )
        for i, (name, unit) in enumerate(zip(self.input_names_, self.input_units_)):
            sel = self.mf_input_ == i
            for var, values, what in [
                ("mf_centre", self.centres_, "centre c"),
                ("mf_sigma", self.sigmas_, "width sigma"),
                ("mf_centre_initial", self.initial_centres_, "initial centre c"),
                ("mf_sigma_initial", self.initial_sigmas_, "initial width sigma"),
            ]:
                ds[f"{var}_{i}"] = (
                    f"mf_{i}",
                    values[sel],
                    {
                        "long_name": f"{what} of the Gaussian membership functions of input {name}",
                        "units": unit,
                    },
                )
            ds[f"input_range_{i}"] = (
                "bound",
                self.input_range_[i],
                {
                    "long_name": f"training range (min, max) of input {name}; predict clamps to it",
                    "units": unit,
                },
            )
            ds[f"consequent_{i}"] = (
                "rule",
                self.consequents_[:, i],
                {
                    "long_name": f"consequent coefficient of input {name} in each rule",
                    "units": _ratio_units(out_u, unit),
                },
            )
        ds["consequent_constant"] = (
            "rule",
            self.consequents_[:, -1],
            {"long_name": "consequent constant term of each rule", "units": out_u},
        )
        ds["train_rmse"] = (
            "epoch",
            self.train_rmse_,
            {"long_name": f"training RMSE of {self.output_name}", "units": out_u},
        )
        if self.val_rmse_.size:
            ds["val_rmse"] = (
                "epoch",
                self.val_rmse_,
                {"long_name": f"validation RMSE of {self.output_name}", "units": out_u},
            )
        ds["step_size"] = (
            "epoch",
            self.step_sizes_,
            {"long_name": "premise step size as a fraction of the input ranges", "units": "1"},
        )
        ds.attrs = {
            "title": "ANFIS model: first-order Takagi-Sugeno rules, Gaussian membership functions",
            "model": "y = sum_r w_r f_r / sum_r w_r, w_r = prod_i exp(-(x_i - c)^2 / (2 sigma^2)), "
            "f_r = sum_i consequent_i x_i + consequent_constant; inputs clamped to input_range_i",
            "output_name": self.output_name,
            "output_units": out_u,
            "best_epoch": int(self.best_epoch_),
            "hyperparameters": json.dumps(self.get_params(), default=json_default),
        }
        return ds

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> ANFIS:
        """Rebuild a fitted model from ``to_dataset`` output; predictions are bit-identical."""
        model = cls(**json.loads(ds.attrs["hyperparameters"]))
        names = [str(v) for v in ds["input_name"].values]
        d = len(names)
        sizes = [ds.sizes[f"mf_{i}"] for i in range(d)]
        offsets = np.cumsum([0] + sizes[:-1])

        def joined(var: str) -> np.ndarray:
            return np.concatenate([np.asarray(ds[f"{var}_{i}"].values, float) for i in range(d)])

        model.n_features_in_ = d
        model.input_names_ = names
        model.input_units_ = [str(v) for v in ds["input_units"].values]
        model.input_range_ = np.stack([np.asarray(ds[f"input_range_{i}"].values, float) for i in range(d)])
        model.mf_input_ = np.repeat(np.arange(d), sizes)
        model.rule_mf_ = np.asarray(ds["rule_mf"].values, dtype=np.int64) - 1 + offsets
        model.centres_, model.sigmas_ = joined("mf_centre"), joined("mf_sigma")
        model.initial_centres_, model.initial_sigmas_ = joined("mf_centre_initial"), joined("mf_sigma_initial")
        coefs = [np.asarray(ds[f"consequent_{i}"].values, float) for i in range(d)]
        model.consequents_ = np.column_stack(coefs + [np.asarray(ds["consequent_constant"].values, float)])
        model.train_rmse_ = np.asarray(ds["train_rmse"].values, float)
        model.val_rmse_ = np.asarray(ds["val_rmse"].values, float) if "val_rmse" in ds else np.array([])
        model.step_sizes_ = np.asarray(ds["step_size"].values, float)
        model.best_epoch_ = int(ds.attrs["best_epoch"])
        model._incidence_ = _incidence(model.rule_mf_, model.centres_.size)
        return model


def _same(a, b) -> bool:
    try:
        return bool(a == b) and type(a) is type(b)
    except (TypeError, ValueError):
        return False
