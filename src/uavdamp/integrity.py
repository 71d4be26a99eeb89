"""Which run an output belongs to: a config digest carried by every output, checked by its consumers and by its
writer, so that a job of another (earlier, killed) run can neither feed a newer run nor replace its result.

The plan (the Snakefile, `workflow/rules/common.smk`) gives every rule a digest, `plan_digest(params, upstream)`:
SHA-256 of its config view and of the digests of the rules it reads from, so that an edit upstream changes every
digest downstream. A job gets its own digest and the digests its inputs must carry (`params: digest, expects`);
`Job(snakemake)`:

- refuses, before any work, an input whose `config_digest` is not the one the plan expects (`StaleInput`, naming
  the file, the digest found and expected, and the rule and command that rebuild it);
- stamps every NetCDF it writes with `config_digest`, `config_digest_rule` and `run_started` (through
  `uavdamp.io.STAMP_ENV`, which `uavdamp.io.with_provenance` reads; a job without a NetCDF output gives each of
  its outputs a hidden `.NAME.stamp` JSON file beside it);
- `Job.writing()`: writes under the output's lock (`uavdamp.io.exclusive`) and refuses (`NewerOutput`, nothing
  written) to replace an output of another digest made by a run started later than its own.

`run_started` is the Snakemake run's start, UTC, set once by `uavdamp.workflow.export_provenance` when the Snakefile
is parsed (a job of a killed run carries its own run's, earlier, start).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
from datetime import UTC, datetime
from pathlib import Path

import netCDF4

from uavdamp import io

DIGEST_ATTR = "config_digest"  # the plan's digest of the rule that wrote the output
RULE_ATTR = "config_digest_rule"  # that rule
RUN_ATTR = "run_started"  # UTC ISO time the writer's Snakemake run started
STAMP_SUFFIX = ".stamp"


def plan_digest(params, upstream=()) -> str:
    """16 hex digits of SHA-256 over a rule's config view `params` (JSON, keys sorted) and the digests `upstream`
    of the rules whose outputs it reads (order and repeats ignored)."""
    text = json.dumps({"params": params, "upstream": sorted(set(upstream))}, sort_keys=True, default=io.json_default)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


class Plan:
    """The plan's digests, rule by rule, as the rule files register them: `digest` registers a rule's digest (of its
    config view and of the rules it reads), `expects` gives a consumer's `{path: [digest, rule]}`."""

    def __init__(self):
        self.digests: dict[str, str] = {}  # "rule" or "rule:wildcard" -> digest

    def digest(self, key: str, params, *upstream: str) -> str:
        """Register and return the digest of rule `key` (upstream: keys already registered)."""
        self.digests[key] = plan_digest(params, [self.digests[u] for u in upstream])
        return self.digests[key]

    def expects(self, pairs: dict[str, str]) -> dict[str, list[str]]:
        """{path: [digest, rule]} of inputs given as {path: key} (key: "rule" or "rule:wildcard"), sorted by path
        (a reordered YAML mapping changes nothing)."""
        return {path: [self.digests[key], key.split(":")[0]] for path, key in sorted(pairs.items())}


