"""The package's architecture rules, read from the source: one clamp of the damping, layering without circles."""

from __future__ import annotations

import ast
import re
import subprocess
import sys

import numpy as np
from conftest import ROOT, anfis_options

from uavdamp.anfis import DampingModel

SRC = ROOT / "src" / "uavdamp"
BOUNDS = re.compile(r"\b(c_min|c_max|damping_min|damping_max)\b")


def _clamps(tree: ast.AST, contract_clip: bool):
    """Calls of min, max or a clip whose arguments name a damper bound (but `uavdamp.contract.clip` itself when
    the module imports it, and the lower end of a log-spaced candidate grid, which cannot start at 0)."""
    grids = [n for n in ast.walk(tree) if isinstance(n, ast.Call) and getattr(n.func, "attr", "") == "geomspace"]
    inside_grid = {id(d) for g in grids for d in ast.walk(g)}
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and id(node) not in inside_grid:
            name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
            if name == "clip" and isinstance(node.func, ast.Name) and contract_clip:
                continue
            if name in ("min", "max", "clip", "minimum", "maximum") and BOUNDS.search(ast.unparse(node)):
                yield node.lineno, ast.unparse(node)


def _imports_contract_clip(tree: ast.AST) -> bool:
    return any(
        isinstance(n, ast.ImportFrom) and n.module == "uavdamp.contract" and any(a.name == "clip" for a in n.names)
        for n in ast.walk(tree)
    )


def test_the_damping_is_clamped_in_one_place():
    """`uavdamp.contract.clip` is the only clamp of a damping demand to [c_min, c_max]: a plant, a law or a
    strategy that clamps on its own would let the bounds drift apart (the architecture issue)."""
    found = []
    for path in SRC.rglob("*.py"):
        tree = ast.parse(path.read_text())
        imported = _imports_contract_clip(tree)
        for function in (n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)):
            if path.name == "contract.py" and function.name == "clip":
                continue
            found += [f"{path.relative_to(SRC)}:{line}: {text}" for line, text in _clamps(function, imported)]
    assert sorted(set(found)) == [], "clamp the damping with uavdamp.contract.clip only"


def _imports(path) -> set[str]:
    tree = ast.parse(path.read_text())
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("uavdamp"):
            names.add(node.module)
        elif isinstance(node, ast.Import):
            names |= {a.name for a in node.names if a.name.startswith("uavdamp")}
    return names


def test_the_packages_import_without_circles():
    """The import graph between uavdamp's packages and top-level modules is acyclic (module-level imports)."""

    def unit(module: str) -> str:
        parts = module.split(".")
        return ".".join(parts[:2]) if len(parts) > 1 else module

    graph: dict[str, set[str]] = {}
    for path in SRC.rglob("*.py"):
        module = "uavdamp." + ".".join(path.relative_to(SRC).with_suffix("").parts)
        graph.setdefault(unit(module), set()).update(unit(m) for m in _imports(path))
    for node in graph:
        graph[node].discard(node)
        graph[node].discard("uavdamp")
    state: dict[str, int] = {}

    def visit(node, trail):
        if state.get(node) == 1:
            raise AssertionError(f"import circle: {' -> '.join([*trail, node])}")
        if state.get(node) == 2:
            return
        state[node] = 1
        for nxt in sorted(graph.get(node, ())):
            visit(nxt, [*trail, node])
        state[node] = 2

    for node in sorted(graph):
        visit(node, [])


# third-party modules a function may import where it is used: heavy readers of one file format, the plotting
# backend, numba (`uavdamp.compiled`: the kernels compiled on first use) and SciPy's heavy subpackages (signal brings
# stats: 0.65 s over numpy and xarray; optimize 0.29 s, interpolate 0.38 s, integrate 0.41 s, ndimage 0.12 s; each
# the least of 3 imports, 2026-12-07), so that `import uavdamp`, the numeric modules and a job that never filters,
# fits or interpolates stay cheap (tests/test_flight_log.py checks the first,
# `test_the_heavy_scipy_subpackages_wait_for_the_first_call` the last)
LAZY_THIRD_PARTY = {"pyulog", "pymavlink", "matplotlib", "numba"}
LAZY_SCIPY = ("scipy.signal", "scipy.optimize", "scipy.interpolate", "scipy.integrate", "scipy.ndimage")


