"""Plug-in files: what they declare they read is an input and in the provenance; an import that fails or exits is an
error naming the file. Expected digests are hashlib's of the bytes written here, not the module's."""

from __future__ import annotations

import hashlib
import json

import pytest
import yaml
from conftest import copy_workflow, deep_update, load_config, snakemake

from uavdamp import plugins
from uavdamp.config import checks, load
from uavdamp.settings import ConfigError

TABLE = '{"gain": 2.5}\n'
DATA_LAW = 'DATA_FILES = ["gain_table.json"]  # read by the law below (relative to this file)\n'


def test_a_plugin_that_exits_at_import_is_an_error_naming_the_file(tmp_path):
    """sys.exit(0) (and any exception) while the plug-in is imported: a ConfigError naming the file and what it
    raised, from the config check every Snakemake call runs.

    seen failing on the previous main: SystemExit(0) went through the config check (so `snakemake all` exited 0
    having done nothing, without a message)."""
    for name, body, raised in (
        ("exits.py", "import sys\nsys.exit(0)\n", "SystemExit"),
        ("breaks.py", "raise KeyError('gain')\n", "KeyError"),
    ):
        path = tmp_path / name
        path.write_text(body)
        config = load(deep_update(load_config("quick.yaml"), {"plugins": [str(path)]}))
        with pytest.raises(ConfigError) as error:
            checks.check_names(config)
        assert f"plugins: importing {str(path)!r} raised {raised}" in str(error.value)


def test_a_plugins_declared_data_files_enter_its_record_and_the_provenance(tmp_path):
    """DATA_FILES relative to the plug-in file: each one's SHA-256 (hashlib here) in the load's record and in the
    ``plugins`` attribute every output of its jobs carries; a declared file that is missing is refused naming it.

    seen failing on the previous main: the record and the provenance held the .py file's SHA-256 only."""
    (tmp_path / "gain_table.json").write_text(TABLE)
    law = tmp_path / "data_law.py"
    law.write_text(DATA_LAW)
    (record,) = plugins.load([str(law)])
    expected = [{"path": str(tmp_path / "gain_table.json"), "sha256": hashlib.sha256(TABLE.encode()).hexdigest()}]
    assert record["data"] == expected
    mine = [r for r in json.loads(plugins.provenance()["plugins"]) if r["path"] == str(law)]
    assert mine == [{"path": str(law), "sha256": hashlib.sha256(DATA_LAW.encode()).hexdigest(), "data": expected}]
    missing = tmp_path / "missing_law.py"
    missing.write_text('DATA_FILES = ["nowhere.json"]\n')
    with pytest.raises(plugins.PluginError, match="nowhere.json"):
        plugins.load([str(missing)])


def test_a_plugins_data_file_is_an_input_of_the_rules_that_import_it(tmp_path):
    """Snakemake dry run (quick config plus an override naming the plug-in): the study job lists the plug-in's data
    file among its inputs, so editing the file reruns it.

    seen failing on the previous main: the study job's inputs held the .py file only (an edited data file gave
    "Nothing to be done")."""
    workdir = copy_workflow(tmp_path / "wf")
    (workdir / "laws").mkdir()
    (workdir / "laws" / "gain_table.json").write_text(TABLE)
    (workdir / "laws" / "data_law.py").write_text(DATA_LAW)
    (workdir / "config" / "data_law.yaml").write_text(yaml.safe_dump({"plugins": ["laws/data_law.py"]}))
    out = load_config("quick.yaml")["output_dir"]
    result = snakemake(
        workdir,
        "-n",
        f"{out}/study/comparison.nc",
        "--configfile",
        "config/quick.yaml",
        "config/data_law.yaml",
        timeout=300,
    )
    assert result.returncode == 0, result.stderr[-3000:]
    plan = result.stdout
    study = plan[plan.index("rule study:") :]
    inputs = study[study.index("input:") : study.index("output:")]
    assert "laws/gain_table.json" in inputs and "laws/data_law.py" in inputs
