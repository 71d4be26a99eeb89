"""Shared fixtures: configs, the session's quick run (built once for all pytest-xdist workers, `shared_once`) and
scratch copies of the workflow for Snakemake runs; the pipeline-heavy files are scheduled first (`LONGEST_FIRST`)."""

from __future__ import annotations

import contextlib
import copy
import io
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from uavdamp.config.load import Config, load
from uavdamp.contract import Observation
from uavdamp.platform import PlatformParams
from uavdamp.reference_table import criteria
from uavdamp.reference_table.grid import DIMS, GridSpec
from uavdamp.settings import parse

ROOT = Path(__file__).resolve().parents[1]


def deep_update(base: dict, override: dict) -> dict:
    """Snakemake's merge of --configfile over configfile: nested dicts merged, the rest replaced."""
    out = copy.deepcopy(base)
    for key, value in override.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = deep_update(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def load_config(name: str = "config.yaml") -> dict:
    """config/config.yaml, or it merged with an override file such as quick.yaml."""
    base = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    if name == "config.yaml":
        return base
    return deep_update(base, yaml.safe_load((ROOT / "config" / name).read_text()))


def typed_config(name: str = "config.yaml") -> Config:
    """A shipped config through the one config layer (`uavdamp.config.load`)."""
    return load(load_config(name))


@pytest.fixture(scope="session")
def default_config() -> dict:
    return load_config()


@pytest.fixture(scope="session")
def quick_config() -> dict:
    return load_config("quick.yaml")


# The platform section as in config/config.yaml (a documented choice; the targets are the paper's Table 1).
PLATFORM = {key: value for key, value in load_config()["platform"].items() if key not in ("response", "stroke")}


def platform_config(**changes) -> dict:
    """PLATFORM with keys replaced in whichever section holds them (unknown keys go to the top level)."""
    config = {section: dict(values) if isinstance(values, dict) else values for section, values in PLATFORM.items()}
    for key, value in changes.items():
        section = next((name for name, values in config.items() if isinstance(values, dict) and key in values), None)
        (config[section] if section else config)[key] = value
    return config


def platform_params(**changes) -> PlatformParams:
    """The default platform with `changes` (config keys, e.g. time_step_s=1e-3), typed."""
    return parse(PlatformParams, platform_config(**changes), "platform")


class FunctionLaw:
    """A damping law from a function of the observation, called every `update_period` s."""

    name = "function"

    def __init__(self, fn, update_period=None):
        self.fn, self.update_period = fn, update_period

    def reset(self):
        pass

    def __call__(self, observation: Observation) -> float:
        return self.fn(observation)


def apt_install(packages: list[str], log=print) -> str | None:
    """Install Debian packages with apt-get (CI runs as root on a bare machine); None when done, else why not."""
    if os.geteuid() != 0:
        return "not root"
    if shutil.which("apt-get") is None:
        return "no apt-get"
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    log(f"installing {' '.join(packages)} with apt-get")
    for cmd in (
        ["apt-get", "update", "-qq"],
        ["apt-get", "install", "-y", "-qq", "--no-install-recommends", *packages],
    ):
        result = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
        if result.returncode != 0:
            return f"{' '.join(cmd)} failed: {result.stderr.strip()[-800:]}"
    return None


def copy_workflow(dest: Path) -> Path:
    """Copy what Snakemake needs (the top-level Snakefile, workflow/, config/, data/) into `dest`; return it."""
    dest.mkdir(parents=True, exist_ok=True)
    for folder in ("workflow", "config", "data"):
        shutil.copytree(ROOT / folder, dest / folder, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy2(ROOT / "Snakefile", dest / "Snakefile")
    return dest


def snakemake(workdir: Path, *args: str, timeout: float = 1800) -> subprocess.CompletedProcess:
    """Run Snakemake in `workdir` with this interpreter; output captured as text."""
    env = dict(os.environ)
    return subprocess.run(
        [sys.executable, "-m", "snakemake", *args],
        cwd=workdir,
        capture_output=True,
        text=True,
        timeout=timeout,
        env=env,
    )


@contextlib.contextmanager
def _process_state_kept(workdir: Path, argv: list[str]):
    """Run a block as if it were `argv` in `workdir`, then restore what a Snakefile's parse changes in-process: the
    working directory, sys.argv, sys.path, the environment (EXUDYN_MODULE), the imported modules and the
    registries a plug-in file adds its law to."""
    from uavdamp import plugins
    from uavdamp.study import metrics, strategies

    registries = [strategies.REGISTRY, metrics.REGISTRY, plugins._LOADED]
    saved = (os.getcwd(), sys.argv[:], sys.path[:], dict(os.environ), set(sys.modules), [dict(r) for r in registries])
    try:
        os.chdir(workdir)
        sys.argv = argv
        yield
    finally:
        cwd, sys.argv, sys.path[:], environ, modules, contents = saved
        os.chdir(cwd)
        os.environ.clear()
        os.environ.update(environ)
        for name in set(sys.modules) - modules:
            del sys.modules[name]
        for registry, content in zip(registries, contents, strict=True):
            registry.clear()
            registry.update(content)


def snakemake_dry(workdir: Path, *args: str) -> subprocess.CompletedProcess:
    """`snakemake -n ARGS` in `workdir` inside this process (Snakemake's own command line, `snakemake.cli.main`):
    the same plan, refusal and output as `snakemake`, without the ~5 s CPU of a new interpreter importing
    Snakemake, Exudyn and xarray. For dry runs, refusals, --lint and --touch (which marks outputs done and runs no
    job) only: a run that executes jobs goes through `snakemake`."""
    from snakemake import cli

    ok = {"-n", "--lint", "--touch"} & set(args)
    assert ok, "in-process Snakemake is for dry runs (-n), --lint and --touch only"
    out, err, code = io.StringIO(), io.StringIO(), 0
    with _process_state_kept(workdir, ["snakemake", *args]):
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                cli.main(list(args))
            except SystemExit as exit_:
                code = exit_.code if isinstance(exit_.code, int) else 1
    return subprocess.CompletedProcess(["snakemake", *args], code, out.getvalue(), err.getvalue())


def planned_rules(result: subprocess.CompletedProcess) -> set[str]:
    """The rules in a Snakemake dry run's job-count table (empty when there is nothing to be done)."""
    plan = result.stdout + result.stderr
    if "Nothing to be done" in plan:
        return set()
    table = plan[plan.index("job ") : plan.index("total")]
    return {line.split()[0] for line in table.splitlines()[2:] if line.strip()}


# The session's quick run also carries a plug-in law from outside the package (the worked example of
# docs/submit-a-law.md), registered through the config alone: this override file names it.
PLUGIN_FILE = "plugins/my_laws.py"  # in the run directory: a copy of examples/my_laws.py
PLUGIN_LAW = "frequency_ratio"
QUICK_RUN_ARGS = ("--configfile", "config/quick.yaml", "config/plugin.yaml")


def plugin_override() -> dict:
    """config/plugin.yaml of the quick run: the plug-in file, and its law added to the study and the benchmark."""
    quick = load_config("quick.yaml")
    return {
        "plugins": [PLUGIN_FILE],
        "study": {"strategies": [*quick["study"]["strategies"], PLUGIN_LAW]},
        "benchmark": {"controllers": [*quick["benchmark"]["controllers"], PLUGIN_LAW]},
    }


def quick_run_config() -> dict:
    """The merged config of the session's quick run (quick.yaml and the plug-in override)."""
    return deep_update(load_config("quick.yaml"), plugin_override())


def with_plugin(workdir: Path) -> Path:
    """The run directory with the quick run's plug-in file and config/plugin.yaml (`QUICK_RUN_ARGS` names it)."""
    (workdir / PLUGIN_FILE).parent.mkdir(exist_ok=True)
    shutil.copy(ROOT / "examples" / "my_laws.py", workdir / PLUGIN_FILE)
    (workdir / "config" / "plugin.yaml").write_text(yaml.safe_dump(plugin_override()))
    return workdir


# fixtures that run the pipeline end to end: every test that depends on one (directly or through another fixture)
# is marked `slow` (`pytest -m "not slow"` leaves them out; plain `pytest` runs them)
PIPELINE_FIXTURES = {"quick_run", "multirotor_run"}


# the longest first (a longest-processing-time order), so that pytest-xdist's workers (`--dist loadfile
# --no-loadscope-reorder`: whole files in this order, the first four two per worker) start the pipelines early and end
# on short files: the quick run with the profile run and then the log case (on the first worker), beside the SLURM
# cluster's table and then the second quick run (killed and resumed), which need the quick run only at their end
# and at their start; then the files of the longest other tests (20-40 s each, measured); then every other file in
# its usual order
LONGEST_FIRST = (
    "tests/workflow/test_multirotor.py",
    "tests/workflow/test_slurm.py",
    "tests/workflow/test_log_case.py",
    "tests/workflow/test_reruns_and_determinism.py::test_a_killed_and_resumed_run",
    "tests/workflow/test_reruns_and_determinism.py",
    "tests/test_helicopter_flight.py",
    "tests/workflow/test_pipeline.py",
    "tests/workflow/test_config_checks.py",
    "tests/test_payload.py",
    "tests/test_anfis_training.py",
    "tests/test_chunks.py",
    "tests/workflow/test_survivor.py",
)


def _rank(item) -> int:
    nodeid = item.nodeid.replace(os.sep, "/")
    return next((k for k, prefix in enumerate(LONGEST_FIRST) if nodeid.startswith(prefix)), len(LONGEST_FIRST))


def pytest_collection_modifyitems(config, items):
    for item in items:
        if PIPELINE_FIXTURES & set(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.slow)
    items.sort(key=_rank)  # stable: the usual order within a rank


def shared_once(tmp_path_factory, name: str, make) -> Path:
    """`make(folder)` run once per test command, whether pytest runs alone or as pytest-xdist workers: the first
    worker to ask makes `name` under the command's shared temporary folder while holding its file lock, the others
    wait for it and reuse the folder (or fail with the first worker's message). Returns the folder."""
    from filelock import FileLock

    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):  # each worker's basetemp sits in the command's own folder
        root = root.parent
    folder, failed = root / name, root / f"{name}.failed"
    with FileLock(root / f"{name}.lock"):
        if failed.exists():
            pytest.fail(f"{name} failed in another worker: {failed.read_text()}")
        if not (folder / ".done").exists():
            try:
                make(folder)
            except BaseException as error:
                failed.write_text(str(error)[-9000:])
                raise
            (folder / ".done").touch()
    return folder


def _compile_kernels(folder: Path) -> None:
    """Compile the numba kernels (`uavdamp.compiled`: machine code cached beside the sources) through the calls the
    workflow makes, before any pipeline starts: in a fresh clone the quick run's two flight jobs otherwise compile
    the rotor's at the same time (about 17 s each under the suite's load, against 3-5 s a flight)."""
    from uavdamp.damping.dampers import SpencerMR, SpencerParams
    from uavdamp.helicopter import flight, model
    from uavdamp.helicopter.rotorloads import RotorLoads
    from uavdamp.platform.gimbal import GimbalParams
    from uavdamp.platform.gimbal_sim import simulate

    heli = flight.flight_helicopter(helicopter_of(load_config("quick.yaml")["helicopter"]).balanced())
    built = model.build(heli)
    n = len(built.mbs.GetObjectParameter(0, "jointTypes"))
    RotorLoads(built, heli, heli.aerodynamics, np.zeros(3), 1.0, 1e-3).update(np.zeros(n), np.zeros(n))
    zero = np.zeros(2)
    SpencerMR(SpencerParams.published(), 2).step(1e-3, 0.0, zero, zero, zero, zero)
    t = np.arange(21) * 5e-4
    simulate(GimbalParams(), t, np.zeros((3, t.size)), np.zeros((3, t.size)), np.zeros((3, t.size)))
    folder.mkdir(parents=True, exist_ok=True)


def _quick_run(workdir: Path) -> None:
    with_plugin(copy_workflow(workdir))
    result = snakemake(workdir, "-j2", "all", "benchmark", *QUICK_RUN_ARGS)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-6000:]


