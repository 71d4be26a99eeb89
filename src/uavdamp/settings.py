"""Typed config sections: the machinery every section class uses (`uavdamp.config.load` assembles the whole config).

A section is a frozen dataclass whose fields are declared with `setting(...)`; the config key defaults to the
field's name, or is given where the key carries a unit the Python name does not need (``time_step`` <-
``time_step_s``). `parse(cls, mapping, where)` converts every value to the field's declared type (float, int,
bool, str, a tuple of those or of sections, a nested section, a mapping of sections, or ``X | None`` for an
optional part) and raises `ConfigError` naming ``where.key`` for an unknown, renamed, missing or ill-typed key
(an unknown key gets the nearest valid one, a renamed key its new name). Range checks live in each class's
``validate()`` (called by `parse`; ``validate(where)`` for a part used under several keys), checks across sections
in `uavdamp.config.checks`.
"""

from __future__ import annotations

import dataclasses
import difflib
import fnmatch
import inspect
import math
import re
import types
import typing
from collections.abc import Mapping
from typing import Any, TypeVar

import yaml

T = TypeVar("T")
# the safe YAML loader config files and the schema are read with: libyaml's where PyYAML has it (the same documents
# and error marks, about ten times faster; every Snakemake start reads them)
SAFE_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
_MISSING = dataclasses.MISSING

# old dotted key (fnmatch pattern: * for a name such as a case's) -> its new name (keys renamed to carry their unit);
# a file using an old key is refused naming the new one
RENAMED: dict[str, str] = {}


NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]*")  # a name that becomes part of a file name (cases, mounts, ...)


class ConfigError(ValueError):
    """A config value breaks a rule: the message starts with the dotted key."""


def setting(key: str | None = None, *, default: Any = _MISSING, length: int | None = None):
    """A dataclass field read from config key `key` (default: the field's name); `length` for fixed-size tuples."""
    metadata = {"key": key, "length": length}
    if default is _MISSING:
        return dataclasses.field(metadata=metadata)
    return dataclasses.field(default=default, metadata=metadata)


def attached(default=None):
    """A dataclass field that is not a config key: a part another section supplies (e.g. the camera of a study)."""
    return dataclasses.field(default=default, metadata={"config": False})


def _in_config(f) -> bool:
    return f.init and f.metadata.get("config", True)


def key_of(cls, name: str) -> str:
    """The config key of field `name` of section class `cls`."""
    for f in dataclasses.fields(cls):
        if f.name == name:
            return f.metadata.get("key") or f.name
    raise KeyError(name)


def keys(cls) -> list[str]:
    """The config keys of section class `cls`, in field order."""
    return [f.metadata.get("key") or f.name for f in dataclasses.fields(cls) if _in_config(f)]


def require(ok: bool, where: str, rule: str) -> None:
    """ConfigError ``where: rule`` unless `ok`."""
    if not ok:
        raise ConfigError(f"{where}: {rule}")


def _optional(kind):
    """(the type inside ``X | None``, True) or (kind, False)."""
    if typing.get_origin(kind) in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(kind) if a is not type(None)]
        return args[0], len(args) < len(typing.get_args(kind))
    return kind, False


def _sequence(value, where: str, length: int | None):
    if isinstance(value, (str, bytes, Mapping)) or not hasattr(value, "__len__"):
        raise ConfigError(f"{where}: expected a list, got {value!r}")
    if length is not None and len(value) != length:
        raise ConfigError(f"{where}: needs {length} values, got {value!r}")
    return value


def _scalar(value, kind, where: str):
    if kind is bool:
        require(isinstance(value, bool), where, f"expected true or false, got {value!r}")
        return value
    if kind is int:
        ok = isinstance(value, int) and not isinstance(value, bool)
        require(ok, where, f"expected an integer, got {value!r}")
        return value
    if kind is float:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
        require(ok, where, f"expected a finite number, got {value!r}{_yaml_number_hint(value)}")
        return float(value)
    if kind is str:
        require(isinstance(value, str), where, f"expected a string, got {value!r}")
        return value
    raise TypeError(f"{where}: unsupported field type {kind!r}")


_YAML11_STRING_NUMBER = re.compile(r"([-+]?(?:\d+\.?\d*|\.\d+))[eE]([-+]?)(\d+)")


