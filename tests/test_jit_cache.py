"""``dem_core.jit_cache``: a kernel is compiled once for its arguments' types, under a lock
that one process holds at a time."""
import subprocess
import sys

from numba import njit

from dem_core.jit_cache import compiled, lock, lock_path


@njit
def _scaled(x, n):
    return x * n


def test_compiled_gives_the_entry_the_call_uses():
    args = (1.5, 4)
    kernel = compiled(_scaled, args)
    assert len(kernel.overloads) == 1
    assert kernel(*args) == 6.0
    assert len(kernel.overloads) == 1            # the call found the entry: no second compile
    compiled(_scaled, (2.5, 3))                  # the same types: nothing new
    assert len(kernel.overloads) == 1


def test_another_process_cannot_take_the_lock_while_it_is_held():
    probe = ("import fcntl, os, sys; fd = os.open(sys.argv[1], os.O_RDWR)\n"
             "try:\n    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB); print('free')\n"
             "except BlockingIOError:\n    print('held')\n")
    run = [sys.executable, "-c", probe, str(lock_path())]
    with lock():
        assert subprocess.run(run, capture_output=True, text=True).stdout.strip() == "held"
    assert subprocess.run(run, capture_output=True, text=True).stdout.strip() == "free"