@pytest.fixture(scope="session")
def quick_run(tmp_path_factory) -> Path:
    """The quick config run from nothing through `all` and `benchmark` (the README's targets), once per test command
    (shared by the pytest-xdist workers), with the plug-in law of `plugin_override`. Tests read it; a test that
    edits a file of it works on a copy (`copy_run`)."""
    shared_once(tmp_path_factory, "kernels", _compile_kernels)
    return shared_once(tmp_path_factory, "quick", _quick_run)


def copy_run(run: Path, dest: Path) -> Path:
    """A copy of a run folder with its files' times kept (Snakemake plans by them); `dest`."""
    shutil.copytree(run, dest, symlinks=True)
    return dest


# the helicopter stage's outputs besides reports-*/helicopter/: its figures (without them Snakemake reruns the jobs
# that draw them)
HELICOPTER_FIGURES = ("fuselage_vibration.png", "helicopter_campbell.png", "helicopter_sensitivity.png")


def seed_helicopter(run: Path, workdir: Path, output_dir: str) -> None:
    """The quick run's helicopter stage (outputs and figures, times kept) copied into `workdir/output_dir`, so that a
    run there whose config leaves the helicopter section as the quick run's reruns none of its jobs (a seeded output
    whose plan differs is still refused by its consumers, `uavdamp.integrity`, and rebuilt)."""
    source, dest = run / "reports-quick", workdir / output_dir
    shutil.copytree(source / "helicopter", dest / "helicopter")
    (dest / "figures").mkdir(parents=True, exist_ok=True)
    for name in HELICOPTER_FIGURES:
        shutil.copy2(source / "figures" / name, dest / "figures" / name)