def _function_imports(path):
    tree = ast.parse(path.read_text())
    for function in (n for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))):
        for node in ast.walk(function):
            if isinstance(node, ast.Import):
                yield node.lineno, function.name, [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module == "scipy":  # `from scipy import signal`
                yield node.lineno, function.name, [f"scipy.{a.name}" for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                yield node.lineno, function.name, [node.module or ""]


def _lazy(module: str) -> bool:
    return module.split(".")[0] in LAZY_THIRD_PARTY or any(module.startswith(p) for p in LAZY_SCIPY)


def test_no_import_hides_inside_a_function():
    """Every arrow of the import graph is at a module's top: a function imports only a heavy third-party reader
    (`LAZY_THIRD_PARTY`) or a heavy SciPy subpackage (`LAZY_SCIPY`), and the package face `uavdamp.__getattr__`
    its lazy `read_flight_log` (the flight-log readers stay out of `import uavdamp`)."""
    found = []
    for path in sorted(SRC.rglob("*.py")):
        for line, function, modules in _function_imports(path):
            if path == SRC / "__init__.py" and function == "__getattr__":
                continue
            hidden = [m for m in modules if not _lazy(m)]
            found += [f"{path.relative_to(SRC)}:{line}: {function}: import {m}" for m in hidden]
    assert found == [], "move these imports to the module's top"


def test_the_plant_does_not_import_the_sources():
    """The plant sits below the vibration sources: `uavdamp.platform` imports neither `uavdamp.sources` nor
    `uavdamp.sources.flight_log` (the mount motion's resampler lives beside its type in `uavdamp.contract`)."""
    found = [
        f"{path.relative_to(SRC)}: {module}"
        for path in sorted((SRC / "platform").rglob("*.py"))
        for module in _imports(path)
        if module.startswith(("uavdamp.sources", "uavdamp.sources.flight_log", "uavdamp.study", "uavdamp.benchmark"))
    ]
    assert found == []


def test_numba_waits_for_the_first_kernel_call():
    """The modules that hold compiled kernels import without numba (`uavdamp.compiled`: a job that steps no kernel
    skips its 0.17 s import); the first kernel call brings it in. Seen failing with `from numba import njit` at a
    kernel module's top."""
    script = (
        "import sys\n"
        "import numpy as np\n"
        "import uavdamp.helicopter.flight, uavdamp.study.payload, uavdamp.benchmark.loop\n"
        "from uavdamp.damping.dampers import SpencerMR, SpencerParams\n"
        "before = 'numba' in sys.modules\n"
        "SpencerMR(SpencerParams.published(), 1).step(1e-3, 0.0, np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(1))\n"
        "print(before, 'numba' in sys.modules)\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    assert done.stdout.split() == ["False", "True"], done.stdout + done.stderr


# job scripts whose runs call nothing from `LAZY_SCIPY` (a run of the quick config, 2026-12-07): gathers, figures of
# stored results, the Exudyn runs and the reference table's chunks
JOBS_WITHOUT_SCIPY_CALLS = (
    "summary",
    "benchmark_gather",
    "benchmark_payload_gather",
    "reference_table",
    "reference_table_chunk",
    "helicopter_run",
    "helicopter_flight",
    "helicopter_sensitivity_run",
    "platform_modes",
)


def _top_imports(path) -> str:
    tree = ast.parse(path.read_text())
    return "\n".join(ast.unparse(n) for n in tree.body if isinstance(n, (ast.Import, ast.ImportFrom)))


def test_the_heavy_scipy_subpackages_wait_for_the_first_call():
    """The Snakefile's imports and the jobs that filter, fit and interpolate nothing import none of `LAZY_SCIPY`
    (each job its own interpreter: about 0.65 s saved where scipy.signal is not needed), nor does the tracker on a
    window it need not decimate (the benchmark's 2 ms grid); the first call that needs one brings it in. (The config
    checks that follow the Snakefile's imports design the gimbal's gains: they need scipy.signal.) Seen failing with
    `from scipy.signal import butter` put back at uavdamp.sources.excitation's top, and with the tracker importing
    scipy.signal before it knows it decimates."""
    scripts = [ROOT / "workflow" / "scripts" / f"{name}.py" for name in JOBS_WITHOUT_SCIPY_CALLS]
    script = "\n".join(
        [
            "import sys",
            "from uavdamp.config import budget, checks, files",
            "from uavdamp.workflow import config_errors_alone, export_provenance",
            *(_top_imports(path) for path in scripts),
            f"print(sorted(m for m in sys.modules if m.startswith({LAZY_SCIPY!r})))",
            "import numpy as np",
            "from uavdamp.signals.tracking import TrackerOptions, frequency_causal",
            "options = TrackerOptions('esprit', 4, 1.0, 3.0, 12.0, 1.5, 8, 7.0)",
            "t = np.arange(0.0, 2.0, 2e-3)",  # 2 ms: 41 samples a period of 12 Hz, no decimation
            "print(round(frequency_causal(t, np.sin(2 * np.pi * 7.0 * t), 1.9, options), 6))",
            "print('scipy.signal' in sys.modules)",
            "from uavdamp.sources import excitation",
            "excitation.high_pass(np.zeros(64), 1e-3, 5.0, 2)",
            "print('scipy.signal' in sys.modules)",
        ]
    )
    done = subprocess.run([sys.executable, "-c", script], cwd=ROOT, capture_output=True, text=True, check=True)
    assert done.stdout.split("\n")[:4] == ["[]", "7.0", "False", "True"], done.stdout + done.stderr


def test_the_snakefile_checks_the_config_without_scikit_learn():
    """What every Snakemake start does before planning (the Snakefile's imports, then every key typed and checked
    against the schema, each other and the budget, as `snakemake benchmark` asks) imports no scikit-learn: the
    estimators cost about 0.5 s of each start (a dry run of the quick run 4.0 -> 3.5 s, farm-bench, 2026-12-07).
    Seen failing with the config checks importing the training rows' split from `uavdamp.anfis.training`."""
    script = (
        "import sys, yaml\n"
        "from uavdamp.config import budget, checks, files\n"
        "from uavdamp.workflow import config_errors_alone, export_provenance\n"
        "typed, estimate = checks.validate(yaml.safe_load(open('config/config.yaml')), benchmark=True)\n"
        "checks.stiffness_warnings(typed), checks.extrapolation(typed), budget.summary(estimate)\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] == 'sklearn')[:3])\n"
    )
    done = subprocess.run([sys.executable, "-c", script], cwd=ROOT, capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]", done.stdout + done.stderr


# job scripts that run damping laws on a trained ANFIS and train nothing
JOBS_THAT_RUN_A_TRAINED_LAW = ("study", "payload", "benchmark_run", "benchmark_payload_run")


def test_the_jobs_that_run_a_trained_law_import_no_scikit_learn(tmp_path):
    """The jobs that only ask a trained ANFIS for C (`JOBS_THAT_RUN_A_TRAINED_LAW`: 36 of the default benchmark's
    jobs) load it as a `DampingPredictor` and import no scikit-learn, whose import takes about 1.2 s of each job:
    their imports, the model read from its file and a prediction. Seen failing with `benchmark_run.py` loading a
    `DampingModel` again."""
    X = np.random.default_rng(0).uniform([5.0, 5.0, 10.0], [30.0, 30.0, 1000.0], (40, 3))
    model = DampingModel.unfitted(anfis_options(epochs=2, seed=0, log_stiffness=True, log_damping=True))
    model.estimator.set_params(init="grid", n_mfs=2)
    model.fit(X, 1.0 + X[:, 0] / X[:, 2]).to_dataset().to_netcdf(tmp_path / "model.nc")
    scripts = [ROOT / "workflow" / "scripts" / f"{name}.py" for name in JOBS_THAT_RUN_A_TRAINED_LAW]
    script = "\n".join(
        [
            "import sys",
            *(_top_imports(path) for path in scripts),
            "from uavdamp import io",
            f"model = DampingPredictor.from_dataset(io.open_dataset({str(tmp_path / 'model.nc')!r}))",
            "print(model.predict([[10.0, 12.0, 100.0]]).shape)",
            "print(sorted(m for m in sys.modules if m.split('.')[0] == 'sklearn')[:3])",
        ]
    )
    done = subprocess.run([sys.executable, "-c", script], cwd=ROOT, capture_output=True, text=True, check=True)
    assert done.stdout.split("\n")[:2] == ["(1,)", "[]"], done.stdout + done.stderr
