"""The quick run's outputs, damaged on a copy: a flipped byte, a truncation or damaged metadata is refused on read
naming the file and its rebuild; `python -m uavdamp.results.verify` lists them and the stale temporary files."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys

import pytest
from conftest import QUICK_RUN_ARGS, copy_workflow, flip_byte_in_data, snakemake

from uavdamp import io
from uavdamp.reference_table import chunks
from uavdamp.results import verify

OUT = "reports-quick"
DAMAGED = {  # a stage's output and a float variable of it
    "reference_table/chunks/2-of-2.nc": "criterion_displacement",
    "anfis/model.nc": "mf_centre_0",
    "study/comparison.nc": "camera_displacement",
}


def _copy(quick_run, relative, tmp_path):
    """A copy of one quick-run output in tmp_path (the shared folder is never damaged)."""
    path = tmp_path / relative
    path.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(quick_run / OUT / relative, path)
    return path


@pytest.mark.parametrize("relative", sorted(DAMAGED))
def test_a_byte_flipped_inside_a_stage_output_is_refused_naming_the_file(quick_run, tmp_path, relative):
    path = _copy(quick_run, relative, tmp_path)
    flip_byte_in_data(path, io.open_dataset(path)[DAMAGED[relative]].values)
    with pytest.raises(io.CorruptOutput, match=f"^{path}: corrupt or truncated") as error:
        io.open_dataset(path)
    assert f"rebuild it: rm {path} && snakemake -j2 all" in str(error.value)


@pytest.mark.parametrize(
    "relative",
    ["reference_table/table.nc", "anfis/model.nc", "study/comparison.nc", "benchmark/criteria.nc"],
)
def test_a_truncated_stage_output_is_refused_naming_the_file(quick_run, tmp_path, relative):
    path = _copy(quick_run, relative, tmp_path)
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    target = "benchmark" if relative.startswith("benchmark") else "all"
    with pytest.raises(io.CorruptOutput, match=f"^{path}: corrupt or truncated.*rm {path} && snakemake -j2 {target}"):
        io.open_dataset(path)


def test_damaged_chunk_metadata_names_the_chunk(quick_run, tmp_path):
    """16 bytes flipped inside the chunk's stored config (an HDF5 attribute, not covered by Fletcher-32): the
    gather's check names the chunk and its rebuild (before: an AttributeError from netCDF4 naming nothing)."""
    path = _copy(quick_run, "reference_table/chunks/2-of-2.nc", tmp_path)
    good = io.open_dataset(path)
    config, points = json.loads(good.attrs["config_reference_table"]), good.point.values
    data = bytearray(path.read_bytes())
    start = data.index(b'"amplitude')
    data[start : start + 16] = bytes(b ^ 0x20 for b in data[start : start + 16])
    path.write_bytes(bytes(data))
    with pytest.raises(ValueError, match=f"^reference-table chunk {path}: .*rebuild it: rm {path} && snakemake"):
        chunks.load_chunk(path, points=points, config=config)


def _dead_pid() -> int:
    done = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    return int(done.stdout)


@pytest.fixture
def damaged_run(quick_run, tmp_path):
    """A copy of the quick run's outputs with comparison.nc truncated, a stale temporary file (its writer's pid
    is dead) and a live one (this process's)."""
    out = tmp_path / OUT
    shutil.copytree(quick_run / OUT, out)
    bad = out / "study/comparison.nc"
    bad.write_bytes(bad.read_bytes()[:5000])
    host = os.uname().nodename
    stale = out / f"anfis/.model.nc~{host}~{_dead_pid()}~abcd1234.tmp.nc"
    live = out / f"anfis/.training.nc~{host}~{os.getpid()}~efgh5678.tmp.nc"
    stale.write_bytes(b"partial")
    live.write_bytes(b"in progress")
    return out, bad, stale, live


def test_verify_lists_the_corrupt_file_and_the_stale_temporary_and_cleans_only_that(damaged_run, capsys):
    out, bad, stale, live = damaged_run
    assert verify.main([str(out)]) == 1
    report = capsys.readouterr().out
    assert f"CORRUPT {bad}: corrupt or truncated" in report and f"rm {bad} && snakemake -j2 all" in report
    assert f"STALE {stale}" in report and str(live) not in report
    assert report.count("CORRUPT") == 1 and stale.exists()
    assert verify.main([str(out), "--clean"]) == 1
    assert not stale.exists() and live.exists()
    bad.unlink()
    assert verify.main([str(out)]) == 0
    assert "0 corrupt, 0 stale temporary" in capsys.readouterr().out


def test_an_untagged_or_foreign_temporary_is_stale_only_when_old(tmp_path):
    path = tmp_path / ".x.nc.abcd1234.tmp.nc"
    path.write_bytes(b"x")
    assert verify.temporary_files(tmp_path) == [path]
    assert not verify.is_stale(path, max_age_h=1.0)
    assert verify.is_stale(path, max_age_h=1.0, now=path.stat().st_mtime + 3601.0)
    foreign = tmp_path / f".y.nc~not-{os.uname().nodename}~1~abcd1234.tmp.nc"
    foreign.write_bytes(b"y")
    assert not verify.is_stale(foreign) and verify.is_stale(foreign, max_age_h=0.0, now=foreign.stat().st_mtime + 1)


def test_the_verify_target_fails_naming_the_corrupt_file_after_onstart_cleaned_the_stale_temporary(
    damaged_run, tmp_path
):
    out, bad, stale, live = damaged_run
    work = copy_workflow(tmp_path / "work")
    shutil.move(out, work / OUT)
    (work / "config/plugin.yaml").write_text("{}\n")
    result = snakemake(work, "-j1", "verify", *QUICK_RUN_ARGS)
    assert result.returncode != 0
    text = result.stdout + result.stderr
    assert f"CORRUPT {OUT}/study/comparison.nc: corrupt or truncated" in text, text[-3000:]
    assert f"removed a stale temporary file: {OUT}/anfis/.model.nc~" in text
    moved = work / OUT / stale.relative_to(out)
    assert not moved.exists() and (work / OUT / live.relative_to(out)).exists()