def load_module(path: Path, name: str):
    """A Python file that is not a package module (a benchmark script, a test helper) imported as `name`."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # a dataclass of the module looks the module up there
    spec.loader.exec_module(module)
    return module


def platform_from(section: dict) -> PlatformParams:
    """A platform section (with or without `response`) as the plants take it."""
    return parse(PlatformParams, {k: v for k, v in section.items() if k not in ("response", "stroke")}, "platform")


def solver_options(duration: float, step: float, output_step: float):
    """Helicopter solver options with the config's Newton and generalized-alpha settings."""
    from uavdamp.helicopter import SolverOptions

    return SolverOptions(
        duration=duration,
        step=step,
        output_step=output_step,
        spectral_radius=0.8,
        newton_tolerance=1e-6,
        newton_absolute_tolerance=1e-8,
    )


def helicopter_of(section: dict):
    """The helicopter section (with or without the analyses' options) as a typed run."""
    from uavdamp.helicopter import HelicopterRun, HelicopterSection
    from uavdamp.settings import keys

    run_keys = set(keys(HelicopterRun))
    cls = HelicopterSection if set(section) > run_keys else HelicopterRun
    return parse(cls, section, "helicopter")


def camera_of(section: dict):
    """The camera section, typed."""
    from uavdamp.camera.optics import CameraModel

    return parse(CameraModel, section, "camera")


