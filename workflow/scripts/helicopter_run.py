"""Snakemake script: one helicopter run (balanced or imbalanced rotor) -> NetCDF."""

import os

# Exudyn's AVX2 module without range checks (falls back when the CPU lacks AVX2); set in the environment so
# that joblib's worker processes load the same module and give bit-identical numbers.
os.environ.setdefault("EXUDYN_MODULE", "fast")

from uavdamp import helicopter, io, workflow  # noqa: E402

workflow.start_log(snakemake.log[0])
cfg = snakemake.params.helicopter
heli = helicopter.Helicopter.from_config(cfg)
if snakemake.wildcards.rotor == "balanced":
    heli = heli.balanced()
elif snakemake.wildcards.rotor == "both_rotors":
    heli = heli.with_tail_rotor_speed(cfg["tail_rotor"]["omega_running_rad_s"])
ds = helicopter.run(
    heli, helicopter.SolverOptions.from_config(cfg["solver"]), progress=f"helicopter {snakemake.wildcards.rotor}"
)
workflow.log_info(f"{snakemake.wildcards.rotor}: {ds.attrs}")
io.write_netcdf(ds, snakemake.output[0], cfg, section="helicopter", command=workflow.snakemake_command(snakemake))
