"""Registries by name (strategies, metrics): one decorator that refuses a second registration."""

from __future__ import annotations


def add(table: dict, kind: str, name: str):
    """Decorator registering a function in `table` under `name`; ValueError if the name is taken."""

    def decorate(fn):
        if name in table:
            raise ValueError(f"{kind} {name!r} is registered twice")
        table[name] = fn
        return fn

    return decorate