def study_options_of(section: dict):
    """The study runs' options from a study section (or its runs' view), with the camera section (if given as the
    `camera` key) attached, as the study job builds them."""
    from dataclasses import replace

    from uavdamp.settings import keys, view
    from uavdamp.study.comparison import StudyOptions

    options = parse(StudyOptions, view(section, StudyOptions), "study")
    section_only = {"camera", "cases", "duration_s", "highpass_hz", "figures", "allow_extrapolation"}
    extra = sorted(set(section) - set(keys(StudyOptions)) - section_only)
    assert not extra, f"unknown study keys {extra}"
    return replace(options, camera=camera_of(section["camera"])) if "camera" in section else options


def synthetic_grid(values: np.ndarray, windows=("transient",)) -> xr.Dataset:
    """A grid dataset whose criteria are `values` (criteria..., window..., f_y, f_z, K, C) or (f_y, f_z, K, C)."""
    values = values.reshape((-1, len(windows), *values.shape[-4:]))
    shape = values.shape[-4:]
    spec = GridSpec(
        freq_y=np.arange(1.0, shape[0] + 1),
        freq_z=np.arange(1.0, shape[1] + 1),
        stiffness=np.geomspace(10, 1000, shape[2]),
        damping=np.geomspace(0.1, 10, shape[3]),
        amplitude=1e-3,
        duration=1.0,
        windows={w: (0.0, 1.0) for w in windows},
    )
    names = list(criteria.CRITERIA)[: values.shape[0]]
    data = {
        criteria.variable(n): (("window", *DIMS), v, criteria.CRITERIA[n]) for n, v in zip(names, values, strict=True)
    }
    failed = np.isnan(values).any(axis=(0, 1)).astype(np.int8)
    return xr.Dataset(
        {**data, "failed": (DIMS, failed, {"units": "1", "long_name": "f"})},
        coords={**spec.coords(), **spec.window_coords()},
    )


