"""Writing and reading result datasets: CF metadata checks, provenance, Fletcher-32 checksums, atomic replace,
one writer per output.

Every variable of one or more dimensions is written with HDF5's Fletcher-32 filter (chunked storage; 0-d
variables are stored compact and carry none), so a flipped byte in its data fails on read; `open_dataset` reads
everything eagerly and turns netCDF/HDF5 errors and truncation into `CorruptOutput`, naming the file and the
command that rebuilds it. `exclusive(path)` holds an OS file lock beside an output while a job writes it. A job's
config digest and run start (`uavdamp.integrity`) reach every file it writes through `STAMP_ENV`.
"""

from __future__ import annotations

import contextlib
import functools
import json
import os
import socket
import sys
import tempfile
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path

import numpy as np
import xarray as xr
from filelock import FileLock, Timeout

from uavdamp import plugins

CONVENTIONS = "CF-1.11"
REFERENCE = (
    "Marichal G.N. et al. (2014) Vibration reduction for vision systems on board UAV using a "
    "neuro-fuzzy controller. J. Vib. Control 20(15) 2243-2253, doi:10.1177/1077546313479632"
)
# CF (and the IOOS checker) require a coordinate named `time` to count from an epoch; the study's
# clock starts at 0 s, so files carry a nominal epoch and `open_dataset` turns it back into seconds.
TIME_UNITS = "s since 2000-01-01 00:00:00"
LOCK_WAIT_S = 6 * 3600.0  # s a job waits for another live writer of its output (a dead one's lock is already free)
PROVENANCE_ENV = "UAVDAMP_PROVENANCE"  # JSON set by the Snakefile (uavdamp.workflow.export_provenance)
STAMP_ENV = "UAVDAMP_STAMP"  # JSON set by a job: its config digest and run start (uavdamp.integrity.Job)
_VERSIONED = ("uavdamp", "numpy", "scipy", "exudyn", "xarray", "netCDF4", "joblib", "scikit-fuzzy", "snakemake")


def package_versions() -> dict[str, str]:
    """Installed versions of the packages that shape the results (missing ones omitted)."""
    versions = {"python": sys.version.split()[0]}
    for name in _VERSIONED:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            continue
    return versions


class CorruptOutput(ValueError, OSError):
    """An output that cannot be read back whole: truncated, not NetCDF, or failing its checksums.

    `reason`: the reader's error, "TYPE: text".
    """

    def __init__(self, path, reason: str):
        super().__init__(
            f"{path}: corrupt or truncated, cannot be read ({reason}); rebuild it: {rebuild_command(path)}"
        )
        self.path, self.reason = Path(path), reason


def rebuild_command(path) -> str:
    """The command that rebuilds output `path`: delete it, then rerun the target that makes it."""
    target = "benchmark" if "benchmark" in Path(path).parts else "all"
    return f"rm {path} && snakemake -j2 {target} (with the same --configfile options)"


def check_metadata(ds: xr.Dataset) -> None:
    """Raise ValueError naming every variable or coordinate without `units` or `long_name`."""
    missing = [
        f"{name} ({key})"
        for name in list(ds.coords) + list(ds.data_vars)
        for key in ("units", "long_name")
        if key not in ds[name].attrs
    ]
    if missing:
        raise ValueError("NetCDF metadata missing: " + ", ".join(missing))


def writer_tag() -> str:
    """`host~pid` of this process: a lock's holder file carries it."""
    return f"{socket.gethostname()}~{os.getpid()}"


def atomic_write(path: str | os.PathLike, write) -> Path:
    """Call write(temporary path) in `path`'s folder, then rename it over `path`; nothing is left on failure
    (but a SIGKILL: `.NAME~host~pid~XXXX.tmp.SUFFIX` stays, `uavdamp.results.verify` finds and cleans it).

    The temporary file gets the permissions a plain open() would give (umask), not mkstemp's 0600.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    prefix = f".{path.name}~{socket.gethostname()}~{os.getpid()}~"
    fd, tmp = tempfile.mkstemp(prefix=prefix, suffix=".tmp" + path.suffix, dir=path.parent)
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def json_default(value):
    """`json.dumps` default for NumPy scalars and arrays."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"not JSON serialisable: {value!r}")


def with_provenance(ds: xr.Dataset, config: dict, *, section: str, command: str | None = None) -> xr.Dataset:
    """Copy of `ds` with CF global attributes and provenance.

    `config` is the config section that produced the data (stored as JSON text under
    `config_<section>`); `command` defaults to the running process's command line.
    """
    command = command if command is not None else " ".join([Path(sys.argv[0]).name, *sys.argv[1:]])
    stamp = datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    out = ds.copy()
    if "time" in out.coords and out["time"].attrs.get("units") == "s":
        out["time"].attrs.update(
            units=TIME_UNITS, standard_name="time", axis="T", calendar="standard", units_metadata="leap_seconds: none"
        )
    out.attrs.update(
        {
            "title": ds.attrs.get("title", f"uavdamp {section}"),
            "Conventions": CONVENTIONS,
            "source": "uavdamp " + package_versions().get("uavdamp", "unknown"),
            "references": REFERENCE,
            "history": f"{stamp} {command}",
            "command": command,
            "package_versions": json.dumps(package_versions(), sort_keys=True),
            f"config_{section}": json.dumps(config, sort_keys=True, default=json_default),
            **json.loads(os.environ.get(PROVENANCE_ENV, "{}")),
            **json.loads(os.environ.get(STAMP_ENV, "{}")),
            **plugins.provenance(),
        }
    )
    return out


