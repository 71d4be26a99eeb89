"""Writing result datasets to NetCDF: CF metadata checks, provenance, atomic replace."""

from __future__ import annotations

import json
import os
import sys
import tempfile
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path

import numpy as np
import xarray as xr

from uavdamp import plugins

CONVENTIONS = "CF-1.11"
REFERENCE = (
    "Marichal G.N. et al. (2014) Vibration reduction for vision systems on board UAV using a "
    "neuro-fuzzy controller. J. Vib. Control 20(15) 2243-2253, doi:10.1177/1077546313479632"
)
# CF (and the IOOS checker) require a coordinate named `time` to count from an epoch; the study's
# clock starts at 0 s, so files carry a nominal epoch and `open_dataset` turns it back into seconds.
TIME_UNITS = "s since 2000-01-01 00:00:00"
PROVENANCE_ENV = "UAVDAMP_PROVENANCE"  # JSON set by the Snakefile (uavdamp.workflow.export_provenance)
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


def atomic_write(path: str | os.PathLike, write) -> Path:
    """Call write(temporary path) in `path`'s folder, then rename it over `path`; nothing is left on failure.

    The temporary file gets the permissions a plain open() would give (umask), not mkstemp's 0600.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp" + path.suffix, dir=path.parent)
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
            **plugins.provenance(),
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
    out = with_provenance(ds, config, section=section, command=command)
    return atomic_write(
        path, lambda tmp: out.to_netcdf(tmp, engine="netcdf4", format="NETCDF4", encoding=_encoding(out))
    )


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
