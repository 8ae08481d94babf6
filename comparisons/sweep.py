"""Run the members of a parameter sweep, in parallel where the launch allows it.

- Launched under MPI (``mpirun -n N python -m mpi4py.futures -m comparisons run ...``): members
  go to mpi4py's ``MPIPoolExecutor`` workers, so a sweep spreads over the nodes of a cluster.
- Otherwise, with ``workers > 1``: a local process pool; with ``workers == 1``: serially. The
  pool has at most ``local_workers()`` processes: the cores this process may use, or
  ``COMPARISONS_WORKERS`` where that is set (e.g. 1 on a machine shared with other jobs, or in
  each of pytest-xdist's workers, ``tests/conftest.py``), so a sweep never runs more members
  side by side than there are cores for them. Each pool process's BLAS and OpenMP thread pools
  (numpy's OpenBLAS; the OpenMP runtime DOLFINx and PETSc load) are cut to its share of the
  cores, ``pool_threads(workers)``, with ``threadpoolctl``; libraries a member loads later read
  ``OMP_NUM_THREADS`` and ``OPENBLAS_NUM_THREADS``, which the pool process sets to the same
  share unless they are set. Left at a thread per core, every process of the pool starts one
  and they oversubscribe the cores (docs/performance.md, "BLAS threads in a sweep's pool").
  numba's threads are the members' own (``Model(threads=n)``).

Each member is a pure function of its parameters (seeds included), so the results are the same
whichever way they ran, and they come back in the order of ``params``.

Inside ``store.case_output`` (every ``comparisons run``), each member's result is written to the
case's ``members/`` folder as soon as it finishes, and with ``resume`` a member kept there is
loaded, not run (``comparisons.store``). A member that raises does not stop the others then:
they finish and are kept, and the first error is raised at the end.

Progress: given a ``comparisons.progress.Progress``, each member reports where it is (its
level or stage, steps, elapsed time, an estimate of what is left; ``progress.report``) and the
Progress shows one updating line per running member on a terminal, plain lines otherwise. The
reports travel by the way the member runs: in this process directly, from a local pool through
a multiprocessing queue drained by a thread here, under MPI as plain lines on the workers'
stderr (mpirun forwards them; the workers may be on other nodes).
"""
from __future__ import annotations

import multiprocessing
import os
import threading
from concurrent.futures import ProcessPoolExecutor, as_completed
from contextlib import contextmanager
from typing import Callable, Sequence

from comparisons import progress as _progress
from comparisons import store


def launched_under_mpi() -> bool:
    """True when this process was started by an MPI launcher with more than one rank."""
    for var in ("OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS"):
        if int(os.environ.get(var, "1")) > 1:
            return True
    return False


