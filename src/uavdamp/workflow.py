"""Snakemake glue for the rules and their scripts: config views, logging, the command for provenance.

Nothing here is physics: the rules call `config_view`/`canonical` to hand each job exactly the config it uses,
and the scripts call `start_log`, `log_info` and `snakemake_command`.
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import subprocess
import sys
from pathlib import Path

import jsonschema
import yaml

from uavdamp import plugins
from uavdamp.integrity import RUN_ATTR, now
from uavdamp.io import PROVENANCE_ENV, package_versions
from uavdamp.settings import SAFE_LOADER, ConfigError

DEBUG_ENV = "UAVDAMP_DEBUG"  # set to 1: a config error shows its traceback too


@contextlib.contextmanager
def config_errors_alone(stream=None):
    """In the Snakefile, around the config checks: a `ConfigError` printed as its message alone (the key and the
    rule it breaks) and the run stopped with exit status 1; with UAVDAMP_DEBUG=1 it propagates with its traceback."""
    try:
        yield
    except ConfigError as error:
        if os.environ.get(DEBUG_ENV, "") not in ("", "0"):
            raise
        print(f"config error: {error}\n(traceback: {DEBUG_ENV}=1)", file=stream or sys.stderr)
        raise SystemExit(1) from None


def snakemake_command(smk) -> str:
    """A readable command for provenance: the rule and its wildcards as Snakemake ran them."""
    wildcards = ", ".join(f"{k}={v}" for k, v in dict(smk.wildcards).items())
    return f"snakemake rule {smk.rule}" + (f" [{wildcards}]" if wildcards else "")


def start_log(path: str | os.PathLike) -> None:
    """Send this process's log records, warnings, prints and tracebacks to `path` (a Snakemake `log:`)."""
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    sys.stderr = sys.stdout = open(path, "a", buffering=1)  # tracebacks and prints land in the log too
    logging.basicConfig(
        stream=sys.stderr, level=logging.INFO, format="%(asctime)s %(levelname)s %(message)s", force=True
    )
    logging.captureWarnings(True)
    logging.getLogger("uavdamp").info("versions: %s", json.dumps(package_versions(), sort_keys=True))


def check_schema(config: dict, schema_path: str | os.PathLike) -> None:
    """ConfigError naming the dotted key, its value and the rule of the config schema (units, ranges) it breaks.

    jsonschema's most relevant error only, in one line (Snakemake's `validate` prints the whole schema)."""

    schema = yaml.load(Path(schema_path).read_text(), Loader=SAFE_LOADER)  # noqa: S506 (libyaml's safe loader)
    error = jsonschema.exceptions.best_match(jsonschema.Draft202012Validator(schema).iter_errors(config))
    if error is not None:
        key = ".".join(str(p) for p in error.absolute_path) or "config"
        raise ConfigError(f"{key}: {error.message} (config schema: {Path(schema_path).name})")


def load_plugins(smk) -> list[dict]:
    """Import the job's plug-in law files (its input `plugins`, `uavdamp.plugins`) and log their SHA-256."""

    records = plugins.load(list(getattr(smk.input, "plugins", [])))
    for record in records:
        log_info(f"plug-in {record['path']} sha256 {record['sha256']}")
    return records


def log_info(message: str) -> None:
    logging.getLogger("uavdamp").info(message)


def config_view(section: dict, *, drop=(), keep=None) -> dict:
    """The keys of a config section a rule uses (all but `drop`, or only `keep`), canonical."""
    return canonical({k: v for k, v in section.items() if k not in drop and (keep is None or k in keep)})


def canonical(config):
    """A config section with its mappings' keys sorted, at every depth (for Snakemake `params:`).

    Snakemake compares params by their text, so the same values in another key order would look
    like an edit and rerun the rule; sorted keys make a reordered YAML file change nothing.
    """
    return json.loads(json.dumps(config, sort_keys=True))


def _git(basedir: str, *args: str) -> str | None:
    try:
        out = subprocess.run(["git", "-C", basedir, *args], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return None
    return out.stdout.strip() if out.returncode == 0 else None


def export_provenance(configfiles, basedir: str, argv=None) -> dict:
    """Put the run's provenance where every job's `uavdamp.io.write_netcdf` finds it (an environment variable).

    git commit of `basedir` and whether its tree had uncommitted changes ("unknown" outside a git work tree),
    the full Snakemake command line, the config files in the order Snakemake merged them, and the run's start
    (`run_started`, UTC: `uavdamp.integrity` tells an earlier run's output from a later one's by it).
    """

    commit = _git(basedir, "rev-parse", "HEAD")
    status = _git(basedir, "status", "--porcelain", "--untracked-files=no") if commit else None
    provenance = {
        "git_commit": commit or "unknown",
        "git_tree_dirty": "unknown" if status is None else ("yes" if status else "no"),
        "command_line": " ".join(sys.argv if argv is None else argv),
        "config_files": json.dumps([str(f) for f in configfiles]),
        RUN_ATTR: now(),
    }
    os.environ[PROVENANCE_ENV] = json.dumps(provenance)
    return provenance
