"""NetCDF writing: metadata checks, provenance, CF time, atomic replace."""

from __future__ import annotations

import json
import os
import stat

import numpy as np
import pytest
import xarray as xr

from uavdamp import io


def small_dataset() -> xr.Dataset:
    return xr.Dataset(
        {"displacement": (("axis", "time"), np.arange(6.0).reshape(2, 3), {"units": "m", "long_name": "displacement"})},
        coords={
            "axis": ("axis", ["y", "z"], {"units": "1", "long_name": "axis"}),
            "time": ("time", [0.0, 0.1, 0.2], {"units": "s", "long_name": "simulation time"}),
        },
    )


def test_round_trip_with_provenance(tmp_path):
    path = io.write_netcdf(
        small_dataset(), tmp_path / "a.nc", {"step": 0.001, "n": np.int64(3)}, section="demo", command="pytest"
    )
    ds = io.open_dataset(path)
    xr.testing.assert_identical(
        ds.displacement.reset_coords(drop=True), small_dataset().displacement.reset_coords(drop=True)
    )
    np.testing.assert_array_equal(ds.time.values, [0.0, 0.1, 0.2])
    assert ds.time.attrs["units"] == "s"
    assert ds.attrs["Conventions"] == "CF-1.11"
    assert io.read_config_attr(ds, "demo") == {"step": 0.001, "n": 3}
    assert "numpy" in json.loads(ds.attrs["package_versions"])
    assert ds.attrs["command"] == "pytest"
    with xr.open_dataset(path, decode_times=False) as raw:
        assert raw.time.attrs["units"] == io.TIME_UNITS
        assert "_FillValue" not in raw.time.encoding or raw.time.encoding["_FillValue"] is None


def test_missing_metadata_named_and_nothing_written(tmp_path):
    target = tmp_path / "b.nc"
    target.write_text("previous result")
    ds = small_dataset()
    del ds["displacement"].attrs["units"]
    with pytest.raises(ValueError, match=r"displacement \(units\)"):
        io.write_netcdf(ds, target, {}, section="demo")
    assert target.read_text() == "previous result"
    assert list(tmp_path.iterdir()) == [target]


def test_failed_write_leaves_no_partial_file(tmp_path):
    ds = small_dataset()
    ds.attrs["bad"] = {"a dict": "is not a valid netCDF attribute"}
    target = tmp_path / "c.nc"
    with pytest.raises(TypeError, match="Invalid value for attr 'bad'"):
        io.write_netcdf(ds, target, {}, section="demo")
    assert list(tmp_path.iterdir()) == []


def test_outputs_get_umask_permissions(tmp_path):
    old = os.umask(0o022)
    try:
        path = io.write_netcdf(small_dataset(), tmp_path / "p.nc", {}, section="demo")
        text = io.write_text("x", tmp_path / "t.txt")
    finally:
        os.umask(old)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644
    assert stat.S_IMODE(text.stat().st_mode) == 0o644
