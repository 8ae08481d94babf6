"""Run the members of a parameter sweep, in parallel where the launch allows it.

- Launched under MPI (``mpirun -n N python -m mpi4py.futures -m comparisons run ...``): members
  go to mpi4py's ``MPIPoolExecutor`` workers, so a sweep spreads over the nodes of a cluster.
- Otherwise, with ``workers > 1``: a local process pool; with ``workers == 1``: serially.

Each member is a pure function of its parameters (seeds included), so the results are the same
whichever way they ran, and they come back in the order of ``params``.
"""
from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor
from typing import Callable, Sequence


def launched_under_mpi() -> bool:
    """True when this process was started by an MPI launcher with more than one rank."""
    for var in ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS"):
        if int(os.environ.get(var, "1")) > 1:
            return True
    return False


def run_sweep(function: Callable, params: Sequence, workers: int = 1, progress=None) -> list:
    """``[function(p) for p in params]``, spread over MPI workers or local processes.

    ``function`` must be importable at module level (it is pickled to the workers).
    """
    params = list(params)
    if launched_under_mpi():
        from mpi4py.futures import MPIPoolExecutor

        with MPIPoolExecutor() as pool:
            return _collect(pool, function, params, progress, "MPI")
    if workers > 1 and len(params) > 1:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            return _collect(pool, function, params, progress, f"{workers} processes")
    results = []
    for i, p in enumerate(params):
        results.append(function(p))
        if progress:
            progress(f"sweep member {i + 1}/{len(params)} done (serial)")
    return results


def _collect(pool, function, params, progress, how):
    futures = [pool.submit(function, p) for p in params]
    results = []
    for i, future in enumerate(futures):
        results.append(future.result())
        if progress:
            progress(f"sweep member {i + 1}/{len(params)} done ({how})")
    return results
