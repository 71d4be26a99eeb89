"""Snakemake script: one benchmark scenario's mount input (wildcard `scenario`) -> NetCDF."""

from uavdamp import integrity, io, workflow
from uavdamp.benchmark import scenarios
from uavdamp.helicopter import FlightRun
from uavdamp.platform import PlatformParams
from uavdamp.settings import parse
from uavdamp.sources import stated

workflow.start_log(snakemake.log[0])
job = integrity.Job(snakemake)  # inputs of this plan's config only; outputs stamped with it
p = snakemake.params
options = parse(scenarios.ScenarioOptions, p.inputs, "benchmark")
params = parse(PlatformParams, p.platform, "platform")
heli = parse(FlightRun, p.helicopter, "helicopter")  # flight scenarios need its aerodynamics
name = snakemake.wildcards.scenario
source = parse(stated.StatedSource, p.source, f"sources.{name}") if p.source else None
config = {"inputs": p.inputs, "helicopter": p.helicopter, "platform": p.platform, "source": p.source}


def make() -> None:
    log = io.open_dataset(snakemake.input.log[0]) if snakemake.input.log else None
    ds = scenarios.scenario_input(name, options, heli, params.time_step, log, source)
    workflow.log_info(f"{name}: {ds.attrs}")
    job.check_outputs()  # under the lock: a later run's output is never replaced
    io.write_netcdf(ds, snakemake.output[0], config, section="benchmark", command=workflow.snakemake_command(snakemake))


# one writer: a job that finds another run's job writing this output waits, then keeps what it finished
if not io.write_once(snakemake.output[0], make, config, section="benchmark"):
    workflow.log_info(f"{snakemake.output[0]}: finished by the process that held its lock; kept, not recomputed")
