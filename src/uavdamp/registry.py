"""Registries by name (strategies, metrics): one decorator that refuses a second registration or an unsafe name."""

from __future__ import annotations

import re

# a registered name becomes part of output names (a plug-in's strategy as the config names it: study.strategies)
SAFE_NAME = re.compile(r"[A-Za-z0-9_]+")


def add(table: dict, kind: str, name: str):
    """Decorator registering a function in `table` under `name`; ValueError if the name is taken or is not a safe
    name (`SAFE_NAME`: letters, digits and _, as the config schema's strategy names)."""
    if not (isinstance(name, str) and SAFE_NAME.fullmatch(name)):
        raise ValueError(f"{kind} name {name!r} must match {SAFE_NAME.pattern} (names become parts of output names)")

    def decorate(fn):
        if name in table:
            raise ValueError(f"{kind} {name!r} is registered twice")
        table[name] = fn
        return fn

    return decorate
