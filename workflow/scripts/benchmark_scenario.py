"""Snakemake script: one benchmark scenario's mount input (wildcard `scenario`) -> NetCDF."""

from uavdamp import io, scenarios, workflow
from uavdamp.helicopter import FlightRun
from uavdamp.platform import PlatformParams
from uavdamp.settings import parse

workflow.start_log(snakemake.log[0])
p = snakemake.params
options = parse(scenarios.ScenarioOptions, p.inputs, "benchmark")
params = parse(PlatformParams, p.platform, "platform")
heli = parse(FlightRun, p.helicopter, "helicopter")  # flight scenarios need its aerodynamics
config = {"inputs": p.inputs, "helicopter": p.helicopter, "platform": p.platform}


def make() -> None:
    log = io.open_dataset(snakemake.input.log[0]) if snakemake.input.log else None
    ds = scenarios.scenario_input(snakemake.wildcards.scenario, options, heli, params.time_step, log)
    workflow.log_info(f"{snakemake.wildcards.scenario}: {ds.attrs}")
    io.write_netcdf(ds, snakemake.output[0], config, section="benchmark", command=workflow.snakemake_command(snakemake))


# one writer: a job that finds another run's job writing this output waits, then keeps what it finished
if not io.write_once(snakemake.output[0], make, config, section="benchmark"):
    workflow.log_info(f"{snakemake.output[0]}: finished by the process that held its lock; kept, not recomputed")
