"""Plug-in laws: a researcher's strategies (and benchmark controllers) in their own Python file.

The config's top-level ``plugins`` lists files (paths relative to the run directory, where Snakemake runs); each is
imported by `load` with importlib from its path (no package, no sys.path edit), and registers what it defines with
`uavdamp.study.strategies.register` when it is imported (and a parameter the benchmark should tune with
`uavdamp.benchmark.tuning.register_tuned`). One registry serves the study (``study.strategies``) and the
benchmark (``benchmark.controllers``); `uavdamp.config.checks` checks both lists against it after loading the plug-ins.

Data files: a plug-in that reads files of its own declares them at module level, ``DATA_FILES = ["my_table.json"]``
(paths relative to the plug-in file). `load` checks they exist and records their SHA-256 with the plug-in's.

Provenance: `load` records each file's path and SHA-256 (`provenance`), and `uavdamp.io.write_netcdf` writes them into
every output of a job that loaded plug-ins (attribute ``plugins``: JSON list of {path, sha256}, and ``data``: the
declared data files' {path, sha256} when there are any). The rules that import them (study, benchmark tuning, runs and
gather) take the plug-in files and their data files (`data_inputs`) as inputs, so editing either reruns what it
affects. Every Snakemake call (a dry run, a report, any target) imports the plug-ins while it reads the config: an
exception or a SystemExit raised at import is a PluginError naming the file.
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
            raise FileNotFoundError(
                f"plugins: no file {str(given)!r} (paths are relative to the run directory, where Snakemake "
                f"runs: {Path.cwd()})"
            )
        key = str(path.resolve())
        if key not in _LOADED:
            digest = sha256(path)
            name = f"uavdamp_plugin_{path.stem}_{digest[:12]}"
            spec = importlib.util.spec_from_file_location(name, path)
            module = importlib.util.module_from_spec(spec)
            sys.modules[name] = module  # dataclasses and pickling look modules up by name
            try:
                spec.loader.exec_module(module)
            except (Exception, SystemExit) as error:  # SystemExit: sys.exit() at import would end Snakemake quietly
                sys.modules.pop(name, None)
                raise PluginError(
                    f"plugins: importing {str(given)!r} raised {type(error).__name__}: {error} (a plug-in file is "
                    "imported by every Snakemake call, before any job: it must only define and register)"
                ) from error
            try:
                data = [{"path": str(p), "sha256": sha256(p)} for p in data_files(module, given)]
            except PluginError:
                sys.modules.pop(name, None)
                raise
            _LOADED[key] = {"path": str(given), "sha256": digest, "module": name, "data": data}
        records.append(_LOADED[key])
    return records


class PluginError(RuntimeError):
    """A plug-in file that could not be imported or declares a data file that is not there (the file named)."""


def data_files(module, given) -> list[Path]:
    """The files a plug-in module declares it reads (``DATA_FILES``, relative to the plug-in file), each checked to
    exist; paths as the plug-in's own path is given (relative to the run directory when it is)."""
    declared = getattr(module, "DATA_FILES", [])
    if isinstance(declared, (str, bytes)) or not all(isinstance(d, str) for d in declared):
        raise PluginError(f"plugins: {str(given)!r}: DATA_FILES must be a list of file names, got {declared!r}")
    found = [Path(given).parent / d for d in declared]
    for file in found:
        if not file.is_file():
            raise PluginError(f"plugins: {str(given)!r} declares DATA_FILES entry {str(file)!r}: no such file")
    return found


def data_inputs(paths) -> list[str]:
    """The data files the plug-ins of `paths` declare (imports them through `load`): inputs, with the plug-in files,
    of every rule that imports plug-ins."""
    return [d["path"] for record in load(paths) for d in record["data"]]


def provenance() -> dict[str, str]:
    """{"plugins": JSON [{path, sha256, data?}]} of the files loaded in this process, {} if none."""
    if not _LOADED:
        return {}
    records = [
        {"path": r["path"], "sha256": r["sha256"], **({"data": r["data"]} if r["data"] else {})}
        for r in _LOADED.values()
    ]
    return {"plugins": json.dumps(records)}