def _encoding(ds: xr.Dataset) -> dict:
    """No _FillValue on coordinates (CF); keep NaN as the fill of float data variables; Fletcher-32 on every
    variable HDF5 chunks (one or more dimensions)."""
    enc = {name: {"_FillValue": None} for name in ds.coords}
    for name, var in ds.data_vars.items():
        enc[name] = {"_FillValue": np.nan if np.issubdtype(var.dtype, np.floating) else None}
    for name, var in ds.variables.items():
        if var.ndim:
            enc[name]["fletcher32"] = True
    return enc


def write_netcdf(
    ds: xr.Dataset, path: str | os.PathLike, config: dict, *, section: str, command: str | None = None
) -> Path:
    """Write `ds` with provenance to `path` atomically (temporary file in the same folder, then rename).

    Raises ValueError before writing anything if a variable lacks `units` or `long_name`.
    """
    check_metadata(ds)
    out = with_provenance(ds, config, section=section, command=command)
    return atomic_write(
        path, lambda tmp: out.to_netcdf(tmp, engine="netcdf4", format="NETCDF4", encoding=_encoding(out))
    )


def open_dataset(path: str | os.PathLike) -> xr.Dataset:
    """Load a dataset written by `write_netcdf` whole, with `time` as plain seconds (float, units "s").

    Raises CorruptOutput naming the file and its rebuild command if it is truncated, not NetCDF, or a
    variable fails its checksum (netCDF4 checks on read: every variable is read here); FileNotFoundError if absent.
    """
    if not Path(path).is_file():
        raise FileNotFoundError(f"{path}: no such file")
    try:
        with xr.open_dataset(path, decode_times=False, engine="netcdf4") as ds:
            ds = ds.load()
    except (OSError, RuntimeError, ValueError, KeyError, IndexError, AttributeError) as error:  # netCDF4/HDF5
        raise CorruptOutput(path, f"{type(error).__name__}: {error}") from None
    if "time" in ds.coords and ds["time"].attrs.get("units") == TIME_UNITS:
        ds["time"].attrs = {"units": "s", "long_name": ds["time"].attrs.get("long_name", "time")}
    return ds


@contextlib.contextmanager
def exclusive(path, *, wait_s: float = 0.0, poll_s: float = 0.5):
    """Hold the lock of output `path` (a hidden `.NAME.lock` beside it) for the block.

    filelock on fcntl: released when the holder dies, even by SIGKILL. If another process holds it, wait up to
    `wait_s` s for it, then raise ValueError naming the holder (host~pid, from `.NAME.lock.holder`). Yields
    True if it had to wait (the holder may have written `path`: check it before recomputing), else False.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    lock = FileLock(path.parent / f".{path.name}.lock")
    holder = path.parent / f".{path.name}.lock.holder"
    try:
        lock.acquire(timeout=0)
        waited = False
    except Timeout:
        try:
            lock.acquire(timeout=wait_s, poll_interval=poll_s)
        except Timeout:
            who = holder.read_text().strip() if holder.is_file() else "unknown"
            raise ValueError(
                f"{path}: another process ({who}, host~pid) has held its lock {lock.lock_file} for more than "
                f"{wait_s:g} s: a job of an earlier, killed run is still running; stop it (README, 'A killed "
                "run') or let it finish, then run Snakemake again"
            ) from None
        waited = True
    try:
        holder.write_text(writer_tag() + "\n")
        yield waited
    finally:
        holder.unlink(missing_ok=True)
        lock.release()


def write_guarded(path, make, *, finished, wait_s: float = LOCK_WAIT_S) -> bool:
    """Under `exclusive(path)`: call make() (compute and write `path`) unless the lock was held by another
    process that left a finished output (finished(path) true): that one is kept as it is. Returns True if made."""
    with exclusive(path, wait_s=wait_s) as waited:
        if waited and finished(path):
            return False
        make()
        return True


def write_once(path, make, config: dict, *, section: str, wait_s: float = LOCK_WAIT_S) -> bool:
    """`write_guarded` for an output whose `config_<section>` says what made it: a holder's output that reads
    whole and was made with `config` is kept. Returns True if made here."""
    finished = functools.partial(kept_output, config=config, section=section)
    return write_guarded(path, make, finished=finished, wait_s=wait_s)


def kept_output(path, config: dict, *, section: str) -> bool:
    """True if `path` exists, reads whole and was made with `config` (its `config_<section>` attribute)."""
    try:
        ds = open_dataset(path)
    except (FileNotFoundError, CorruptOutput):
        return False
    stored = ds.attrs.get(f"config_{section}")
    return stored is not None and json.loads(stored) == json.loads(json.dumps(config, default=json_default))


def read_config_attr(ds: xr.Dataset, section: str) -> dict:
    """The config section stored in a dataset written by `write_netcdf`; KeyError naming the attribute, the file and
    the sections it holds when the section is not stored."""
    key = f"config_{section}"
    if key not in ds.attrs:
        stored = sorted(name.removeprefix("config_") for name in ds.attrs if name.startswith("config_"))
        source = ds.encoding.get("source", "the dataset")
        raise KeyError(f"{source}: no attribute {key!r}: config section {section!r} not stored (stored: {stored})")
    return json.loads(ds.attrs[key])


def save_figure(fig, path: str | os.PathLike, dpi: int = 120) -> Path:
    """Save a matplotlib figure atomically and close it."""
    import matplotlib.pyplot as plt

    try:
        return atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format=Path(path).suffix.lstrip(".") or None))
    finally:
        plt.close(fig)


def write_text(text: str, path: str | os.PathLike) -> Path:
    """Write a text file atomically."""
    return atomic_write(path, lambda tmp: Path(tmp).write_text(text))
