"""The ANFIS's argument checks (``ANFIS.fit`` calls ``check_params``) and the output scaling of ``fit``."""

from __future__ import annotations

import numbers
from collections.abc import Sequence

import numpy as np

INITS = ("grid", "fcm", "subtractive")
MAX_RULES = 4096


def _is_int(value) -> bool:
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def _is_real(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool) and np.isfinite(value)


def _output_scaling(y: np.ndarray, name: str) -> tuple[float, float]:
    """(offset, scale): the output's mid-range and half-range (1 for a constant output)."""
    lo, hi = float(y.min()), float(y.max())
    half = 0.5 * hi - 0.5 * lo  # halves first: the difference of two large finite values may overflow
    if not np.isfinite(2.0 * half):
        raise ValueError(
            f"{name} spans [{lo:g}, {hi:g}]: its range is not a finite float64, so the model cannot be fitted; "
            "rescale the target"
        )
    return 0.5 * lo + 0.5 * hi, (half if half > 0 else 1.0)


def check_structure(est, n_inputs: int, n_samples: int) -> list[int]:
    """Validate init, n_mfs, n_rules and radius; return MFs per input (grid) or []."""
    if not isinstance(est.init, str) or est.init not in INITS:
        raise ValueError(f"init must be one of {', '.join(INITS)}, got {est.init!r}")
    if est.init == "grid":
        n_mfs = [est.n_mfs] * n_inputs if _is_int(est.n_mfs) else est.n_mfs
        if (
            isinstance(n_mfs, (str, bytes))
            or not isinstance(n_mfs, (Sequence, np.ndarray))
            or len(n_mfs) != n_inputs
            or not all(_is_int(m) and m >= 1 for m in n_mfs)
        ):
            raise ValueError(f"n_mfs must be a positive int or {n_inputs} positive ints, got {est.n_mfs!r}")
        n_mfs = [int(m) for m in n_mfs]
        if np.prod(n_mfs, dtype=float) > MAX_RULES:
            raise ValueError(
                f"n_mfs={est.n_mfs!r} gives more than {MAX_RULES} grid rules; use init='subtractive' or 'fcm'"
            )
        return n_mfs
    if est.init == "fcm" and not (_is_int(est.n_rules) and 1 <= est.n_rules <= n_samples):
        raise ValueError(
            f"n_rules must be an int between 1 and the number of samples (n_samples={n_samples}) "
            f"for init='fcm', got {est.n_rules!r}"
        )
    if est.init == "subtractive" and not (_is_real(est.radius) and 0 < est.radius <= 1):
        raise ValueError(f"radius must be a number in (0, 1] for init='subtractive', got {est.radius!r}")
    return []


def check_params(est, n_inputs: int, n_samples: int) -> list[int]:
    """Validate the constructor arguments for data with n_inputs columns; return MFs per input."""
    n_mfs = check_structure(est, n_inputs, n_samples)
    if not (_is_int(est.epochs) and est.epochs >= 1):
        raise ValueError(f"epochs must be an int >= 1, got {est.epochs!r}")
    checks = [
        ("error_goal", lambda v: v >= 0, ">= 0"),
        ("step_size", lambda v: v > 0, "> 0"),
        ("step_increase", lambda v: v > 1, "> 1"),
        ("step_decrease", lambda v: 0 < v < 1, "in (0, 1)"),
        ("min_sigma_frac", lambda v: 0 < v <= 1, "in (0, 1]"),
        ("ridge", lambda v: v >= 0, ">= 0"),
        ("max_memory_gb", lambda v: v > 0, "> 0"),
        ("validation_fraction", lambda v: 0 <= v < 1, "in [0, 1)"),
    ]
    for name, ok, text in checks:
        value = getattr(est, name)
        if not (_is_real(value) and ok(value)):
            raise ValueError(f"{name} must be a finite number {text}, got {value!r}")
    if est.random_state is not None and not (_is_int(est.random_state) and est.random_state >= 0):
        raise ValueError(f"random_state must be None or an int >= 0, got {est.random_state!r}")
    for name in ("input_names", "input_units"):
        value = getattr(est, name)
        if value is not None and (
            isinstance(value, str)
            or not isinstance(value, Sequence)
            or len(value) != n_inputs
            or not all(isinstance(v, str) for v in value)
        ):
            raise ValueError(f"{name} must be None or {n_inputs} strings (one per input), got {value!r}")
    if est.input_names is not None and (len(set(est.input_names)) != n_inputs or "" in est.input_names):
        raise ValueError(f"input_names must be distinct non-empty strings, got {est.input_names!r}")
    if not (isinstance(est.output_name, str) and est.output_name):
        raise ValueError(f"output_name must be a non-empty string, got {est.output_name!r}")
    if not isinstance(est.output_units, str):
        raise ValueError(f"output_units must be a string, got {est.output_units!r}")
    return n_mfs
