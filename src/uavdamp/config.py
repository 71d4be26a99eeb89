"""Typed config sections: a frozen dataclass per config section, loaded with unknown and missing keys refused.

A section class declares its fields with `setting(...)`; the config key defaults to the field's name, or is given
explicitly where the key carries a unit the Python name does not need (``time_step`` <- ``time_step_s``).
`load(cls, mapping, where)` converts every value to the field's declared type (float, int, bool, str, a tuple of
floats, a nested section class, or a mapping of section classes) and raises ValueError naming ``where.key`` for
an unknown, missing or ill-typed key. Range checks live in each class's ``validate()`` (called by `load`), and
checks that span sections in `uavdamp.checks`.
"""

from __future__ import annotations

import dataclasses
import math
import typing
from collections.abc import Mapping
from typing import Any, TypeVar

T = TypeVar("T")
_MISSING = dataclasses.MISSING


def setting(key: str | None = None, *, default: Any = _MISSING, length: int | None = None):
    """A dataclass field read from config key `key` (default: the field's name); `length` for fixed-size tuples."""
    metadata = {"key": key, "length": length}
    if default is _MISSING:
        return dataclasses.field(metadata=metadata)
    return dataclasses.field(default=default, metadata=metadata)


def key_of(cls, name: str) -> str:
    """The config key of field `name` of section class `cls`."""
    for f in dataclasses.fields(cls):
        if f.name == name:
            return f.metadata.get("key") or f.name
    raise KeyError(name)


def _convert(value, kind, where: str, length: int | None):
    origin = typing.get_origin(kind)
    if dataclasses.is_dataclass(kind):  # a nested section: by its own from_config (its keys' names) if it has one
        return kind.from_config(value) if hasattr(kind, "from_config") else load(kind, value, where)
    if origin is tuple:
        if isinstance(value, (str, bytes, Mapping)) or not hasattr(value, "__len__"):
            raise ValueError(f"{where}: expected a list, got {value!r}")
        item = typing.get_args(kind)[0]
        if length is not None and len(value) != length:
            raise ValueError(f"{where}: needs {length} values, got {value!r}")
        return tuple(_convert(v, item, f"{where}[{i}]", None) for i, v in enumerate(value))
    if origin is dict:
        if not isinstance(value, Mapping):
            raise ValueError(f"{where}: expected a mapping, got {value!r}")
        item = typing.get_args(kind)[1]
        return {str(k): _convert(v, item, f"{where}.{k}", None) for k, v in value.items()}
    if kind is bool:
        if not isinstance(value, bool):
            raise ValueError(f"{where}: expected true or false, got {value!r}")
        return value
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ValueError(f"{where}: expected an integer, got {value!r}")
        return value
    if kind is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(f"{where}: expected a finite number, got {value!r}")
        return float(value)
    if kind is str:
        if not isinstance(value, str):
            raise ValueError(f"{where}: expected a string, got {value!r}")
        return value
    raise TypeError(f"{where}: unsupported field type {kind!r}")


def load(cls: type[T], mapping, where: str) -> T:
    """An instance of section class `cls` from a config mapping; ValueError names ``where.key`` on any problem."""
    if not isinstance(mapping, Mapping):
        raise ValueError(f"{where}: expected a mapping, got {type(mapping).__name__}")
    hints = typing.get_type_hints(cls)
    fields = {key_of(cls, f.name): f for f in dataclasses.fields(cls) if f.init}
    unknown = sorted(set(mapping) - set(fields))
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {unknown}")
    values = {}
    for key, f in fields.items():
        if key not in mapping:
            if f.default is _MISSING and f.default_factory is _MISSING:
                raise ValueError(f"{where}: missing key {key!r}")
            continue
        kind = hints[f.name]
        if typing.get_origin(kind) in (typing.Union, getattr(__import__("types"), "UnionType", None)):
            kind = next(a for a in typing.get_args(kind) if a is not type(None))
        values[f.name] = _convert(mapping[key], kind, f"{where}.{key}", f.metadata.get("length"))
    obj = cls(**values)
    if hasattr(obj, "validate"):
        obj.validate()
    return obj


def require(ok: bool, where: str, rule: str) -> None:
    """ValueError ``where: rule`` unless `ok`."""
    if not ok:
        raise ValueError(f"{where}: {rule}")