def usable_cores() -> int:
    """The cores this process may run on (its CPU affinity, where the system has one)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (
        os.cpu_count() or 1)


def local_workers() -> int:
    """The most members a local pool runs side by side: ``COMPARISONS_WORKERS`` if set (a whole
    number >= 1, ValueError naming it otherwise), else ``usable_cores()``."""
    value = os.environ.get("COMPARISONS_WORKERS")
    if value is None:
        return usable_cores()
    if not value.strip().isdigit() or int(value) < 1:
        raise ValueError(f"COMPARISONS_WORKERS must be a whole number >= 1, got {value!r}")
    return int(value)


def pool_threads(workers: int) -> int:
    """The BLAS/OpenMP threads each of ``workers`` pool processes may start: its share of
    ``usable_cores()``, at least one."""
    return max(1, usable_cores() // max(1, int(workers)))


def run_sweep(function: Callable, params: Sequence, workers: int = 1, progress=None) -> list:
    """``[function(p) for p in params]``, spread over MPI workers or local processes, with the
    members kept by (and, resuming, loaded from) the ``store.case_output`` in force.

    ``function`` must be importable at module level (it is pickled to the workers).
    ``progress``: a callable(str) for the sweep's own lines; a ``comparisons.progress.Progress``
    also shows each member's reports (module docstring).
    """
    params = list(params)
    keep = store.current()
    say = progress or (lambda message: None)
    board = progress if isinstance(progress, _progress.Progress) and not progress.quiet else None
    if board is not None:
        board.new_sweep()
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
        if board is not None:
            board.finish(i)
        if error is not None:
            if keep is None:
                raise error
            errors.append(error)
            say(f"sweep member {i + 1}/{n} failed ({how}): {error!r}")
            return
        results[i] = keep.save(function, params[i], result) if keep is not None else result
        say(f"sweep member {i + 1}/{n} done ({how})")

    who = [(i, n, _label(p), getattr(board, "label", "")) for i, p in enumerate(params)]
    _execute(function, params, todo, workers, done, who, board)
    if errors:
        raise errors[0]
    return results


def _label(p) -> str:
    """A member's label in progress lines: its parameters' "label", if any."""
    return str(p["label"]) if isinstance(p, dict) and "label" in p else ""


def _execute(function, params, todo, workers, done, who, board):
    """Run ``function(params[i])`` for each ``i`` in ``todo``, calling ``done(i, how, result,
    error)`` as each finishes; member ``i`` is ``who[i]`` (index, n, label, case) and its
    reports go to ``board`` (a Progress, or None: dropped)."""
    if not todo:
        return
    if launched_under_mpi():
        from mpi4py.futures import MPIPoolExecutor

        with MPIPoolExecutor() as pool:
            return _pooled(pool, function, params, todo, done, "MPI", who,
                           "lines" if board is not None else None)
    workers = min(workers, local_workers())
    if workers > 1 and len(todo) > 1:
        with _reports_from_pool(board) as queue:
            with ProcessPoolExecutor(max_workers=workers, initializer=_worker_init,
                                     initargs=(queue, pool_threads(workers))) as pool:
                return _pooled(pool, function, params, todo, done, f"{workers} processes",
                               who, "queue" if queue is not None else None)
    for i in todo:
        try:
            with _progress.as_member(*who[i], None if board is None else board.member):
                result = function(params[i])
        except Exception as error:
            done(i, "serial", error=error)
            continue
        done(i, "serial", result)


def _worker_init(queue, threads):
    """A local pool process's start: its reports go to ``queue`` (``progress.worker_init``),
    its BLAS and OpenMP pools have at most ``threads`` threads (module docstring)."""
    from threadpoolctl import threadpool_limits

    _progress.worker_init(queue)
    for name in _THREAD_VARIABLES:                  # read by the libraries loaded from now on
        os.environ.setdefault(name, str(threads))
    threadpool_limits(limits=threads)               # those loaded already (members run in
    #                                                 this thread: OpenMP's limit is a thread's)


_THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def _pooled(pool, function, params, todo, done, how, who, send):
    futures = {pool.submit(_run_member, function, params[i], who[i], send): i for i in todo}
    for future in as_completed(futures):
        error = future.exception()
        done(futures[future], how, None if error else future.result(), error)


def _run_member(function, param, who, send):
    """In a worker: ``function(param)`` as member ``who`` (index, n, label, case), its reports
    sent by ``send``: "queue" (a local pool's queue), "lines" (stderr, MPI) or None."""
    sender = (_progress.queue_sender() if send == "queue" else
              _progress.line_sender(who[3]) if send == "lines" else None)
    with _progress.as_member(*who, sender):
        return function(param)


@contextmanager
def _reports_from_pool(board):
    """A multiprocessing queue for a local pool's reports and a thread that shows them on
    ``board`` until the block ends (None and no thread without a board)."""
    if board is None:
        yield None
        return
    queue = multiprocessing.Queue()
    thread = threading.Thread(target=_show_reports, args=(queue, board), daemon=True)
    thread.start()
    try:
        yield queue
    finally:
        queue.put(None)                 # after the pool has shut down: its reports are in
        thread.join(timeout=10)
        queue.close()


def _show_reports(queue, board):
    while True:
        status = queue.get()
        if status is None:
            return
        board.member(status)
