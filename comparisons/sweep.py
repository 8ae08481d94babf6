"""Run the members of a parameter sweep, in parallel where the launch allows it.

- Launched under MPI (``mpirun -n N python -m mpi4py.futures -m comparisons run ...``): members
  go to mpi4py's ``MPIPoolExecutor`` workers, so a sweep spreads over the nodes of a cluster.
- Otherwise, with ``workers > 1``: a local process pool; with ``workers == 1``: serially.

Each member is a pure function of its parameters (seeds included), so the results are the same
whichever way they ran, and they come back in the order of ``params``.

Inside ``store.case_output`` (every ``comparisons run``), each member's result is written to the
case's ``members/`` folder as soon as it finishes, and with ``resume`` a member kept there is
loaded, not run (``comparisons.store``). A member that raises does not stop the others then:
they finish and are kept, and the first error is raised at the end.
"""
from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Callable, Sequence

from comparisons import store


def launched_under_mpi() -> bool:
    """True when this process was started by an MPI launcher with more than one rank."""
    for var in ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS"):
        if int(os.environ.get(var, "1")) > 1:
            return True
    return False


def run_sweep(function: Callable, params: Sequence, workers: int = 1, progress=None) -> list:
    """``[function(p) for p in params]``, spread over MPI workers or local processes, with the
    members kept by (and, resuming, loaded from) the ``store.case_output`` in force.

    ``function`` must be importable at module level (it is pickled to the workers).
    """
    params = list(params)
    keep = store.current()
    say = progress or (lambda message: None)
    n = len(params)
    results, todo, errors = [None] * n, [], []
    for i, p in enumerate(params):
        found, value = keep.load(function, p) if keep is not None else (False, None)
        if found:
            results[i] = value
            say(f"sweep member {i + 1}/{n} kept from an earlier run (not run again)")
        else:
            todo.append(i)

    def done(i, how, result=None, error=None):
        if error is not None:
            if keep is None:
                raise error
            errors.append(error)
            say(f"sweep member {i + 1}/{n} failed ({how}): {error!r}")
            return
        results[i] = keep.save(function, params[i], result) if keep is not None else result
        say(f"sweep member {i + 1}/{n} done ({how})")

    _execute(function, params, todo, workers, done)
    if errors:
        raise errors[0]
    return results


def _execute(function, params, todo, workers, done):
    """Run ``function(params[i])`` for each ``i`` in ``todo``, calling ``done(i, how, result,
    error)`` as each finishes."""
    if not todo:
        return
    if launched_under_mpi():
        from mpi4py.futures import MPIPoolExecutor

        with MPIPoolExecutor() as pool:
            return _pooled(pool, function, params, todo, done, "MPI")
    if workers > 1 and len(todo) > 1:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            return _pooled(pool, function, params, todo, done, f"{workers} processes")
    for i in todo:
        try:
            result = function(params[i])
        except Exception as error:
            done(i, "serial", error=error)
            continue
        done(i, "serial", result)


def _pooled(pool, function, params, todo, done, how):
    futures = {pool.submit(function, params[i]): i for i in todo}
    for future in as_completed(futures):
        error = future.exception()
        done(futures[future], how, None if error else future.result(), error)
