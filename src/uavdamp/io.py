"""Writing result datasets to NetCDF: CF metadata checks, provenance, atomic replace."""

from __future__ import annotations

import json
import logging
import os
import sys
import tempfile
from datetime import datetime, timezone
from importlib import metadata
from pathlib import Path

import numpy as np
import xarray as xr

CONVENTIONS = "CF-1.11"
REFERENCE = (
    "Marichal G.N. et al. (2014) Vibration reduction for vision systems on board UAV using a "
    "neuro-fuzzy controller. J. Vib. Control 20(15) 2243-2253, doi:10.1177/1077546313479632"
)
# CF (and the IOOS checker) require a coordinate named `time` to count from an epoch; the study's
# clock starts at 0 s, so files carry a nominal epoch and `open_dataset` turns it back into seconds.
TIME_UNITS = "s since 2000-01-01 00:00:00"
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


def _temporary_beside(path: Path) -> str:
    """A new empty file in `path`'s folder with the permissions a plain open() would give (umask)."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp" + path.suffix, dir=path.parent)
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    return tmp


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
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
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
        }
    )
    return out


def _encoding(ds: xr.Dataset) -> dict:
    """No _FillValue on coordinates (CF); keep NaN as the fill of float data variables."""
    enc = {name: {"_FillValue": None} for name in ds.coords}
    for name, var in ds.data_vars.items():
        if np.issubdtype(var.dtype, np.floating):
            enc[name] = {"_FillValue": np.nan}
        else:
            enc[name] = {"_FillValue": None}
    return enc


def write_netcdf(
    ds: xr.Dataset, path: str | os.PathLike, config: dict, *, section: str, command: str | None = None
) -> Path:
    """Write `ds` with provenance to `path` atomically (temporary file in the same folder, then rename).

    Raises ValueError before writing anything if a variable lacks `units` or `long_name`.
    """
    check_metadata(ds)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    out = with_provenance(ds, config, section=section, command=command)
    tmp = _temporary_beside(path)
    try:
        out.to_netcdf(tmp, engine="netcdf4", format="NETCDF4", encoding=_encoding(out))
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def open_dataset(path: str | os.PathLike) -> xr.Dataset:
    """Load a dataset written by `write_netcdf`, with `time` as plain seconds (float, units "s")."""
    with xr.open_dataset(path, decode_times=False) as ds:
        ds = ds.load()
    if "time" in ds.coords and ds["time"].attrs.get("units") == TIME_UNITS:
        ds["time"].attrs = {"units": "s", "long_name": ds["time"].attrs.get("long_name", "time")}
    return ds


def read_config_attr(ds: xr.Dataset, section: str) -> dict:
    """The config section stored in a dataset written by `write_netcdf`."""
    return json.loads(ds.attrs[f"config_{section}"])


def snakemake_command(smk) -> str:
    """A readable command for provenance: the rule and its wildcards as Snakemake ran them."""
    wildcards = ", ".join(f"{k}={v}" for k, v in dict(smk.wildcards).items())
    return f"snakemake rule {smk.rule}" + (f" [{wildcards}]" if wildcards else "")


def start_log(path: str | os.PathLike) -> None:
    """Send this process's log records, warnings, prints and tracebacks to `path` (a Snakemake `log:`)."""
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    sys.stderr = sys.stdout = open(path, "a", buffering=1)  # tracebacks and prints land in the log too
    logging.basicConfig(stream=sys.stderr, level=logging.INFO,
                        format="%(asctime)s %(levelname)s %(message)s", force=True)
    logging.captureWarnings(True)
    logging.getLogger("uavdamp").info("versions: %s", json.dumps(package_versions(), sort_keys=True))


def log_info(message: str) -> None:
    logging.getLogger("uavdamp").info(message)


def save_figure(fig, path: str | os.PathLike, dpi: int = 120) -> Path:
    """Save a matplotlib figure atomically (temporary file in the same folder, then rename) and close it."""
    import matplotlib.pyplot as plt

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = _temporary_beside(path)
    try:
        fig.savefig(tmp, dpi=dpi, format=path.suffix.lstrip(".") or None)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    finally:
        plt.close(fig)
    return path


def write_text(text: str, path: str | os.PathLike) -> Path:
    """Write a text file atomically (temporary file in the same folder, then rename)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = _temporary_beside(path)
    try:
        Path(tmp).write_text(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def config_view(section: dict, *, drop=(), keep=None) -> dict:
    """The keys of a config section a rule uses (all but `drop`, or only `keep`), canonical."""
    return canonical({k: v for k, v in section.items() if k not in drop and (keep is None or k in keep)})


def canonical(config):
    """A config section with its mappings' keys sorted, at every depth (for Snakemake `params:`).

    Snakemake compares params by their text, so the same values in another key order would look
    like an edit and rerun the rule; sorted keys make a reordered YAML file change nothing.
    """
    return json.loads(json.dumps(config, sort_keys=True))
