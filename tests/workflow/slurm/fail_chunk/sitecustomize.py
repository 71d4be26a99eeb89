"""Test hook (tests/workflow/test_slurm.py only): make one reference-table chunk fail, inside its own job process.

On PYTHONPATH with UAVDAMP_TEST_FAIL_CHUNK="i-of-N" set, every Python process started by Snakemake (locally or as a
SLURM job) loads this module at start-up and wraps `uavdamp.reference_table.chunks.run_chunk` to raise for that
chunk. Production
code has no such hook; a monkeypatch cannot reach a SLURM job's process.
"""

import os

_BAD = os.environ.get("UAVDAMP_TEST_FAIL_CHUNK")
if _BAD:
    os.environ.setdefault("EXUDYN_MODULE", "fast")  # what the Snakefile sets before the jobs import uavdamp
    from uavdamp.reference_table import chunks

    _real = chunks.run_chunk

    def _failing(platform, spec, *, n_chunks=1, chunk=0, **options):
        if f"{chunk + 1}-of-{n_chunks}" == _BAD:
            raise RuntimeError(f"chunk {_BAD} failed on purpose (test hook UAVDAMP_TEST_FAIL_CHUNK)")
        return _real(platform, spec, n_chunks=n_chunks, chunk=chunk, **options)

    chunks.run_chunk = _failing
