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


def test_a_process_with_its_own_numba_cache_has_its_own_lock(tmp_path):
    # it loads and writes its own cache, so it must not wait for processes compiling into
    # another (tests/test_same_bits.py's loading run once waited 230 s for one)
    import os
    probe = "from dem_core.jit_cache import lock_path; print(lock_path())"
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    other = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                           env=env).stdout.strip()
    assert other and other != str(lock_path())
