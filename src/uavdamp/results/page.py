"""The results page's building blocks: its tables, figures and page, and how a number is written on it."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

DIGITS = 4  # significant digits of every value shown
MISSING = "-"


@dataclass(frozen=True)
class Table:
    """One table of the page: flat, every column labelled, cells already formatted as text."""

    title: str
    frame: pd.DataFrame
    note: str = ""
    labels: int = 1  # leading columns that label the rows (left-aligned)


@dataclass(frozen=True)
class Figure:
    """A figure of the run: its file (relative to the page) and a one-sentence caption."""

    path: str
    title: str
    caption: str


@dataclass
class Page:
    """The results page: provenance, findings, descriptions, figures and tables."""

    provenance: dict
    findings: list[str] = field(default_factory=list)
    descriptions: list[tuple[str, dict[str, str]]] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)
    tables: list[Table] = field(default_factory=list)


def fmt(value, digits: int = DIGITS) -> str:
    """`value` to `digits` significant digits, positional (no exponent between 1e-4 and 1e7); NaN, None: '-'."""
    if value is None or isinstance(value, str):
        return MISSING if value is None else value
    value = float(value)
    if not np.isfinite(value):
        return MISSING
    if value == 0:
        return "0"
    if 1e-4 <= abs(value) < 1e7:
        return np.format_float_positional(value, precision=digits, unique=False, fractional=False, trim="-")
    return f"{value:.{digits - 1}e}"


def signed(value: float, digits: int = 2) -> str:
    """A difference with its sign ('+0.012', '-3.1'), `digits` significant digits."""
    return MISSING if not np.isfinite(value) else ("+" if value >= 0 else "-") + fmt(abs(value), digits)
