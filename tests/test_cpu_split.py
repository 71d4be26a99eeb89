"""benchmarks/cpu_split.py: a py-spy profile's samples split by process and by what the process was doing."""

from __future__ import annotations

import subprocess
import sys

import pytest
from conftest import ROOT, load_module

cs = load_module(ROOT / "benchmarks/cpu_split.py", "uavdamp_cpu_split")

PYTEST = 'process 10:"/venv/bin/python3 .venv/bin/pytest -p no:cacheprovider"'
WORKER = 'process 11:"/venv/bin/python3 -u -c import sys;exec(eval(sys.stdin.readline()))"'  # a ";" inside
SNAKEMAKE = 'process 12:"/venv/bin/python3 -m snakemake -j2 all --configfile config/quick.yaml"'
STUDY = 'process 13:"/venv/bin/python3 /tmp/q/.snakemake/scripts/tmpab12_x.study.py"'
IMPORT = "_find_and_load (<frozen importlib._bootstrap>:1176);<module> (scipy/stats/__init__.py:3)"
SAVE = "save_figure (uavdamp/io.py:275);Figure.savefig (matplotlib/figure.py:3515)"
LAYOUT = "do_constrained_layout (matplotlib/_constrained_layout.py:120)"
# a hand-made raw profile (py-spy's format: the process frames, then the Python frames, then the sample count)
LINES = [
    f"{PYTEST};{WORKER};{SNAKEMAKE};{STUDY};<module> (tmpab12_x.study.py:13);{IMPORT} 7\n",
    f"{PYTEST};{WORKER};{SNAKEMAKE};{STUDY};<module> (tmpab12_x.study.py:45);{SAVE};{LAYOUT} 5\n",
    f"{PYTEST};{WORKER};{SNAKEMAKE};{STUDY};<module> (tmpab12_x.study.py:45);{SAVE};draw_path (agg.py:1) 3\n",
    f"{PYTEST};{WORKER};{SNAKEMAKE};{STUDY};run_study (uavdamp/study/comparison.py:80);expm (scipy/linalg.py:9) 11\n",
    f"{PYTEST};{WORKER};{SNAKEMAKE};Thread._bootstrap (threading.py:1002);Condition.wait (threading.py:331) 4\n",
    f"{PYTEST};{WORKER};test_x (tests/test_x.py:3);expm (scipy/linalg.py:9) 6\n",
    'process 14:"";main (snakemake/cli.py:2) 2\n',  # py-spy's own child: no command line
    "\n",
    "a line without a count\n",
]


def test_samples_are_split_by_process_and_activity_as_counted_by_hand():
    """Each line's leaf process (the last process frame, a command line with a ";" kept whole) and its activity:
    the study job imported 7, drew figures 5 + 3 (5 of them in the constrained layout) and computed 11 samples,
    Snakemake waited 4, the pytest worker computed 6; blank and malformed lines are skipped."""
    split = cs.split(LINES)
    assert split == {
        "job study.py": {"import": 7, "figure": 8, "layout": 5, "compute": 11},
        "snakemake": {"waiting": 4},
        "pytest worker": {"compute": 6},
        "the command": {"compute": 2},
    }


def test_the_report_gives_seconds_at_the_rate_and_the_shares_of_the_whole_run():
    """At 2 Hz: the study job 7 + 8 + 11 = 26 samples, 13.0 s; the run 38 samples, 19.0 s, of which imports
    7 / 38 = 18 %, figures 8 / 38 = 21 %, waiting 4 / 38 = 11 %, compute 19 / 38 = 50 %."""
    text = cs.report(cs.split(LINES), rate=2.0, top=10)
    assert "import 18 %, figure 21 %, layout 13 %, waiting 11 %, compute 50 %" in text.splitlines()[0]
    rows = {line.split()[0] + " " + line.split()[1]: line.split() for line in text.splitlines()[2:]}
    assert rows["job study.py"][2:] == ["13.0", "3.5", "4.0", "2.5", "0.0", "5.5"]
    assert text.splitlines()[2].split() == ["all", "19.0", "3.5", "4.0", "2.5", "2.0", "9.5"]


@pytest.mark.parametrize(
    ("args", "message"),
    [(["record", "x.raw"], "give the command to profile after --"), (["report", "missing.raw"], "missing.raw")],
)
def test_a_missing_command_or_profile_is_named(tmp_path, args, message):
    result = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks/cpu_split.py"), *args], cwd=tmp_path, capture_output=True, text=True
    )
    assert result.returncode != 0 and message in result.stderr
