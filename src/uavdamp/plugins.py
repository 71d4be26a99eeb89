"""Plug-in laws: a researcher's strategies (and benchmark controllers) in their own Python file.

The config's top-level ``plugins`` lists files (paths relative to the working directory, as Snakemake runs); each is
imported by `load` with importlib from its path (no package, no sys.path edit), and registers what it defines with
`uavdamp.strategies.register` when it is imported (and a parameter the benchmark should tune with
`uavdamp.tuning.register_tuned`). One registry serves the study (``study.strategies``) and the
benchmark (``benchmark.controllers``); `uavdamp.checks` checks both lists against it after loading the plug-ins.

Provenance: `load` records each file's path and SHA-256 (`provenance`), and `uavdamp.io.write_netcdf` writes them into
every output of a job that loaded plug-ins (attribute ``plugins``: JSON list of {path, sha256}). The rules that import
them (study, benchmark tuning, runs and gather) take the files as inputs, so editing one reruns what it affects.
"""

from __future__ import annotations

import hashlib
import importlib.util
import json
import sys
from pathlib import Path

_LOADED: dict[str, dict] = {}  # resolved path -> {"path": as given, "sha256": ..., "module": name}


def sha256(path: str | Path) -> str:
    """SHA-256 (hex) of a file's bytes."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def load(paths) -> list[dict]:
    """Import every plug-in file of `paths` once per process (a second call with the same file does nothing: the
    registry refuses a name twice); returns their records [{path, sha256, module}]. FileNotFoundError names a
    missing file; an error raised while importing it propagates with the file named in its traceback."""
    records = []
    for given in paths:
        path = Path(given)
        if not path.is_file():
            raise FileNotFoundError(f"plugins: no file {str(given)!r} (paths are relative to the working directory)")
        key = str(path.resolve())
        if key not in _LOADED:
            digest = sha256(path)
            name = f"uavdamp_plugin_{path.stem}_{digest[:12]}"
            spec = importlib.util.spec_from_file_location(name, path)
            module = importlib.util.module_from_spec(spec)
            sys.modules[name] = module  # dataclasses and pickling look modules up by name
            try:
                spec.loader.exec_module(module)
            except BaseException:
                sys.modules.pop(name, None)
                raise
            _LOADED[key] = {"path": str(given), "sha256": digest, "module": name}
        records.append(_LOADED[key])
    return records


def provenance() -> dict[str, str]:
    """{"plugins": JSON [{path, sha256}]} of the files loaded in this process, {} if none."""
    if not _LOADED:
        return {}
    return {"plugins": json.dumps([{"path": r["path"], "sha256": r["sha256"]} for r in _LOADED.values()])}
