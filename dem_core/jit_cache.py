"""One process at a time compiles a kernel; the others load what it wrote to numba's cache.

numba compiles a ``cache=True`` kernel the first time a process calls it with new argument
types, or loads it from the cache that an earlier process wrote (compiling the step from a
clean clone takes far longer than loading it: docs/performance.md, "The serial kernel and
numba's pipelines"). Processes that start together,
each with an empty cache (a sweep's members, pytest-xdist's workers), would each compile it.
``compiled`` compiles (or loads) a kernel for the types of its arguments under a file lock,
so the first process compiles and the others wait for it and load its cache entry.

``first_run_notice`` says so, in one line on a terminal, when numba has nothing cached yet
for the time step: a first run on a machine (or after the kernels were edited) spends a minute
or more compiling before its first step, which looks like a hang otherwise.
"""
from __future__ import annotations

import contextlib
import hashlib
import os
import sys
import tempfile
from pathlib import Path

__all__ = ["compiled", "lock", "lock_path", "first_run_notice", "has_cache", "NOTICE"]

# measured from an empty cache on a 2-core host (docs/performance.md, "The first compile")
NOTICE = ("dem_core: compiling the numba kernels, once for this machine: about 1 min for rigid "
          "blocks, 3 min with deformable ones (later runs load them from numba's cache)")
NOTICE_ENV = "DEM_CORE_COMPILE_NOTICE"      # "1": always say it, "0": never; else on a terminal
_said = [False]


def compiled(kernel, args):
    """``kernel`` (a numba dispatcher) with an entry for the types of ``args``, compiled or
    loaded from the cache under the lock (``lock``) if this process has no entry yet. Once it
    has one, numba's own dispatch takes over (typing the arguments in Python here costs too
    much to do at every call: docs/performance.md, "The serial kernel and numba's pipelines";
    a further signature, if any, compiles on the call,
    unlocked)."""
    if not kernel.overloads:
        types = tuple(kernel.typeof_pyval(a) for a in args)
        with lock():
            kernel.compile(types)
    return kernel


@contextlib.contextmanager
def lock():
    """An exclusive lock on a file in the temporary folder, one per copy of ``dem_core`` and
    numba cache folder (none
    where ``fcntl`` is missing or the file cannot be opened: then each process compiles for
    itself, as without the lock)."""
    try:
        import fcntl
        fd = os.open(lock_path(), os.O_RDWR | os.O_CREAT, 0o666)
    except (ImportError, OSError):
        yield
        return
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)                    # (closing releases the lock)


def lock_path() -> Path:
    """The lock's file: named by this copy of ``dem_core``'s folder and the numba cache it
    writes to (``NUMBA_CACHE_DIR``, if set): processes with caches of their own do not wait
    for each other (a process loading from its own full cache once waited 230 s for another
    that compiled into the default one, tests/test_same_bits.py)."""
    import numba

    here = f"{Path(__file__).resolve().parent}|{numba.config.CACHE_DIR or ''}".encode()
    return Path(tempfile.gettempdir()) / f"dem_core-jit-{hashlib.sha1(here).hexdigest()[:12]}.lock"


def has_cache(kernel) -> bool:
    """True when numba's cache holds an entry for ``kernel`` (any signature) that is current
    (its index's stamp matches the source file); True too when that cannot be read (numba's
    cache layout is internal: no notice is better than a false one)."""
    try:
        return bool(kernel._cache._cache_file._load_index())
    except Exception:               # (no cache=True, or another numba's internals)
        return True


def first_run_notice(kernel, stream=None) -> bool:
    """Print ``NOTICE`` once per process on ``stream`` (stderr) when ``kernel`` (the time
    step) has nothing in numba's cache. Only on a terminal, so a log, a pipe or a captured
    stream keeps its lines as they were, unless the environment's ``DEM_CORE_COMPILE_NOTICE``
    is "1" (always) or "0" (never). Returns whether it printed."""
    stream = sys.stderr if stream is None else stream
    wanted = os.environ.get(NOTICE_ENV)
    if _said[0] or wanted == "0" or has_cache(kernel):
        return False
    if wanted != "1" and not (hasattr(stream, "isatty") and stream.isatty()):
        return False
    _said[0] = True
    print(NOTICE, file=stream, flush=True)
    return True