def file_sha256(path) -> str:
    """SHA-256 of a file's bytes (hex): a rule parameter that reruns its job when the file's content changes."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def now() -> str:
    """The current UTC time as `run_started` holds it (ISO 8601, microseconds)."""
    return datetime.now(UTC).isoformat(timespec="microseconds")


class StaleInput(ValueError):
    """An input made with another config digest than the one the current plan expects."""


class NewerOutput(RuntimeError):
    """An output already written by a later run with another config: this job (of an earlier run) must not replace
    it."""


def stamp_path(path) -> Path:
    """The hidden stamp file of an output that is not NetCDF: `.NAME.stamp` beside it."""
    path = Path(path)
    return path.parent / f".{path.name}{STAMP_SUFFIX}"


def read_stamp(path) -> dict | None:
    """{config_digest, config_digest_rule, run_started} of output `path` (its NetCDF attributes, or its stamp file),
    None if the file is absent; missing keys are None (an output of a version without stamps)."""
    path = Path(path)
    if path.suffix == ".nc":
        if not path.is_file():
            return None

        try:
            with netCDF4.Dataset(path) as nc:
                attrs = {key: nc.getncattr(key) for key in nc.ncattrs()}
        except OSError as error:
            raise io.CorruptOutput(path, f"{type(error).__name__}: {error}") from None
    else:
        if not path.is_file():
            return None
        side = stamp_path(path)
        attrs = json.loads(side.read_text()) if side.is_file() else {}
    return {key: (str(attrs[key]) if key in attrs else None) for key in (DIGEST_ATTR, RULE_ATTR, RUN_ATTR)}


def rebuild(path, rule: str) -> str:
    return f"rule {rule} rebuilds it: rm {path} && snakemake -j2 {path} (with the same --configfile options)"


def check_inputs(expected: dict) -> None:
    """StaleInput naming the first input whose digest is not the plan's: `expected` maps path -> [digest, rule]."""
    for path, (digest, rule) in expected.items():
        stamp = read_stamp(path)
        if stamp is None:
            raise FileNotFoundError(f"{path}: no such file; {rebuild(path, rule)}")
        if stamp[DIGEST_ATTR] != digest:
            found = stamp[DIGEST_ATTR] or "none"
            raise StaleInput(
                f"{path}: made with config digest {found} (run started {stamp[RUN_ATTR] or 'unknown'}), but the "
                f"current plan expects {digest}: it is the output of another run's job (one of an earlier, killed "
                f"run, or an edit since), not of this config; refused; {rebuild(path, rule)}"
            )


def check_replace(path, digest: str, run_started: str) -> None:
    """NewerOutput if `path` holds an output of another digest than `digest` whose run started after
    `run_started`."""
    stamp = read_stamp(path)
    if stamp is None or stamp[DIGEST_ATTR] in (None, digest) or stamp[RUN_ATTR] is None:
        return
    if datetime.fromisoformat(stamp[RUN_ATTR]) > datetime.fromisoformat(run_started):
        raise NewerOutput(
            f"{path}: not replaced: it holds the result of a later run (config digest {stamp[DIGEST_ATTR]}, run "
            f"started {stamp[RUN_ATTR]}, rule {stamp[RULE_ATTR]}) and this job belongs to an earlier run (config "
            f"digest {digest}, run started {run_started}): a job that survived a killed run; nothing written"
        )


class Job:
    """A Snakemake job's stamp: its digest, its run's start, its outputs; inputs checked on creation."""

    def __init__(self, smk):
        params = smk.params
        self.digest, self.rule = str(params.digest), str(smk.rule)
        self.outputs = [str(o) for o in smk.output]
        provenance = json.loads(os.environ.get(io.PROVENANCE_ENV, "{}"))
        self.run_started = provenance.get(RUN_ATTR) or now()
        check_inputs(dict(getattr(params, "expects", {}) or {}))
        stamp = {DIGEST_ATTR: self.digest, RULE_ATTR: self.rule, RUN_ATTR: self.run_started}
        os.environ[io.STAMP_ENV] = json.dumps(stamp)

    @property
    def primary(self) -> str:
        """The output whose lock guards them all: the first NetCDF one, else the first."""
        return next((o for o in self.outputs if o.endswith(".nc")), self.outputs[0])

    def check_outputs(self) -> None:
        """NewerOutput if any output already holds a later run's result of another digest."""
        for path in self.outputs:
            check_replace(path, self.digest, self.run_started)

    @contextlib.contextmanager
    def writing(self, *, locked: bool = False, wait_s: float = io.LOCK_WAIT_S):
        """Hold the primary output's lock (unless the caller holds it: `locked`), refuse to replace a later run's
        outputs, let the block write them; a job without a NetCDF output then stamps each one (`stamp_path`)."""
        lock = contextlib.nullcontext() if locked else io.exclusive(self.primary, wait_s=wait_s)
        with lock:
            self.check_outputs()
            yield self
            if self.primary.endswith(".nc"):  # the NetCDF output carries the stamp of them all
                return
            stamp = {DIGEST_ATTR: self.digest, RULE_ATTR: self.rule, RUN_ATTR: self.run_started}
            for path in self.outputs:
                if Path(path).is_file():
                    io.write_text(json.dumps(stamp) + "\n", stamp_path(path))
