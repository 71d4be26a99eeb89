"""The config files as Snakemake read them, read again strictly: a duplicated key or a YAML error is refused naming
the file and the line, before any job.

Snakemake loads its config files itself (`configfile:` and --configfile) with a YAML reader that keeps the last of
two equal keys without a word; the Snakefile passes ``workflow.configfiles`` to `check` before the config is
validated. Files using Snakemake's YTE templating (``__use_yte__: true``) are code, not data: their keys are
checked as written in the template.
"""

from __future__ import annotations

from pathlib import Path

import yaml

from uavdamp.settings import SAFE_LOADER, ConfigError


class _StrictLoader(SAFE_LOADER):
    """A safe YAML loader that refuses a key given twice in one mapping."""


def _mapping(loader: _StrictLoader, node: yaml.MappingNode, deep: bool = False) -> dict:
    loader.flatten_mapping(node)
    seen: dict = {}
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=deep)
        if key in seen:
            raise yaml.constructor.ConstructorError(
                None, None, f"duplicate key {key!r} (first given on line {seen[key] + 1})", key_node.start_mark
            )
        seen[key] = key_node.start_mark.line
    return loader.construct_mapping(node, deep=deep)


_StrictLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _mapping)


def read(path: str | Path):
    """The YAML file `path` parsed strictly; ConfigError ``path, line N: problem`` on a duplicate key or bad YAML."""
    text = Path(path).read_text(encoding="utf-8")
    try:
        return yaml.load(text, Loader=_StrictLoader)  # noqa: S506 (a SafeLoader subclass)
    except yaml.MarkedYAMLError as error:
        mark = error.problem_mark
        where = f"{path}, line {mark.line + 1}, column {mark.column + 1}" if mark else str(path)
        raise ConfigError(f"{where}: {error.problem or error}") from None
    except yaml.YAMLError as error:
        raise ConfigError(f"{path}: {error}") from None


def check(paths) -> None:
    """Every config file of `paths` (Snakemake's ``workflow.configfiles``) read strictly (`read`)."""
    for path in paths:
        read(path)
