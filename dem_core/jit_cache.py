"""One process at a time compiles a kernel; the others load what it wrote to numba's cache.

numba compiles a ``cache=True`` kernel the first time a process calls it with new argument
types, or loads it from the cache that an earlier process wrote (compiling the step from a
clean clone takes far longer than loading it: docs/performance.md, "The serial kernel and
numba's pipelines"). Processes that start together,
each with an empty cache (a sweep's members, pytest-xdist's workers), would each compile it.
``compiled`` compiles (or loads) a kernel for the types of its arguments under a file lock,
so the first process compiles and the others wait for it and load its cache entry.
"""
from __future__ import annotations

import contextlib
import hashlib
import os
import tempfile
from pathlib import Path

__all__ = ["compiled", "lock", "lock_path"]


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
    """An exclusive lock on a file in the temporary folder, one per copy of ``dem_core`` (none
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
    """The lock's file: named by this copy of ``dem_core``'s folder (its own numba cache)."""
    here = str(Path(__file__).resolve().parent).encode()
    return Path(tempfile.gettempdir()) / f"dem_core-jit-{hashlib.sha1(here).hexdigest()[:12]}.lock"