def displacement_grid(values: np.ndarray) -> xr.Dataset:
    """A grid dataset whose displacement criterion is `values` (f_y, f_z, K, C) in one window."""
    shape = values.shape
    spec = GridSpec(
        freq_y=np.arange(1.0, shape[0] + 1),
        freq_z=np.arange(1.0, shape[1] + 1),
        stiffness=np.array([10.0, 20.0, 50.0, 100.0][: shape[2]]),
        damping=np.array([1.0, 2.0, 4.0, 8.0, 16.0][: shape[3]]),
        amplitude=1e-3,
        duration=1.0,
        windows={"transient": (0.0, 1.0)},
    )
    data = {criteria.variable("displacement"): (("window", *DIMS), values[None], criteria.CRITERIA["displacement"])}
    failed = np.isnan(values).astype(np.int8)
    return xr.Dataset(
        {**data, "failed": (DIMS, failed, {"units": "1", "long_name": "f"})},
        coords={**spec.coords(), **spec.window_coords()},
    )


def excitation_options(cases: dict, *, duration: float, highpass_hz: float, band_hz: tuple[float, float]):
    """The excitation stage's options: `cases` (config mappings) over `duration` s, high-passed, the dominant line
    read in `band_hz` (the tracker's band; the rest of the tracker as in config/config.yaml)."""
    from uavdamp.sources.excitation import ExcitationOptions

    tracking = {**load_config()["study"]["tracking"], "min_freq_hz": band_hz[0], "max_freq_hz": band_hz[1]}
    section = {"cases": cases, "duration_s": duration, "highpass_hz": highpass_hz, "tracking": tracking}
    return parse(ExcitationOptions, section, "study")


# an `anfis` section for the estimator's and the training stage's tests (small: 40 epochs, 3 folds, 2 candidates)
ANFIS_OPTIONS = {
    "epochs": 40,
    "error_goal": 0.0,
    "step_size": 0.01,
    "step_increase": 1.1,
    "step_decrease": 0.9,
    "min_sigma_frac": 0.01,
    "ridge": 0.0,
    "log_stiffness": False,
    "log_damping": False,
    "train_fraction": 0.8,
    "seed": 7,
    "epoch_selection": "validation",
    "validation_fraction": 0.2,
    "baselines": ["linear", "knn"],
    "selection": {
        "folds": 3,
        "rule": "one_se",
        "candidates": [{"init": "grid", "n_mfs": 2}, {"init": "subtractive", "radius": 0.5}],
    },
}


