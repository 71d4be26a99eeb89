"""Snakemake script: the benchmark on the payload, one scenario (wildcard `scenario`) -> the gimbal's runs on it."""

from uavdamp import integrity, io, workflow
from uavdamp.anfis.predictor import DampingPredictor
from uavdamp.benchmark import payload as bench
from uavdamp.benchmark.runner import case_of
from uavdamp.camera.optics import CameraModel
from uavdamp.platform import PlatformParams
from uavdamp.settings import parse
from uavdamp.sources.stated import StatedSource, motion
from uavdamp.study.payload import PayloadSection

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
p = snakemake.params
platform = parse(PlatformParams, p.platform, "platform")
options = parse(bench.PayloadBenchmark, {"mounts": list(p.mounts)}, "benchmark.payload")
section = parse(PayloadSection, p.payload, "payload").with_camera(platform.structure)
section = bench.benchmark_section(section, options, float(p.duration_s))
camera = parse(CameraModel, p.camera, "camera")
config = {
    "mounts": p.mounts,
    "duration_s": p.duration_s,
    "payload": p.payload,
    "camera": p.camera,
    "platform": p.platform,
    "source": p.source,
}


def scenario_input(name: str) -> tuple:
    """(time s, mount motion, description) of the scenario: its file, or a stated source generated here."""
    if p.source:  # a stated source of benchmark.payload.sources, over the scenarios' duration
        source = parse(StatedSource, p.source, f"sources.{name}")
        time, mount, _ = motion(source, float(p.duration_s))
        return time, mount, source.description or source.kind
    scenario = io.open_dataset(snakemake.input.scenario[0])
    time, mount = case_of(scenario)
    return time, mount, f"{scenario.attrs.get('kind', '')} {scenario.attrs.get('spec', '')}".strip()


def make() -> None:
    name = snakemake.wildcards.scenario
    time, mount, described = scenario_input(name)
    table = io.open_dataset(snakemake.input.table)  # the payload table: the scheduled law's
    model = DampingPredictor.from_dataset(io.open_dataset(snakemake.input.model))  # the payload ANFIS
    ds = bench.run_scenario(name, described, time, mount, section, platform, camera, table, model)
    workflow.log_info(f"los_std (rad):\n{ds.los_std.to_dataframe().to_string()}")
    if "law_los_std" in ds:
        workflow.log_info(f"law_los_std (rad):\n{ds.law_los_std.to_dataframe().to_string()}")
    job.check_outputs()  # under the lock: a later run's output is never replaced
    io.write_netcdf(ds, snakemake.output[0], config, section="benchmark", command=workflow.snakemake_command(snakemake))


# one writer: a job that finds another run's job writing this output waits, then keeps what it finished
if not io.write_once(snakemake.output[0], make, config, section="benchmark"):
    workflow.log_info(f"{snakemake.output[0]}: finished by the process that held its lock; kept, not recomputed")