def _yaml_number_hint(value) -> str:
    """Why a number written like 1.0e9 or 1e-3 arrived as a string: YAML 1.1 (PyYAML, Snakemake's loader) reads a
    float in exponent notation only with a dot in the mantissa and a signed exponent; the fix in both notations."""
    found = _YAML11_STRING_NUMBER.fullmatch(value.strip()) if isinstance(value, str) else None
    if found is None:
        return ""
    mantissa, sign, exponent = found.groups()
    dotted = mantissa if "." in mantissa else f"{mantissa}.0"
    return (
        f": YAML 1.1 reads {value} as a string (a float needs a dot and a signed exponent): write "
        f"{dotted}e{sign or '+'}{exponent} or {float(value)!r}"
    )


def convert(value, kind, where: str, length: int | None = None):
    """`value` as type `kind` (see the module docstring); ConfigError naming `where`."""
    kind, optional = _optional(kind)
    if value is None and optional:
        return None
    if dataclasses.is_dataclass(kind):
        return parse(kind, value, where)
    origin = typing.get_origin(kind)
    if origin is tuple:
        item = typing.get_args(kind)[0]
        items = _sequence(value, where, length)
        return tuple(convert(v, item, f"{where}[{i}]") for i, v in enumerate(items))
    if origin is dict:
        require(isinstance(value, Mapping), where, f"expected a mapping, got {value!r}")
        item = typing.get_args(kind)[1]
        return {str(k): convert(v, item, join(where, k)) for k, v in value.items()}
    return _scalar(value, kind, where)


def join(where: str, key) -> str:
    """The dotted key `key` under `where` ("" at the top)."""
    return f"{where}.{key}" if where else str(key)


def unknown_key(where: str, key: str, valid: list[str]) -> ConfigError:
    """The error for key `key` under `where`: its new name if it was renamed, else the nearest valid key."""
    dotted = join(where, key)
    for old, new in RENAMED.items():
        if fnmatch.fnmatchcase(dotted, old):
            return ConfigError(f"{dotted}: renamed to {join(where, new)} (the key now carries its unit)")
    near = difflib.get_close_matches(str(key), valid, n=1)
    hint = f"; did you mean {join(where, near[0])}?" if near else f" (valid keys: {', '.join(valid)})"
    rule = f"{where or 'the config'} takes only its own keys (workflow/schemas/config.schema.yaml, config/README.md)"
    return ConfigError(f"{dotted}: unknown key{hint} {rule}")


def parse(cls: type[T], mapping, where: str) -> T:
    """An instance of section class `cls` from a config mapping; ConfigError names ``where.key`` on any problem."""
    require(isinstance(mapping, Mapping), where, f"expected a mapping, got {type(mapping).__name__}")
    hints = typing.get_type_hints(cls)
    fields = {key_of(cls, f.name): f for f in dataclasses.fields(cls) if _in_config(f)}
    for key in mapping:
        if key not in fields:
            raise unknown_key(where, key, list(fields))
    values = {}
    for key, f in fields.items():
        if key not in mapping:
            if f.default is _MISSING and f.default_factory is _MISSING:
                raise ConfigError(f"{join(where, key)}: missing key")
            continue
        values[f.name] = convert(mapping[key], hints[f.name], join(where, key), f.metadata.get("length"))
    obj = cls(**values)
    _validate(obj, where)
    return obj


def _validate(obj, where: str) -> None:
    if hasattr(obj, "validate"):  # a reusable part (`validate(where)`) is told where it sits
        takes_where = len(inspect.signature(obj.validate).parameters) == 1
        obj.validate(where) if takes_where else obj.validate()


def revalidate(obj, where: str) -> None:
    """Every section inside `obj` (a section built or changed in code, e.g. by `dataclasses.replace`) checked again,
    innermost first, as `parse` checks them; ConfigError names the key."""
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if dataclasses.is_dataclass(value) and not isinstance(value, type):
            revalidate(value, join(where, key_of(type(obj), f.name)))
    _validate(obj, where)


def view(mapping: Mapping, cls) -> dict:
    """The keys of `mapping` that section class `cls` reads (a rule's `params:` view of a section)."""
    wanted = set(keys(cls))
    return {k: v for k, v in mapping.items() if k in wanted}