def anfis_options(options: dict | None = None, **changes):
    """ANFIS_OPTIONS (or `options`) with `changes`, typed as the training stage receives them."""
    from uavdamp.anfis import AnfisOptions

    return parse(AnfisOptions, {**(ANFIS_OPTIONS if options is None else options), **changes}, "anfis")


def sine_yz(freq_y_hz: float, freq_z_hz: float, amplitude: float, duration: float, time_step: float):
    """(time s, y m, z m) of `uavdamp.sources.excitation.sine_input`'s planar mount motion."""
    from uavdamp.sources.excitation import sine_input

    time, mount = sine_input(freq_y_hz, freq_z_hz, amplitude, duration, time_step)
    return time, mount.y, mount.z


def planar_cases(name: str, time, y, z):
    """A one-case input dataset in the shape of `uavdamp.sources.excitation.cases_dataset`: y, z translation (m), no x
    and
    no rotation."""
    translation = np.stack([np.zeros_like(y), y, z])
    attrs = {"frame": "inertial"}
    return xr.Dataset(
        {
            "mount_displacement": (("case", "mount_axis", "time"), translation[None], {"units": "m", **attrs}),
            "mount_rotation": (("case", "mount_axis", "time"), np.zeros_like(translation)[None], {"units": "rad"}),
        },
        coords={
            "case": ("case", [name], {"units": "1", "long_name": "case"}),
            "axis": ("axis", ["y", "z"], {"units": "1", "long_name": "axis"}),
            "mount_axis": ("mount_axis", ["x", "y", "z"], {"units": "1", "long_name": "mount axis"}),
            "time": ("time", time, {"units": "s", "long_name": "time"}),
        },
    )


def mount_yz(response):
    """A plant response's mount translation on the isolator's axes (y, z), m, dims (axis, time)."""
    return response["mount_displacement"].sel(mount_axis=["y", "z"]).rename(mount_axis="axis")


def vibration_dataset(t, omega, displacement, spectrum, dominant) -> xr.Dataset:
    """The vibration stage's layout for one mount point "cg": displacement (rotor, axis, time), m, spectrum
    (rotor, axis, omega), m, dominant (rotor, axis), rad s-1, rotors imbalanced and balanced."""
    return xr.Dataset(
        {
            "mount_displacement": (("rotor", "mount", "axis", "time"), np.asarray(displacement)[:, None]),
            "amplitude_spectrum": (("rotor", "mount", "axis", "omega"), np.asarray(spectrum)[:, None]),
            "dominant_omega": (("rotor", "mount", "axis"), np.asarray(dominant)[:, None]),
        },
        coords={
            "rotor": ["imbalanced", "balanced"],
            "mount": ["cg"],
            "axis": ["x", "y", "z"],
            "time": t,
            "omega": omega,
        },
    )


def flip_byte_in_data(path: Path, values: np.ndarray) -> int:
    """Flip one byte of `path` inside the stored data of a variable whose values are `values` (float64 or int):
    the first element whose 8 bytes occur exactly once in the file (uncompressed HDF5 chunks hold the values as
    they are in memory, little-endian); its lowest mantissa byte is XOR-ed with 1. Returns the byte's offset."""
    data = bytearray(path.read_bytes())
    for value in np.ravel(np.asarray(values, dtype="<f8")):
        pattern = value.tobytes()
        offset = data.find(pattern)
        if offset >= 0 and data.find(pattern, offset + 1) < 0:
            data[offset] ^= 1
            path.write_bytes(bytes(data))
            return offset
    raise AssertionError(f"{path}: no value of the variable found once in the file")
